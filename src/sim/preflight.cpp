#include "sim/preflight.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "sim/recharge.h"
#include "sim/stage1.h"

namespace cavesim {
namespace {

// Bytes per voxel of the block (see bench/README.md, "Pre-flight", for the measured peaks).
constexpr double kProgramBytes = 64e6;     // the program, TBB, OpenVDB, before any grid
constexpr double kDomainBytes = 25;        // porosity, porosity0, pressure, water, flow (float), zone (int32), flags
constexpr double kMarchBytes = 12;         // the zone march's merged time (double) and label (int32)
constexpr double kMarchPerThread = 13;     // per front marching at once: time (double), slowness (float), seed flag
constexpr double kStage2DenseBytes = 22;   // water (double), rate (float), pressure (double), seed + scratch flags
constexpr double kStage2ActiveBytes = 80;  // per voxel of an active tile: 9 doubles of transients, masks
constexpr double kActiveShare = 0.6;       // share of the block's tiles that water reaches (fig10 k = 1…4: 0.4–0.5)
constexpr double kOutputBytes = 40;        // the state grids as OpenVDB trees while state.vdb is written

// Rough time: ns per voxel for the fixed work, ns per voxel-iteration of stage 2.
constexpr double kFixedNs = 5000;
constexpr double kIterationNs = 40;
constexpr double kLargestZone = 1.3;  // the largest zone against an equal share of the block (fig10 k = 1…3)

std::string megabytes(double bytes) {
    return withThousands(long(std::ceil(bytes / 1e6))) + " MB";
}

}  // namespace

RunEstimate estimateRun(const Scenario& s, int threads) {
    RunEstimate e;
    const double n = double(s.size[0]) * double(s.size[1]) * double(s.size[2]);
    e.voxels = n;
    const double domain = kDomainBytes * n;
    const double sources = double(s.sources.size() + (s.recharge.empty() ? 0 : rechargeSources(s).size()));
    if (s.stage1.enabled && sources > 0) {
        const double atOnce = std::min(sources, double(std::max(1, threads)));
        // The largest network: the largest zone, or the neighbourhood its network is limited to.
        const double zone =
            std::min({kLargestZone * n / sources, n, double(s.stage1.networkVoxels), double(s.stage1.maxGraphVoxels)});
        e.stage1Bytes =
            domain + kMarchBytes * n + std::max(atOnce * kMarchPerThread * n, atOnce * stage1NetworkBytes(zone));
    }
    if (s.stage2.enabled) e.stage2Bytes = domain + kStage2DenseBytes * n + kActiveShare * kStage2ActiveBytes * n;
    e.outputBytes = domain + kOutputBytes * n;
    e.peakBytes = e.outputBytes;
    e.peakPhase = "output";
    if (e.stage1Bytes > e.peakBytes) {
        e.peakBytes = e.stage1Bytes;
        e.peakPhase = "stage 1";
    }
    if (e.stage2Bytes > e.peakBytes) {
        e.peakBytes = e.stage2Bytes;
        e.peakPhase = "stage 2";
    }
    e.peakBytes += kProgramBytes;
    e.seconds = n * kFixedNs * 1e-9 + (s.stage2.enabled ? n * double(s.stage2.iterations) * kIterationNs * 1e-9 : 0);
    return e;
}

std::string describeEstimate(const RunEstimate& e) {
    std::string time;
    if (e.seconds < 90)
        time = std::to_string(std::max(1L, std::lround(e.seconds))) + " s";
    else if (e.seconds < 5400)
        time = std::to_string(std::lround(e.seconds / 60)) + " min";
    else
        time = std::to_string(std::lround(e.seconds / 3600)) + " h";
    return "peak memory about " + megabytes(e.peakBytes) + " (" + e.peakPhase + "), time roughly " + time;
}

void checkMemory(const RunEstimate& e, const MemoryLimits& limits) {
    const double usable = limits.usable();
    if (usable > 0 && e.peakBytes > usable)
        throw InputError("the run would need about " + megabytes(e.peakBytes) + " at its peak (" + e.peakPhase + ", " +
                         std::to_string(long(e.voxels)) + " voxels), more than the " + megabytes(usable) +
                         " this process may use (" + limits.describe() +
                         "); make the domain smaller, or give the process more memory");
}

}  // namespace cavesim
