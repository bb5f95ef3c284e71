// artemis: the command-line program. Flags are parsed here and only here.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string_view>

#include "artemis/core/allocator.hpp"
#include "artemis/core/log.hpp"
#include "commands.hpp"

namespace artemis::cli {

int fail(const Status& status) {
  log::error("{}", status.message());
  return 1;
}

}  // namespace artemis::cli

namespace {

int run(int argc, char** argv) {
  CLI::App app{
      "ARTEMIS: textured, semantically queryable triangle meshes from LiDAR + camera recordings.\n"
      "Logs go to stderr; results and --json output to stdout."};
  app.set_version_flag("--version", "artemis 0.1.0");
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "debug, info, warn, error or off")
      ->capture_default_str()
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}));
  app.parse_complete_callback([&] {
    using artemis::log::Level;
    const Level level = log_level == "debug"   ? Level::kDebug
                        : log_level == "warn"  ? Level::kWarn
                        : log_level == "error" ? Level::kError
                        : log_level == "off"   ? Level::kOff
                                               : Level::kInfo;
    artemis::log::setLevel(level);
  });

  int exit_code = 0;
  artemis::cli::addDatasetCommands(app, exit_code);
  artemis::cli::addSimCommand(app, exit_code);
  artemis::cli::addRunCommand(app, exit_code);
  artemis::cli::addEvalCommands(app, exit_code);
  artemis::cli::addGroundCommand(app, exit_code);
  artemis::cli::addRenderCommand(app, exit_code);
  artemis::cli::addExportCommand(app, exit_code);
  artemis::cli::addViewCommand(app, exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    artemis::log::error("{}", e.what());
    return 1;
  }
  return exit_code;
}

// Whether the command maps a recording (`artemis [--log-level L] run ...`): the one whose frames
// fault in fresh memory by the megabyte, and worth starting the program twice for.
bool mapsARecording(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--log-level") {
      ++i;
      continue;
    }
    if (!arg.starts_with("-")) return arg == "run";
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (mapsARecording(argc, argv)) artemis::useTunedAllocator(argv);  // may restart it, tuned (core/allocator.hpp)
  // Anything thrown outside the parse (setting up the commands, reporting an error) ends here
  // with a message and a non-zero exit code rather than in std::terminate.
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "artemis: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "artemis: unknown error\n");
  }
  return 1;
}
