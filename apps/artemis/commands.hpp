#pragma once
// Subcommands of the artemis CLI. Each adds itself to the app; its callback stores the exit code.

#include <CLI/CLI.hpp>

#include "artemis/core/status.hpp"

namespace artemis::cli {

void addDatasetCommands(CLI::App& app, int& exit_code);
void addSimCommand(CLI::App& app, int& exit_code);
void addRunCommand(CLI::App& app, int& exit_code);
void addEvalCommands(CLI::App& app, int& exit_code);
void addGroundCommand(CLI::App& app, int& exit_code);
void addRenderCommand(CLI::App& app, int& exit_code);
void addExportCommand(CLI::App& app, int& exit_code);
void addViewCommand(CLI::App& app, int& exit_code);

// Logs the error and returns the exit code of a failed command, 1.
int fail(const Status& status);

}  // namespace artemis::cli
