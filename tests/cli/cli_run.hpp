#pragma once
// Runs the built artemis program with arguments, capturing exit code, stdout and stderr; or starts
// it in the background, to be killed.

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/ended_process.hpp"
#include "support/test_support.hpp"

namespace artemis::test {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// `environment`: settings put before the program ("NAME=value "), or empty.
inline RunResult runCli(const std::string& environment, const std::string& args) {
  TempDir tmp;
  const std::string cmd = environment + std::string(ARTEMIS_CLI_PATH) + " " + args + " 2>" + (tmp / "stderr").string();
  RunResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(tmp / "stderr");
  std::stringstream ss;
  ss << err.rdbuf();
  r.err = ss.str();
  return r;
}

inline RunResult runCli(const std::string& args) {
  return runCli("", args);
}

// Starts artemis with `args` (its output discarded); the caller waits for it or kills it.
inline pid_t spawnCli(const std::vector<std::string>& args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string program = ARTEMIS_CLI_PATH;
    argv.push_back(program.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Entries of `folder` whose names start with a dot: staging folders and temporary files.
inline std::vector<std::string> hiddenEntries(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (!name.empty() && name[0] == '.') names.push_back(name);
  }
  return names;
}

}  // namespace artemis::test
