/// @file preflight.h
/// @brief The pre-flight check of a run: an estimate of its peak memory and a rough time, made
/// from the scenario alone before any work, and the check of that estimate against what the
/// process may use (core/memory.h). Replaces a fixed cap on the number of voxels.
///
/// The memory model counts bytes per voxel of the block for each phase (the dense domain, the
/// zone march and the flow networks of stage 1, the dense and per-active-tile state of stage 2,
/// the output grids, the speleothem stage's level set) and takes the largest phase;
/// `bench/README.md` compares it with measured peaks.
///
/// The speleothem stage (`[speleothems] enabled`) is estimated from its level set: the cave's
/// surface area A, guessed before any work as a fixed share of the block's bounding-box area
/// (the cave is not known yet), spread over a band of about `kSpeleoBandVoxels`·A/h² voxels of
/// edge h (`voxel_size`), each costing a fixed number of bytes and, per growth step, of
/// nanoseconds; the steps are `years` over the stable step 0.5·h/v_max (v_max = α·l_Q at the
/// fastest drip site) or `time_step`. The constants are measured (docs/speleothems.md,
/// "Pre-flight").
#pragma once

#include <string>

#include "core/memory.h"
#include "sim/scenario.h"

namespace cavesim {

/// Estimated resources of a whole run. Bytes and seconds.
struct RunEstimate {
    double voxels = 0;
    double peakBytes = 0;        ///< the largest phase, plus the program's own
    double stage1Bytes = 0;      ///< stage 1 with the domain
    double stage2Bytes = 0;      ///< stage 2 with the domain
    double outputBytes = 0;      ///< state files, mesh and report with the domain
    double speleoBytes = 0;      ///< the speleothem stage with the domain (0 when it is off)
    double speleoSurfaceM2 = 0;  ///< the cave surface area the speleothem estimate assumes, m²
    double speleoVoxels = 0;     ///< level-set voxels of the speleothem stage
    double speleoSteps = 0;      ///< growth steps
    double speleoSeconds = 0;    ///< rough time of the speleothem stage (included in `seconds`)
    const char* peakPhase = "";
    double seconds = 0;  ///< rough whole-run time on one 2-core machine (a factor of 2 either way)
};

/// The estimate for `scenario` run with `threads` worker threads (≥ 1).
RunEstimate estimateRun(const Scenario& scenario, int threads);

/// The cave surface area (m²) the pre-flight assumes for `scenario` before any work: a fixed
/// share of its block's bounding-box area (calibrated on the Figure 10 cave).
double expectedCaveSurface(const Scenario& scenario);

/// The speleothem stage of `scenario` on a cave of surface area `surfaceM2` (m²): sets the
/// `speleo*` fields of `estimate` (bytes without the domain's), nothing when decoration is off.
void estimateSpeleothems(const Scenario& scenario, double surfaceM2, RunEstimate& estimate);

/// "peak memory about 1,234 MB (stage 2), time roughly 3 min" — for `cavesim validate`.
std::string describeEstimate(const RunEstimate& estimate);

/// Refuses a run whose estimate exceeds what the process may use (the smallest known limit).
/// @throw InputError naming both numbers and the limits they came from
void checkMemory(const RunEstimate& estimate, const MemoryLimits& limits);

}  // namespace cavesim
