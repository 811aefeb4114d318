/// @file commands.h
/// @brief The subcommands of `cavesim`: each returns the exit code or throws (InputError → 2).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace cavesim::cli {

struct RunOptions {
    std::optional<std::string> scenarioPath;  ///< empty: the built-in default (fig10)
    std::string outDir;                       ///< empty: out/<scenario name>
    int threads = 0;                          ///< 0: all cores
    std::optional<std::string> seed;          ///< overrides the scenario's seed (checked by runCommand)
    bool force = false;
    bool quiet = false;
    std::string meshStyle;                    ///< empty: the scenario's [output] mesh_style
};

struct ReproduceOptions {
    std::string scenarioDir = "scenarios";
    std::string outDir = "out/reproduce";
    std::string docPath = "docs/reproduction.md";
    int threads = 0;
};

int runCommand(const RunOptions& options);
int validateCommand(const std::string& path);
int reportCommand(const std::string& dir);
int reproduceCommand(const ReproduceOptions& options);

}  // namespace cavesim::cli
