// The cavesim command: parses arguments, calls the library, reports errors, sets the exit code.
//   0 ok, 1 runtime failure, 2 bad input (scenario, arguments, output directory).
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>

#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/ensemble.h"
#include "cli/interrupt.h"
#include "cli/progress_bar.h"
#include "core/error.h"
#include "sim/parameters.h"
#include "sim/scenario_io.h"

namespace {

/// The names of a choice key (the parameter registry's), for CLI11's IsMember.
std::vector<std::string> choiceNames(const cavesim::Param& p) {
    std::vector<std::string> names;
    for (const cavesim::ParamChoice& c : p.choices) names.push_back(c.name);
    return names;
}

/// The enum value of the choice `name` (one of choiceNames(p): CLI11 checked it).
template <typename E>
E choiceValue(const cavesim::Param& p, const std::string& name) {
    for (const cavesim::ParamChoice& c : p.choices)
        if (name == c.name) return E(c.value);
    throw cavesim::InputError("'" + name + "' is not a choice of '" + p.key + "'");
}

}  // namespace

int main(int argc, char** argv) {
    using namespace cavesim;
    CLI::App app{"cavesim " CAVESIM_VERSION
                 " - grows cave-like channel networks in a voxel block of rock (Pytel & Mann, JCGT 2015)\n"
                 "and reports their shape as geoscientists measure real caves."};
    app.set_version_flag("--version", std::string("cavesim ") + CAVESIM_VERSION);
    app.require_subcommand(1);

    // An empty --out (an unset shell variable) once fell back to the default folder silently.
    const CLI::Validator notEmpty(
        [](const std::string& v) { return v.empty() ? std::string("an empty path: give a folder") : std::string(); },
        "PATH");
    app::RunRequest run;
    bool quiet = false;
    // --mesh-style and --mesh-normals override `[output]` keys: their names are the registry's.
    const Scenario defaults;
    const Param& meshStyleKey = *findParam(defaults, &defaults.output.meshStyle).second;
    const Param& meshNormalsKey = *findParam(defaults, &defaults.output.meshNormals).second;
    std::string meshStyle;
    CLI::App* runCmd = app.add_subcommand("run", "Run a scenario (the built-in Figure 10 scenario without SCENARIO)");
    runCmd->add_option("scenario", run.scenarioPath, "Scenario file (TOML); see docs/scenario-format.md");
    runCmd->add_option("--out,-o", run.outDir, "Output directory (default out/<scenario name>)")->check(notEmpty);
    runCmd->add_option("--threads,-j", run.threads, "Worker threads (default: all cores); results do not depend on it")
        ->check(CLI::Range(1, 1024));
    runCmd->add_option("--seed", run.seed, "Override the scenario's seed: a whole number in [0, 2^63 - 1]");
    runCmd->add_flag("--force,-f", run.force, "Replace a non-empty output directory");
    runCmd->add_option("--mesh-style", meshStyle, "smooth (default) or voxel (also writes the blocky mesh)")
        ->check(CLI::IsMember(choiceNames(meshStyleKey)));
    runCmd->add_option("--formats", run.formats,
                       "Files for other tools, a comma list of glb, vtk, stl, svx, th, gocad, csv, vdb, or all, "
                       "or none (default: the scenario's [output] formats, glb,vtk,svx,csv)");
    std::string meshNormals;
    runCmd->add_option("--mesh-normals", meshNormals, "outward (default) or inward: the side cave.glb's normals face")
        ->check(CLI::IsMember(choiceNames(meshNormalsKey)));
    runCmd
        ->add_option("--checkpoint-every", run.checkpointEvery,
                     "Write a checkpoint after every N-th stage-2 iteration (0: none, the default), for "
                     "`cavesim resume`; the output files are the same either way")
        ->check(CLI::Range(0, 1000000000));
    runCmd->add_flag("--quiet,-q", quiet, "No progress output");

    app::ResumeRequest resume;
    CLI::App* resumeCmd = app.add_subcommand(
        "resume",
        "Finish a stopped `run --checkpoint-every N` from its newest checkpoint: the same files as a run "
        "that never stopped");
    resumeCmd->add_option("dir", resume.dir, "Output directory of the stopped run (its --out)")->required()->check(notEmpty);
    resumeCmd->add_option("--threads,-j", resume.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    resumeCmd->add_flag("--force,-f", resume.force, "Replace a non-empty output directory");
    resumeCmd->add_flag("--quiet,-q", quiet, "No progress output");

    std::string validatePath;
    CLI::App* validateCmd = app.add_subcommand("validate", "Check a scenario file and print a summary");
    validateCmd->add_option("scenario", validatePath, "Scenario file (TOML)")->required();

    std::string reportDir;
    CLI::App* reportCmd = app.add_subcommand("report", "Rebuild report.json and report.md from a run's files");
    reportCmd->add_option("dir", reportDir, "Output directory of an earlier run")->required();

    bool example = false;
    CLI::App* referenceCmd =
        app.add_subcommand("reference", "Print the scenario reference (Markdown, docs/scenario-format.md)");
    referenceCmd->add_flag("--example", example,
                           "Print a complete, commented example scenario instead (every key at its default)");

    // `reproduce [paper|geology]`: one command that rebuilds a generated page of the docs and its
    // pictures from shipped scenarios; the word names which page (the options are the same).
    app::ReproduceOptions repro;
    std::string reproSet = "paper";
    CLI::App* reproCmd = app.add_subcommand(
        "reproduce",
        "Rebuild a generated page of the docs and its pictures: paper (default) runs the paper's figure "
        "scenarios and writes docs/reproduction.md; geology runs the shipped geological settings (seed 1) and "
        "writes docs/geology_settings.md and docs/images/geology_*.png");
    reproCmd->add_option("set", reproSet, "What to rebuild: paper or geology")
        ->check(CLI::IsMember({"paper", "geology"}))
        ->capture_default_str();
    reproCmd->add_option("--scenarios", repro.scenarioDir, "Folder of the scenarios")->capture_default_str();
    reproCmd->add_option("--out,-o", repro.outDir, "Folder for the runs (default out/reproduce; geology: out/geology)")
        ->check(notEmpty);
    reproCmd->add_option("--doc", repro.docPath,
                         "Markdown file to write, in an existing folder; the pictures go into images/ beside it "
                         "(default docs/reproduction.md; geology: docs/geology_settings.md)");
    reproCmd->add_option("--threads,-j", repro.threads, "Worker threads")->check(CLI::Range(1, 1024));

    app::EnsembleRequest ens;
    CLI::App* ensembleCmd = app.add_subcommand(
        "ensemble", "Run N realisations of a scenario (in parallel; under mpirun spread over the ranks), resumable");
    ensembleCmd->add_option("scenario", ens.scenarioPath, "Scenario file (TOML)")->required();
    ensembleCmd->add_option("--members,-n", ens.members, "Number of members")->required()->check(CLI::Range(1, 100000));
    ensembleCmd->add_option("--vary", ens.vary,
                            "KEY=LOW:HIGH[:uniform|log] draws a number key per member (repeatable; keys with 'rate' "
                            "in their name are log-uniform unless told)");
    ensembleCmd->add_option("--out,-o", ens.outDir, "Ensemble folder (default out/<scenario name>_ensemble)")
        ->check(notEmpty);
    ensembleCmd
        ->add_option("--threads,-j", ens.threads,
                     "Threads of this process (default: all cores, shared by the ranks on a machine)")
        ->check(CLI::Range(1, 1024));
    ensembleCmd->add_option("--parallel", ens.parallel, "Members at once in this process (default: the threads)")
        ->check(CLI::Range(1, 1024));

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }

    try {
        if (*runCmd || *resumeCmd) {
            if (!meshStyle.empty()) run.meshStyle = choiceValue<MeshStyle>(meshStyleKey, meshStyle);
            if (!meshNormals.empty()) run.meshNormals = choiceValue<MeshNormals>(meshNormalsKey, meshNormals);
            cli::ProgressBar bar(quiet);
            cli::installStopHandlers();  // the callbacks below are the run's safe points
            // For the tests of checkpoints only: the process kills itself (SIGKILL, no clean-up) when
            // stage 2 reports this iteration done, right after its checkpoint.
            const char* killAt = std::getenv("CAVESIM_TEST_KILL_AT_ITERATION");
            const long killIteration = killAt ? std::atol(killAt) : 0;
            app::PipelineOptions callbacks;
            callbacks.progress = [&bar, killIteration](const std::string& phase, long done, long total) {
                if (killIteration > 0 && phase == "stage 2" && done == killIteration) std::raise(SIGKILL);
                cli::throwIfStopped();
                bar.update(phase, done, total);
            };
            callbacks.log = [&bar](const std::string& message) {
                cli::throwIfStopped();
                bar.log(message);
            };
            const app::RunOutcome done = *runCmd ? app::runScenario(run, callbacks) : app::resumeRun(resume, callbacks);
            bar.log("wrote " + done.out.string() + " in " + std::to_string(done.seconds).substr(0, 5) + " s" +
                    (done.breakthroughIteration
                         ? ", breakthrough at iteration " + std::to_string(*done.breakthroughIteration)
                         : std::string()));
            return 0;
        }
        if (*ensembleCmd) {
            const app::Communicator comm = app::processCommunicator();
            const auto log = [&comm](const std::string& m) {
                std::fprintf(stderr, "%s%s\n", comm.size > 1 ? ("[" + std::to_string(comm.rank) + "] ").c_str() : "",
                             m.c_str());
            };
            const app::EnsembleOutcome done = app::runEnsemble(ens, comm, log);
            if (done.summary) {
                std::printf("wrote %s: %d member(s), %d ok, %d failed\n", done.out.string().c_str(), done.members,
                            done.ok, done.failed);
                if (done.failed > 0) return 1;
            }
            return 0;
        }
        if (*validateCmd) {
            std::printf("%s\n", app::validateSummary(validatePath).c_str());
            return 0;
        }
        if (*referenceCmd) {
            std::fputs((example ? exampleScenarioToml() : scenarioReferenceMarkdown()).c_str(), stdout);
            return 0;
        }
        if (*reportCmd) {
            std::printf("%s\n", app::rebuildReport(reportDir).c_str());
            return 0;
        }
        if (*reproCmd) {
            repro.set = reproSet == "geology" ? app::ReproduceSet::kGeology : app::ReproduceSet::kPaper;
            app::reproduce(repro, [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
            return 0;
        }
    } catch (const Cancelled& e) {
        // A checkpoint of the stopped run (run --checkpoint-every, resume) stays for `cavesim resume`.
        const std::string dir = *resumeCmd ? resume.dir : run.checkpointEvery > 0 ? run.outDir : std::string();
        std::error_code ec;
        const bool kept = !dir.empty() && std::filesystem::exists(app::checkpointDir(dir) / app::kCheckpointFile, ec);
        std::fprintf(stderr, "\ncavesim: interrupted by %s: stopped, the unfinished output was removed%s\n", e.what(),
                     kept ? ("; its checkpoint is kept: `cavesim resume " + dir + "` continues it").c_str() : "");
        return 128 + cli::stopSignal();
    } catch (const InputError& e) {
        std::fprintf(stderr, "cavesim: error: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        const Scenario& d = defaults;
        std::fprintf(stderr,
                     "cavesim: failed: out of memory (the run needs more than this process may use: "
                     "a smaller %s, %s or fewer %s need less)\n",
                     scenarioKey(d, &d.size).c_str(), scenarioKey(d, &d.output.imageWidth).c_str(),
                     scenarioKey(d, &d.stage2.snapshots).c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cavesim: failed: %s\n", e.what());
        return 1;
    }
    return 0;
}
