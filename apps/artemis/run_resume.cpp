#include "run_resume.hpp"

#include <unistd.h>

#include <csignal>
#include <nlohmann/json.hpp>
#include <string_view>

#include "artemis/io/read_file.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRecordFile = "checkpoint.json";
constexpr int kRecordFormat = 1;

bool leftOut(const CLI::Option& opt) {
  for (const std::string& name : opt.get_lnames()) {
    if (name == "help" || name == "out" || name == "resume") return true;
  }
  return false;
}

std::atomic<bool> g_stop{false};

void askToStop(int /*signal*/) {
  g_stop.store(true);
  constexpr std::string_view kSay = "\nstopping after this frame, with a checkpoint (again to quit at once)\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kSay.data(), kSay.size());
}

}  // namespace

StopOnInterrupt::StopOnInterrupt() {
  g_stop.store(false);
  struct sigaction action {};
  action.sa_handler = askToStop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // the second signal finds the default action
  sigaction(SIGINT, &action, &previous_[0]);
  sigaction(SIGTERM, &action, &previous_[1]);
}

StopOnInterrupt::~StopOnInterrupt() {
  sigaction(SIGINT, &previous_[0], nullptr);
  sigaction(SIGTERM, &previous_[1], nullptr);
}

const std::atomic<bool>* StopOnInterrupt::flag() const {
  return &g_stop;
}

std::vector<std::string> givenArgs(const CLI::App& cmd) {
  std::vector<std::string> args;
  std::vector<std::string> positionals;
  for (const CLI::Option* opt : cmd.get_options()) {
    if (opt->count() == 0 || leftOut(*opt)) continue;
    if (!opt->nonpositional()) {
      positionals.insert(positionals.end(), opt->results().begin(), opt->results().end());
      continue;
    }
    const std::string name =
        !opt->get_lnames().empty() ? "--" + opt->get_lnames().front() : "-" + opt->get_snames().front();
    if (opt->get_type_size_max() == 0) {  // a flag: once per time it was given
      for (std::size_t k = 0; k < opt->count(); ++k) args.push_back(name);
      continue;
    }
    for (const std::string& value : opt->results()) {
      args.push_back(name);
      args.push_back(value);
    }
  }
  if (!positionals.empty()) {
    args.emplace_back("--");
    args.insert(args.end(), positionals.begin(), positionals.end());
  }
  return args;
}

std::string resumeRecordJson(const ResumeRecord& record) {
  const nlohmann::ordered_json j = {
      {"format", kRecordFormat}, {"working_dir", record.working_dir.string()}, {"args", record.args}};
  return j.dump(2) + "\n";
}

Result<ResumeRecord> readResumeRecord(const fs::path& out) {
  const fs::path path = out / kRecordFile;
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) {
    if (text.status().code() == StatusCode::kNotFound) {
      return notFound(
          path.string() + ": not found; " + out.string() +
          " holds no run that can be resumed (was it started with --checkpoint-every 0, or did it finish?)");
    }
    return text.status();
  }
  try {
    const nlohmann::json j = nlohmann::json::parse(*text);
    if (j.at("format").get<int>() != kRecordFormat) {
      return invalidArgument(path.string() + ": written by another version of artemis (format " +
                             std::to_string(j.at("format").get<int>()) + "); run again without --resume");
    }
    ResumeRecord record;
    record.working_dir = j.at("working_dir").get<std::string>();
    record.args = j.at("args").get<std::vector<std::string>>();
    return record;
  } catch (const nlohmann::json::exception& e) {
    return parseError(path.string() + ": " + e.what());
  }
}

}  // namespace artemis::cli
