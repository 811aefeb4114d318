/// @file commands.h
/// @brief What each `cavesim` subcommand does, as library calls: `src/cli/main.cpp` parses the
/// arguments, calls one of these with a progress and a log callback, prints what it returns and
/// maps exceptions to exit codes (InputError → 2, anything else → 1).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "app/pipeline.h"
#include "sim/options.h"
#include "sim/scenario.h"

namespace cavesim::app {

struct RunRequest {
    std::optional<std::string> scenarioPath;  ///< empty: the built-in default (fig10)
    std::string outDir;                       ///< empty: out/<scenario name>
    int threads = 0;                          ///< 0: all cores
    std::optional<std::string> seed;          ///< overrides the scenario's seed, as typed
    bool force = false;                       ///< replace a non-empty output directory
    std::optional<MeshStyle> meshStyle;       ///< overrides the scenario's mesh style
    std::optional<std::string> formats;       ///< `--formats` list (formats::parseFormatSet), overrides
    std::optional<MeshNormals> meshNormals;   ///< overrides the scenario's `[output] mesh_normals`
    /// `--checkpoint-every N`: a checkpoint after every N-th stage-2 iteration (app/checkpoint.h);
    /// 0: none. Checkpoints do not change any output file.
    int checkpointEvery = 0;
};

/// `cavesim resume DIR`.
struct ResumeRequest {
    std::string dir;     ///< the output folder of the stopped run (`--out`)
    int threads = 0;     ///< 0: all cores
    bool force = false;  ///< replace a non-empty output directory (also when the run had --force)
};

struct RunOutcome {
    std::filesystem::path out;  ///< the output directory written
    double seconds = 0;
    std::optional<int> breakthroughIteration;
};

/// The scenario a run request asks for: parsed (or the default), seed and mesh style overridden,
/// validated.
/// @throw InputError on a bad scenario or seed
Scenario requestedScenario(const RunRequest& request);

/// `--seed TEXT`: digits only (no sign, no wrap-around), at most 2^63 − 1, leading zeros allowed.
/// @throw InputError naming the value and what is allowed
std::uint64_t parseSeed(const std::string& text);

/// `cavesim run`: the whole run into an output directory that appears complete or not at all.
/// `callbacks.threads` is ignored (the request's thread count is used and recorded).
RunOutcome runScenario(const RunRequest& request, const PipelineOptions& callbacks);

/// `cavesim resume DIR`: finishes a stopped `run --checkpoint-every` from its checkpoint
/// (app/checkpoint.h) with the same files, byte for byte, as a run that never stopped (timings and
/// the thread count in the report aside), and removes the checkpoint once the folder is in place.
/// @throw InputError when there is no checkpoint, it is damaged or cut, or it no longer matches
///        its scenario (nothing is written then)
RunOutcome resumeRun(const ResumeRequest& request, const PipelineOptions& callbacks);

/// The scenario a checkpoint (app/checkpoint.h) was made from, as its run read it: its scenario
/// text parsed under its path (the built-in default when the path is empty), the overrides it
/// records (seed, mesh style, formats, normals) applied, validated; its [site]'s files not read yet
/// (site::loadSite). `cavesim resume` and the library's `api::resume` start from it.
/// @throw InputError when the text no longer parses or an override is not allowed
Scenario checkpointScenario(const Checkpoint& checkpoint);

/// Checks that `scenario` (checkpointScenario, its site loaded) is the scenario `checkpoint` was
/// made from (its hash) and that its stage 2 goes past the checkpoint's iteration.
/// @throw InputError naming `shown` and what does not match
void checkResumable(const Checkpoint& checkpoint, const Scenario& scenario, const std::string& shown);

/// `cavesim validate`: the one-line summary of a valid scenario file.
/// @throw InputError when the file is not a valid scenario
std::string validateSummary(const std::string& path);

/// `cavesim report DIR`: rebuilds report.json, report.md and the skeleton files of a run from its
/// files; returns a one-line message.
/// @throw InputError when the folder is not an intact run folder (nothing is rewritten then)
std::string rebuildReport(const std::string& dir);

/// What `cavesim reproduce` rebuilds.
enum class ReproduceSet {
    kPaper,    ///< the paper's figure scenarios: docs/reproduction.md and its pictures
    kGeology,  ///< the shipped geological settings (app/geology_settings.h): docs/geology_settings.md
               ///< and docs/images/geology_<setting>.png
};

struct ReproduceOptions {
    ReproduceSet set = ReproduceSet::kPaper;
    std::string scenarioDir = "scenarios";  ///< folder of the scenario files
    std::string outDir;                     ///< folder of the runs; empty: reproduceDefaultOut(set)
    /// Markdown file to write; its folder must exist, the pictures go into `images/` beside it;
    /// empty: reproduceDefaultDoc(set).
    std::string docPath;
    int threads = 0;  ///< 0: all cores
};

/// The folder of the runs when `--out` is not given: "out/reproduce" (paper), "out/geology".
std::string reproduceDefaultOut(ReproduceSet set);
/// The Markdown file when `--doc` is not given: "docs/reproduction.md" (paper),
/// "docs/geology_settings.md" (geology).
std::string reproduceDefaultDoc(ReproduceSet set);

/// `cavesim reproduce [paper|geology]`: runs the set's scenarios (each run folder appears whole or
/// not at all), then writes the pictures into `images/` beside the Markdown file and the file
/// itself. Every scenario is read and every folder checked before the first run, and nothing is
/// written into the docs before every run has succeeded; each file there is written whole
/// (writeFileAtomic).
/// @throw InputError (nothing written) when the scenario folder or a scenario file is missing or
///        invalid, the Markdown file's folder does not exist, is not a folder or cannot be written,
///        the Markdown path is a folder, `images/` beside it is not a folder, or the runs' folder is
///        refused (OutputDir)
/// @throw RuntimeError on a failure while running or writing
void reproduce(const ReproduceOptions& options, const LogFn& log);

}  // namespace cavesim::app
