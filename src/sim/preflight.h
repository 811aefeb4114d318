/// @file preflight.h
/// @brief The pre-flight check of a run: an estimate of its peak memory and a rough time, made
/// from the scenario alone before any work, and the check of that estimate against what the
/// process may use (core/memory.h). Replaces a fixed cap on the number of voxels.
///
/// The memory model counts bytes per voxel of the block for each phase (the dense domain, the
/// zone march and the flow networks of stage 1, the dense and per-active-tile state of stage 2,
/// the output grids) and takes the largest phase; `bench/README.md` compares it with measured
/// peaks.
#pragma once

#include <string>

#include "core/memory.h"
#include "sim/scenario.h"

namespace cavesim {

/// Estimated resources of a whole run. Bytes and seconds.
struct RunEstimate {
    double voxels = 0;
    double peakBytes = 0;    ///< the largest phase, plus the program's own
    double stage1Bytes = 0;  ///< stage 1 with the domain
    double stage2Bytes = 0;  ///< stage 2 with the domain
    double outputBytes = 0;  ///< state files, mesh and report with the domain
    const char* peakPhase = "";
    double seconds = 0;  ///< rough whole-run time on one 2-core machine (a factor of 2 either way)
};

/// The estimate for `scenario` run with `threads` worker threads (≥ 1).
RunEstimate estimateRun(const Scenario& scenario, int threads);

/// "peak memory about 1,234 MB (stage 2), time roughly 3 min" — for `cavesim validate`.
std::string describeEstimate(const RunEstimate& estimate);

/// Refuses a run whose estimate exceeds what the process may use (the smallest known limit).
/// @throw InputError naming both numbers and the limits they came from
void checkMemory(const RunEstimate& estimate, const MemoryLimits& limits);

}  // namespace cavesim
