// `cavesim run` and `cavesim validate`: from a scenario file to a complete output directory.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/output_dir.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/exports.h"
#include "sim/preflight.h"
#include "sim/recharge.h"
#include "sim/scenario_io.h"
#include "site/site.h"

namespace fs = std::filesystem;

namespace cavesim::app {

std::string validateSummary(const std::string& path) {
    Scenario s = parseScenarioFile(path);
    site::loadSite(s);  // the site's files are part of the scenario: checked here too
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: ok: scenario '%s', grid %d x %d x %d (%.3g m voxels), %zu source(s), %zu sink(s), stage 1 %s, "
                  "stage 2 %s",
                  path.c_str(), s.name.c_str(), s.size[0], s.size[1], s.size[2], s.voxelSize,
                  allSources(s).size(),
                  s.sinks.size() + (s.siteData ? s.siteData->sinks.size() : 0), s.stage1.enabled ? "on" : "off",
                  s.stage2.enabled ? (std::to_string(s.stage2.totalIterations()) + " iterations").c_str() : "off");
    return std::string(buf) + "; " + describeEstimate(estimateRun(s, int(tbb::info::default_concurrency())));
}

std::uint64_t parseSeed(const std::string& text) {
    // The effective scenario.toml must hold the seed and reproduce the run.
    const std::string digits =
        text.size() > 1 ? text.substr(std::min(text.find_first_not_of('0'), text.size() - 1)) : text;
    const std::string allowed =
        ": must be a whole number in [0, " + std::to_string(std::numeric_limits<std::int64_t>::max()) + "]";
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || digits.size() > 19)
        throw InputError("--seed " + text + allowed);
    const unsigned long long v = std::stoull(digits);
    if (v > std::uint64_t(std::numeric_limits<std::int64_t>::max())) throw InputError("--seed " + text + allowed);
    return v;
}

namespace {

/// The scenario a run request asks for before its [site]'s files are read: parsed (the scenario
/// file's `text` read earlier when it is given), its overrides applied, validated.
Scenario unloadedScenario(const RunRequest& request, const std::string* text) {
    Scenario s = request.scenarioPath ? (text ? parseScenarioString(*text, *request.scenarioPath)
                                              : parseScenarioFile(*request.scenarioPath))
                                      : defaultScenario();
    if (request.seed) s.seed = parseSeed(*request.seed);
    if (request.meshStyle) s.output.meshStyle = *request.meshStyle;
    if (request.formats) s.output.formats = formats::formatList(formats::parseFormatSet(*request.formats));
    if (request.meshNormals) s.output.meshNormals = *request.meshNormals;
    validateScenario(s);
    return s;
}

/// The request a checkpoint records (its scenario, seed and overrides; no folder, threads 0).
RunRequest checkpointRequest(const Checkpoint& c) {
    RunRequest request;
    if (!c.scenarioPath.empty()) request.scenarioPath = c.scenarioPath;
    request.seed = c.seed;
    request.force = c.force;
    request.meshStyle = c.meshStyle;
    request.formats = c.formats;
    request.meshNormals = c.meshNormals;
    request.checkpointEvery = c.every;
    return request;
}

/// A run of `s` as `request` asks, continuing from `resume` when it is given.
RunOutcome execute(const RunRequest& request, const Scenario& s, const PipelineOptions& callbacks,
                   const Checkpoint* resume, const std::string& resumeName) {
    const int threads = request.threads > 0 ? request.threads : int(tbb::info::default_concurrency());
    checkMemory(estimateRun(s, threads), readMemoryLimits());  // before any work, the output folder included
    const fs::path out = request.outDir.empty() ? fs::path("out") / s.name : fs::path(request.outDir);
    OutputDir dir(out, request.force);  // refuses a non-empty directory before any work

    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    PipelineOptions options = callbacks;
    options.threads = threads;
    if (options.log)
        options.log("scenario '" + s.name + "' (" + s.path + "), grid " + std::to_string(s.size[0]) + "x" +
                    std::to_string(s.size[1]) + "x" + std::to_string(s.size[2]) + ", seed " + std::to_string(s.seed) +
                    ", " + std::to_string(threads) + " thread(s)");
    const fs::path checkpoints = checkpointDir(dir.target());
    if (request.checkpointEvery > 0) {
        Checkpoint& c = options.checkpoint;
        c.every = request.checkpointEvery;
        if (request.scenarioPath) {
            c.scenarioPath = *request.scenarioPath;
            c.scenarioText = resume ? resume->scenarioText : readFileBytes(*request.scenarioPath);
        }
        c.seed = request.seed;
        c.formats = request.formats;
        c.meshStyle = request.meshStyle;
        c.meshNormals = request.meshNormals;
        c.force = request.force;
        c.scenarioHash = scenarioHash(s);
        std::error_code ec;
        fs::create_directories(checkpoints, ec);
        if (ec) throw InputError("cannot create the checkpoint folder " + checkpoints.string() + ": " + ec.message());
        options.checkpointDir = checkpoints;
    }
    options.resume = resume;
    options.resumeName = resumeName;
    dir.open();
    const PipelineResult result = runPipeline(s, dir, options);
    // The last safe point: a caller that asked to stop meanwhile gets nothing moved into place.
    reportProgress(options.progress, "moving results into place", 0, 1);
    dir.commit();
    // The folder is complete: a checkpoint of a run into it (this one's, or an older one's) is spent.
    std::error_code ec;
    if (fs::exists(checkpoints, ec)) fs::remove_all(checkpoints, ec);
    return RunOutcome{out, result.totalSeconds, result.breakthroughIteration};
}

}  // namespace

