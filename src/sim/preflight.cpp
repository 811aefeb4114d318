#include "sim/preflight.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/text.h"
#include "sim/fractures.h"
#include "sim/recharge.h"
#include "sim/stage1.h"

namespace cavesim {
namespace {

// Bytes per voxel of the block (see bench/README.md, "Pre-flight", for the measured peaks).
constexpr double kProgramBytes = 64e6;       // the program, TBB, OpenVDB, before any grid
constexpr double kDomainBytes = 25;          // porosity, porosity0, pressure, water, flow (float), zone (int32), flags
constexpr double kMarchBytes = 12;           // the zone march's time (double) and label (int32)
constexpr double kMarchScratch = 7;          // while it marches: slowness (float), the queue, the boundary bands (~3)
constexpr double kMarchScratchUnequal = 31;  // with unequal pressures: the stronger fronts' times in weaker zones
constexpr double kStage2DenseBytes = 22;     // water (double), rate (float), pressure (double), seed + scratch flags
constexpr double kStage2ActiveBytes = 80;    // per voxel of an active tile: 9 doubles of transients, masks
constexpr double kActiveShare = 0.6;  // share of the block's tiles that water reaches (fig10 k = 1…4: 0.4–0.5)
constexpr double kOutputBytes = 40;   // the state grids as OpenVDB trees while state.vdb is written
// Per stage-2 iteration: its history row, kept in memory and written to report.json (about 330 bytes
// a row there) as a JSON tree. A 2 × 1 × 1 block: 119 MB peak at 20 000 iterations, 590 MB at 200 000.
constexpr double kHistoryBytes = 2700;

// Rough time: ns per voxel for the fixed work, ns per voxel-iteration of stage 2.
constexpr double kFixedNs = 5000;
constexpr double kIterationNs = 40;
constexpr double kIterationFixedNs = 13000;  // per iteration whatever the block (2 voxels: 200 000 in 2.8 s)
// Fracture families: ns per voxel a disc's slab visits (rasterised, then measured). Measured on a
// 40³ block, 2 cores under load: 407 000 discs of 40 voxels, aperture 3, 12.1 s; 4 070 such discs
// of aperture 10⁶ (each the whole block), 1.6 s.
constexpr double kFractureVoxelNs = 6;
constexpr double kLargestZone = 1.3;  // the largest zone against an equal share of the block (fig10 k = 1…3)

// The speleothem stage (docs/speleothems.md, "Pre-flight", for the measurements).
constexpr double kCaveSurfacePerBoxArea = 0.14;  // cave surface / bounding-box area (fig10: 1 680 / 12 000 m²)
constexpr double kSpeleoBandVoxels = 6.0;        // level-set voxels per A/h² (band of ±3 voxels)
constexpr double kSpeleoBytes = 270;             // peak bytes per level-set voxel (frame copies, meshes, samples)
constexpr double kSpeleoSetupNs = 19000;         // per level-set voxel: level set, relief, meshes, pictures
constexpr double kSpeleoStepNs = 330;            // per level-set voxel and growth step

std::string megabytes(double bytes) {
    return withThousands(long(std::ceil(bytes / 1e6))) + " MB";
}

std::string roughTime(double seconds) {
    if (seconds < 90) return std::to_string(std::max(1L, std::lround(seconds))) + " s";
    if (seconds < 5400) return std::to_string(std::lround(seconds / 60)) + " min";
    if (seconds < 3600.0 * 24 * 365 * 100) return std::to_string(std::lround(seconds / 3600)) + " h";
    return "more than a century";  // no integer overflow however absurd the request
}

}  // namespace

RunEstimate estimateRun(const Scenario& s, int threads) {
    RunEstimate e;
    const double n = double(s.size[0]) * double(s.size[1]) * double(s.size[2]);
    e.voxels = n;
    const double domain = kDomainBytes * n;
    const std::vector<SourceSpec> all = allSources(s);
    const double sources = double(all.size());
    // With unequal pressures the stronger fronts cross the weaker zones (scale_512: 19 bytes a
    // voxel in all with equal pressures, 43 with pressures 3, 1.5, 1, 1, 2, 1; bench/README.md).
    bool unequal = false;
    for (const SourceSpec& src : all) unequal = unequal || src.pressure != all.front().pressure;
    if (s.stage1.enabled && sources > 0) {
        const double atOnce = std::min(sources, double(std::max(1, threads)));
        // The largest network: the largest zone, or the neighbourhood its network is limited to.
        const double zone =
            std::min({kLargestZone * n / sources, n, double(s.stage1.networkVoxels), double(s.stage1.maxGraphVoxels)});
        e.stage1Bytes =
            domain + kMarchBytes * n +
            std::max((unequal ? kMarchScratchUnequal : kMarchScratch) * n, atOnce * stage1NetworkBytes(zone));
    }
    if (s.stage2.enabled) e.stage2Bytes = domain + kStage2DenseBytes * n + kActiveShare * kStage2ActiveBytes * n;
    e.outputBytes = domain + kOutputBytes * n;
    if (s.stage2.enabled) e.outputBytes += kHistoryBytes * double(s.stage2.totalIterations());
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
    e.seconds =
        n * kFixedNs * 1e-9 +
        (s.stage2.enabled ? (n * kIterationNs + kIterationFixedNs) * double(s.stage2.totalIterations()) * 1e-9 : 0);
    // A dense fracture network costs time before stage 1: each disc's slab (at most the block).
    const Dims dims{s.size[0], s.size[1], s.size[2]};
    for (const FractureFamily& f : s.fractureFamilies) {
        const double slab = std::min(n, meanDiscArea(f.lengthExponent, f.minLength, f.maxLength) * (f.aperture + 1));
        e.seconds += fractureCount(f, dims) * slab * kFractureVoxelNs * 1e-9;
    }
    if (s.speleothems.enabled) {
        estimateSpeleothems(s, expectedCaveSurface(s), e);
        e.speleoBytes += domain;
        e.seconds += e.speleoSeconds;
        if (e.speleoBytes > e.peakBytes) {
            e.peakBytes = e.speleoBytes;
            e.peakPhase = "speleothems";
        }
    }
    e.peakBytes += kProgramBytes;
    return e;
}

double expectedCaveSurface(const Scenario& s) {
    const double x = s.size[0] * s.voxelSize, y = s.size[1] * s.voxelSize, z = s.size[2] * s.voxelSize;
    return kCaveSurfacePerBoxArea * 2 * (x * y + x * z + y * z);
}

void estimateSpeleothems(const Scenario& s, double surfaceM2, RunEstimate& e) {
    const SpeleothemOptions& o = s.speleothems;
    e.speleoSurfaceM2 = e.speleoVoxels = e.speleoSteps = e.speleoBytes = e.speleoSeconds = 0;
    if (!o.enabled || !(o.voxelSize > 0)) return;
    const double h = o.voxelSize;
    e.speleoSurfaceM2 = surfaceM2;
    e.speleoVoxels = kSpeleoBandVoxels * surfaceM2 / (h * h);
    e.speleoBytes = kSpeleoBytes * e.speleoVoxels;
    // Steps: `grow`'s step at the fastest drip site's α·l_Q (nothing moves without a speed).
    const double vmax = o.alpha * o.lQ * std::exp(std::abs(o.dripVariability));
    e.speleoSteps = o.drained && vmax > 0 ? std::ceil(o.years / speleothemStep(o, h, vmax)) : 0;
    e.speleoSeconds = e.speleoVoxels * (kSpeleoSetupNs + e.speleoSteps * kSpeleoStepNs) * 1e-9;
}

std::string describeEstimate(const RunEstimate& e) {
    std::string text =
        "peak memory about " + megabytes(e.peakBytes) + " (" + e.peakPhase + "), time roughly " + roughTime(e.seconds);
    if (e.speleoVoxels > 0) {
        char buf[160];
        std::snprintf(buf, sizeof buf, " (speleothems: about %.1f M level-set voxels for %s m² of cave, %.0f steps, %s)",
                      e.speleoVoxels / 1e6, withThousands(std::lround(e.speleoSurfaceM2)).c_str(), e.speleoSteps,
                      roughTime(e.speleoSeconds).c_str());
        text += buf;
    }
    return text;
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
