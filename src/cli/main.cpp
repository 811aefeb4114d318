// The cavesim command: parses arguments, calls the library, reports errors, sets the exit code.
//   0 ok, 1 runtime failure, 2 bad input (scenario, arguments, output directory).
#include <cstdio>
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/error.h"

int main(int argc, char** argv) {
    using namespace cavesim;
    CLI::App app{"cavesim " CAVESIM_VERSION
                 " - grows cave-like channel networks in a voxel block of rock (Pytel & Mann, JCGT 2015)\n"
                 "and reports their shape as geoscientists measure real caves."};
    app.set_version_flag("--version", std::string("cavesim ") + CAVESIM_VERSION);
    app.require_subcommand(1);

    cli::RunOptions run;
    CLI::App* runCmd = app.add_subcommand("run", "Run a scenario (the built-in Figure 10 scenario without SCENARIO)");
    runCmd->add_option("scenario", run.scenarioPath, "Scenario file (TOML); see docs/scenario-format.md");
    runCmd->add_option("--out,-o", run.outDir, "Output directory (default out/<scenario name>)");
    runCmd->add_option("--threads,-j", run.threads, "Worker threads (default: all cores); results do not depend on it")
        ->check(CLI::Range(1, 1024));
    runCmd->add_option("--seed", run.seed, "Override the scenario's seed: a whole number in [0, 2^63 - 1]");
    runCmd->add_flag("--force,-f", run.force, "Replace a non-empty output directory");
    runCmd->add_option("--mesh-style", run.meshStyle, "smooth (default) or voxel (also writes the blocky mesh)")
        ->check(CLI::IsMember({"smooth", "voxel"}));
    runCmd->add_flag("--quiet,-q", run.quiet, "No progress output");

    std::string validatePath;
    CLI::App* validateCmd = app.add_subcommand("validate", "Check a scenario file and print a summary");
    validateCmd->add_option("scenario", validatePath, "Scenario file (TOML)")->required();

    std::string reportDir;
    CLI::App* reportCmd = app.add_subcommand("report", "Rebuild report.json and report.md from a run's files");
    reportCmd->add_option("dir", reportDir, "Output directory of an earlier run")->required();

    cli::ReproduceOptions repro;
    CLI::App* reproCmd =
        app.add_subcommand("reproduce", "Run the paper's figure scenarios and write docs/reproduction.md");
    reproCmd->add_option("--scenarios", repro.scenarioDir, "Folder of the figure scenarios")->capture_default_str();
    reproCmd->add_option("--out,-o", repro.outDir, "Folder for the runs")->capture_default_str();
    reproCmd->add_option("--doc", repro.docPath, "Markdown file to write")->capture_default_str();
    reproCmd->add_option("--threads,-j", repro.threads, "Worker threads")->check(CLI::Range(1, 1024));

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }

    try {
        if (*runCmd) return cli::runCommand(run);
        if (*validateCmd) return cli::validateCommand(validatePath);
        if (*reportCmd) return cli::reportCommand(reportDir);
        if (*reproCmd) return cli::reproduceCommand(repro);
    } catch (const InputError& e) {
        std::fprintf(stderr, "cavesim: error: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "cavesim: failed: out of memory (the run needs more than this process may use: "
                             "a smaller [domain] size, image_width or fewer snapshots need less)\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cavesim: failed: %s\n", e.what());
        return 1;
    }
    return 0;
}
