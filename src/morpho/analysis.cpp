/// @file analysis.cpp
/// @brief One pass from the cave voxels to every figure of the report.
#include "morpho/analysis.h"

#include <chrono>

#include "sim/cave.h"

namespace cavesim::morpho {

CaveAnalysis analyseCave(const Domain& dom, const std::vector<std::optional<int>>& connectedIteration,
                         const SkeletonOptions& skeletonOptions) {
    const auto t0 = std::chrono::steady_clock::now();
    CaveAnalysis a;
    const Grid3<std::uint8_t> cave = caveMask(dom);
    a.skeleton = skeletonize(cave, dom.voxelSize, skeletonOptions);

    NetworkInput in;
    in.dims = dom.dims;
    in.voxelSize = dom.voxelSize;
    in.cave = &cave;
    bool anyPressure = false;
    for (float p : dom.pressure.data) anyPressure = anyPressure || p != 0.f;
    in.pressure = anyPressure ? &dom.pressure : nullptr;
    in.sources = dom.sourceVoxels;
    in.sinks = dom.sinkVoxels;
    in.connectedIteration = connectedIteration;
    a.network = analyseNetwork(a.skeleton, in);

    a.morphometry = computeMorphometry(cave, a.skeleton, dom.voxelSize);
    a.metrics = computeGraphMetrics(a.skeleton);
    a.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return a;
}

}  // namespace cavesim::morpho
