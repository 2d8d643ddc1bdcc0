// Subcommands of the `veil` program.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace veil::app {

// Each adds its subcommand to `app`; the callback it sets runs the command and may throw.
void addRenderCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addVoxelizeCommand(CLI::App& app);
void addTechniquesCommand(CLI::App& app);
void addCompareCommand(CLI::App& app); // compare_command.cpp
void addRegressCommand(CLI::App& app); // regress_command.cpp

} // namespace veil::app
