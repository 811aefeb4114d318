/// @file analysis.cpp
/// @brief One pass from the cave voxels to every figure of the report.
#include "morpho/analysis.h"

#include "core/timer.h"
#include "sim/cave.h"

namespace cavesim::morpho {

CaveAnalysis analyseCave(const Cave& cave, const Grid3<float>* pressure,
                         const std::vector<std::optional<int>>& connectedIteration,
                         const SkeletonOptions& skeletonOptions) {
    const Stopwatch watch;
    CaveAnalysis a;
    a.skeleton = skeletonize(cave.mask, cave.voxelSize, skeletonOptions);

    NetworkInput in;
    in.dims = cave.dims();
    in.voxelSize = cave.voxelSize;
    in.cave = &cave.mask;
    in.pressure = pressure;
    in.sources = cave.sourceVoxels;
    in.sinks = cave.sinkVoxels;
    in.connectedIteration = connectedIteration;
    a.network = analyseNetwork(a.skeleton, in);

    a.morphometry = computeMorphometry(cave.mask, a.skeleton, cave.voxelSize);
    a.metrics = computeGraphMetrics(a.skeleton);
    a.seconds = watch.seconds();
    return a;
}

}  // namespace cavesim::morpho
