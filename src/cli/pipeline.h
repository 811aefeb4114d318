/// @file pipeline.h
/// @brief One run from a validated scenario to every output file (DESIGN §1, §4).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/output_dir.h"
#include "cli/progress_bar.h"
#include "sim/domain.h"
#include "sim/scenario.h"

namespace cavesim::cli {

struct PipelineResult {
    double totalSeconds = 0;
    std::optional<int> breakthroughIteration;
    nlohmann::json report;  ///< the report.json document written
};

/// Writes the named grids of the domain (DESIGN §4) to a .vdb file.
void writeStateVdb(const std::string& path, const Domain& domain, bool stage2);

/// Builds the domain, runs the enabled stages, meshes, draws and reports into `dir` (staging).
PipelineResult runPipeline(const Scenario& scenario, int threads, const OutputDir& dir, ProgressBar& bar);

}  // namespace cavesim::cli
