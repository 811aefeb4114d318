/// @file pipeline.h
/// @brief One run from a validated scenario to every output file: domain, stage 1, the interim
/// step, stage 2, state files, mesh, pictures, skeleton and report.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/checkpoint.h"
#include "app/output_dir.h"
#include "app/report.h"
#include "core/progress.h"
#include "morpho/analysis.h"
#include "sim/cave.h"
#include "sim/domain.h"
#include "sim/options.h"
#include "sim/scenario.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

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
    /// Checkpoints (app/checkpoint.h) after every `checkpoint.every`-th stage-2 iteration (0: none),
    /// into `checkpointDir`; `checkpoint` holds how the run was asked for, the rest is filled in.
    Checkpoint checkpoint;
    std::filesystem::path checkpointDir;
    /// Not null: continue stage 2 from this checkpoint (its domain fingerprint is checked).
    const Checkpoint* resume = nullptr;
    std::string resumeName;  ///< names `resume`'s file in messages
};

struct PipelineResult {
    double totalSeconds = 0;
    std::optional<int> breakthroughIteration;
    nlohmann::json report;        ///< the report.json document written
    nlohmann::json alsoMeasured;  ///< with `alsoMeasure`: the report's analysis keys under that definition
};

/// Stage 1 of `scenario` on `domain` (runStage1), with a limit it exceeds reported as an InputError
/// naming the scenario file, the line of the source and the key: the stage as a run runs it.
/// @throw InputError for a limit the scenario exceeds; RuntimeError on a failure while running
Stage1Result runScenarioStage1(Domain& domain, const Scenario& scenario, Rng& rng, const ProgressFn& progress);

/// What a caller of runStages does around the stages (each may be empty).
struct StageHooks {
    /// After stage 1, its result in `record.stage1` and its time taken.
    std::function<void(const Domain& domain, const RunRecord& record)> afterStage1;
    /// After the interim step (prepareStage2), before stage 2's first iteration; part of stage 2's time.
    std::function<void(const Domain& domain, RunRecord& record)> beforeStage2;
    /// Stage 2's snapshots (runStage2).
    SnapshotFn snapshot;
    /// Stage 2's checkpoints, or the state it continues from (runStage2).
    Stage2Checkpoints checkpoints;
};

/// Stage-2 checkpoints in `hooks`, the same for `cavesim run`/`resume` and the library. When `resume`
/// is given or `every` > 0, the domain is fingerprinted before stage 2 (domainFingerprint); a resumed
/// run's fingerprint is checked against `resume` (checkResumedDomain with `resumeName`, `advice`) and
/// stage 2 continues from `resume`'s state. Every `every` iterations `save` gets `base` with that
/// fingerprint, the iteration and stage 2's state, to complete and write. A `beforeStage2` already in
/// `hooks` runs after the check. `resume` must outlive the run.
void wireCheckpoints(StageHooks& hooks, const Checkpoint* resume, const std::string& resumeName,
                     const std::string& advice, int every, const Checkpoint& base,
                     std::function<void(Checkpoint& checkpoint)> save);

/// The enabled stages of `scenario` on `domain` as a run runs them (built by buildDomain with
/// `rng`, which the stages draw on next): stage 1 (runScenarioStage1), the interim step and
/// stage 2, their results and times in `record`.
/// @throw InputError for a limit the scenario exceeds; RuntimeError on a failure while running
void runStages(Domain& domain, const Scenario& scenario, Rng& rng, RunRecord& record, const ProgressFn& progress,
               const StageHooks& hooks = {});

/// The strikes of the scenario's fracture families, degrees clockwise from north in [0, 180):
/// dip direction − 90°, for the pattern's family-share criterion (empty without families).
std::vector<double> familyStrikes(const Scenario& scenario);

/// The cave analysis of a run (morpho::analyseCave with the scenario's fracture strikes and the
/// protochannel proximity): the pressure field when stage 2 ran, and `connected`, the iterations at
/// which the sources joined a sink (empty without stage 2).
morpho::CaveAnalysis analyseRun(const Cave& cave, const Domain& domain, const Scenario& scenario,
                                const std::vector<std::optional<int>>& connected);

/// The source connection iterations of a run's record (empty without stage 2).
std::vector<std::optional<int>> connectedIterations(const RunRecord& record);

/// Distance (voxels) within which centreline counts as near a stage-1 protochannel.
inline constexpr double kNearProtochannelVoxels = 2.0;

/// When stage 2 ran: the share of the centreline and of the block within kNearProtochannelVoxels
/// of a protochannel voxel (flag kProtochannel), stored in `analysis.nearProtochannels`.
void addProtochannelProximity(morpho::CaveAnalysis& analysis, const Domain& domain, const Scenario& scenario);

/// Builds the domain, runs the enabled stages, meshes, draws and reports into `dir` (staging).
/// @throw InputError for limits the scenario exceeds (naming the file, line and key);
///        RuntimeError on a failure while running
PipelineResult runPipeline(const Scenario& scenario, const OutputDir& dir, const PipelineOptions& options);

}  // namespace cavesim::app
