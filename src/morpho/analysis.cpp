/// @file analysis.cpp
/// @brief One pass from the cave voxels to every figure of the report.
#include "morpho/analysis.h"

#include "core/timer.h"
#include "sim/cave.h"

namespace cavesim::morpho {

CaveAnalysis analyseCave(const Cave& cave, const Grid3<float>* pressure,
                         const std::vector<std::optional<int>>& connectedIteration,
                         const SkeletonOptions& skeletonOptions, const std::vector<double>& familyStrikesDeg) {
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
    const Dims& d = cave.dims();
    const bool section = (d.nx == 1) + (d.ny == 1) + (d.nz == 1) == 1;
    if (section) {
        a.pattern.pattern = "not classified";
        a.pattern.rule = "a 2D section has no plan pattern";
    } else {
        PatternOptions po;
        po.voxelSize = cave.voxelSize;
        a.pattern =
            classifyPattern(a.skeleton, a.metrics, a.morphometry.areal_coverage_pct_opt / 100.0, po, familyStrikesDeg);
        a.sections = measureCrossSections(cave.mask, cave.voxelSize, a.skeleton);
    }
    a.seconds = watch.seconds();
    return a;
}

}  // namespace cavesim::morpho
