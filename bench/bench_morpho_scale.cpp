// The report's analysis at scale (issue 18: a 194 k-node skeleton took 36.9 s): skeleton, network
// analysis, morphometry and graph metrics of one synthetic cave, timed as a whole and per step.
//  - BM_AnalyseLattice/N: an N×N lattice of wiggling tubes (radius 1.5 voxels, 12 voxels apart) in
//    a block N·12 × N·12 × 7 voxels, with one source and one sink at opposite corners. The skeleton
//    has about 24·N² nodes: N = 90 gives ~195 k, the size. Time per node should stay flat
//    as N grows (near-linear); the counters give the skeleton's size.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>

#include "core/timer.h"
#include "morpho/analysis.h"
#include "sim/cave.h"

namespace {

using namespace cavesim;

constexpr int kSpacing = 12;

Cave latticeCave(int n) {
    const int side = n * kSpacing;
    Cave c;
    c.mask = Grid3<std::uint8_t>(Dims{side, side, 7}, 0);
    c.voxelSize = 1.0;
    const auto disc = [&](double x, double y, double z) {
        for (int k = int(z) - 2; k <= int(z) + 2; ++k)
            for (int j = int(y) - 2; j <= int(y) + 2; ++j)
                for (int i = int(x) - 2; i <= int(x) + 2; ++i) {
                    if (i < 0 || j < 0 || k < 0 || i >= side || j >= side || k >= 7) continue;
                    const double dx = i - x, dy = j - y, dz = k - z;
                    if (dx * dx + dy * dy + dz * dz <= 2.25) c.mask.at(i, j, k) = 1;
                }
    };
    for (int line = 0; line < n; ++line) {
        const double base = 6 + line * kSpacing;
        for (int s = 0; s < side; ++s) {
            const double wiggle = 1.5 * std::sin(0.37 * s + line), lift = 3 + std::sin(0.21 * s + 2 * line);
            disc(s, base + wiggle, lift);  // along x
            disc(base + wiggle, s, lift);  // along y
        }
    }
    const Dims& d = c.mask.dims;
    for (std::size_t v = 0; v < d.count(); ++v) {
        const Index3 p = d.coord(v);
        if (c.mask[v] && p.i < 8 && p.j < 8) {
            c.sourceVoxels.assign(1, {v});
            break;
        }
    }
    for (std::size_t v = d.count(); v-- > 0;) {
        const Index3 p = d.coord(v);
        if (c.mask[v] && p.i >= side - 8 && p.j >= side - 8) {
            c.sinkVoxels.assign(1, {v});
            break;
        }
    }
    return c;
}

void BM_AnalyseLattice(benchmark::State& state) {
    const Cave cave = latticeCave(int(state.range(0)));
    morpho::CaveAnalysis a;
    double skeleton = 0;
    for (auto _ : state) {
        const Stopwatch t;
        a.skeleton = morpho::skeletonize(cave.mask, cave.voxelSize);
        skeleton += t.seconds();
        a = morpho::analyseCave(cave, nullptr, {std::optional<int>(1)});
        benchmark::DoNotOptimize(a.skeleton.nodes.data());
    }
    state.counters["nodes"] = double(a.skeleton.nodes.size());
    state.counters["edges"] = double(a.skeleton.edges.size());
    state.counters["skeleton_s"] = skeleton / double(state.iterations());
}
BENCHMARK(BM_AnalyseLattice)->Arg(10)->Arg(30)->Arg(90)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
