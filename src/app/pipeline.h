/// @file pipeline.h
/// @brief One run from a validated scenario to every output file: domain, stage 1, the interim
/// step, stage 2, state files, mesh, pictures, skeleton and report.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/output_dir.h"
#include "core/progress.h"
#include "sim/options.h"
#include "sim/domain.h"
#include "sim/scenario.h"
#include "sim/stage1.h"

namespace cavesim::app {

/// A one-line message for the user ("stage 1: 3 zone(s) …"); may be empty.
using LogFn = std::function<void(const std::string& message)>;

struct PipelineOptions {
    int threads = 1;  ///< recorded in the report (the caller sets TBB's limit)
    /// Also measure the cave under this definition (no mesh or pictures for it): `reproduce`
    /// measures both definitions from one simulation.
    std::optional<CaveExtent> alsoMeasure;
    ProgressFn progress;
    LogFn log;
};

struct PipelineResult {
    double totalSeconds = 0;
    std::optional<int> breakthroughIteration;
    nlohmann::json report;       ///< the report.json document written
    nlohmann::json alsoMeasured; ///< with `alsoMeasure`: the report's analysis keys under that definition
};

/// Stage 1 of `scenario` on `domain` (runStage1), with a limit it exceeds reported as an InputError
/// naming the scenario file, the line of the source and the key: the stage as a run runs it.
/// @throw InputError for a limit the scenario exceeds; RuntimeError on a failure while running
Stage1Result runScenarioStage1(Domain& domain, const Scenario& scenario, Rng& rng, const ProgressFn& progress);

/// Builds the domain, runs the enabled stages, meshes, draws and reports into `dir` (staging).
/// @throw InputError for limits the scenario exceeds (naming the file, line and key);
///        RuntimeError on a failure while running
PipelineResult runPipeline(const Scenario& scenario, const OutputDir& dir, const PipelineOptions& options);

}  // namespace cavesim::app