Scenario requestedScenario(const RunRequest& request) {
    Scenario s = unloadedScenario(request, nullptr);
    site::loadSite(s);
    return s;
}

RunOutcome runScenario(const RunRequest& request, const PipelineOptions& callbacks) {
    return execute(request, requestedScenario(request), callbacks, nullptr, std::string());
}

Scenario checkpointScenario(const Checkpoint& c) {
    return unloadedScenario(checkpointRequest(c), c.scenarioPath.empty() ? nullptr : &c.scenarioText);
}

void checkResumable(const Checkpoint& c, const Scenario& s, const std::string& shown) {
    if (scenarioHash(s) != c.scenarioHash)
        throw InputError(shown +
                         ": the scenario it holds no longer reads as the run read it (another version of cavesim?); "
                         "start the run again");
    if (!s.stage2.enabled || c.iteration >= s.stage2.totalIterations())
        throw InputError(shown + ": a checkpoint after iteration " + std::to_string(c.iteration) +
                         ", which its scenario's stage 2 does not reach");
}

RunOutcome resumeRun(const ResumeRequest& r, const PipelineOptions& callbacks) {
    const fs::path file = checkpointDir(r.dir) / kCheckpointFile;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw InputError(r.dir + ": no checkpoint to resume from (" + file.string() +
                         " is missing; `cavesim run --checkpoint-every N` writes one)");
    const std::string shown = file.string();
    const Checkpoint c = decodeCheckpoint(readFileBytes(file), shown);
    RunRequest request = checkpointRequest(c);
    request.outDir = r.dir;
    request.threads = r.threads;
    request.force = c.force || r.force;
    Scenario s = checkpointScenario(c);
    site::loadSite(s);
    checkResumable(c, s, shown);
    // The pictures of the snapshots before the checkpoint come from it: a checkpoint without them
    // (the library's, which draws none) cannot finish an output folder.
    if (s.output.images) {
        const auto taken = std::count_if(s.stage2.snapshots.begin(), s.stage2.snapshots.end(),
                                         [&](int it) { return it <= c.iteration; });
        if (std::size_t(taken) != c.frames.size())
            throw InputError(shown + ": it holds " + std::to_string(c.frames.size()) + " of the " +
                             std::to_string(taken) +
                             " stage-2 pictures taken before it (a checkpoint of a library run, which draws none?); "
                             "resume it with the library (api::resume), or start the run again");
    }
    if (callbacks.log)
        callbacks.log("resuming from " + shown + ", after stage-2 iteration " + std::to_string(c.iteration));
    return execute(request, s, callbacks, &c, shown);
}

}  // namespace cavesim::app
