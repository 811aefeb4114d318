// The cave skeleton (issue 6: skeleton, indices and report of a 60×60×20 result under 1 s).
//  - BM_SkeletonTubes/N: N winding tubes of radius 1–3 voxels through a 60×60×20 grid, crossing
//    each other (loops, junctions); counters give the cave voxels and the skeleton's size.
//  - BM_SkeletonFig10: the cave of the built-in Figure 10 scenario (stages 1 and 2 run once,
//    outside the timing).
// More morpho benchmarks: add BENCHMARK functions below (bench_morpho_metrics.cpp holds the
// network metrics and indices).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>

#include "morpho/skeleton.h"
#include "sim/cave.h"
#include "sim/scenario_io.h"
#include "sim/simulate.h"

namespace {

using namespace cavesim;
using Mask = Grid3<std::uint8_t>;

/// `tubes` seeded random polylines (5 segments, wandering in all three axes) of radius 1–3 voxels.
Mask windingTubes(int tubes, std::uint32_t seed) {
    const Dims d{60, 60, 20};
    Mask m(d, 0);
    std::mt19937 rng(seed);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (double(rng()) / 4294967296.0); };
    for (int t = 0; t < tubes; ++t) {
        const double rho = uniform(1.5, 3.5);  // r + 1/2 for r in 1…3
        std::array<double, 3> p{uniform(0, 59), uniform(0, 59), uniform(2, 17)};
        for (int s = 0; s < 5; ++s) {
            const std::array<double, 3> q{std::clamp(p[0] + uniform(-18, 18), 0.0, 59.0),
                                          std::clamp(p[1] + uniform(-18, 18), 0.0, 59.0),
                                          std::clamp(p[2] + uniform(-5, 5), 2.0, 17.0)};
            const double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
            const double l2 = dx * dx + dy * dy + dz * dz;
            for (int k = 0; k < d.nz; ++k)
                for (int j = 0; j < d.ny; ++j)
                    for (int i = 0; i < d.nx; ++i) {
                        const double ax = i - p[0], ay = j - p[1], az = k - p[2];
                        const double u = l2 > 0 ? std::clamp((ax * dx + ay * dy + az * dz) / l2, 0.0, 1.0) : 0.0;
                        const double ex = ax - u * dx, ey = ay - u * dy, ez = az - u * dz;
                        if (ex * ex + ey * ey + ez * ez <= rho * rho) m.at(i, j, k) = 1;
                    }
            p = q;
        }
    }
    return m;
}

void reportSize(benchmark::State& state, const Mask& mask, const morpho::Skeleton& s) {
    long cave = 0;
    for (const auto v : mask.data) cave += v != 0;
    state.counters["cave_voxels"] = double(cave);
    state.counters["nodes"] = double(s.nodes.size());
    state.counters["edges"] = double(s.edges.size());
}

void BM_SkeletonTubes(benchmark::State& state) {
    const Mask mask = windingTubes(int(state.range(0)), 7);
    morpho::Skeleton s;
    for (auto _ : state) {
        s = morpho::skeletonize(mask, 1.0);
        benchmark::DoNotOptimize(s.nodes.data());
    }
    reportSize(state, mask, s);
}
BENCHMARK(BM_SkeletonTubes)->Arg(4)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The Figure 10 cave, simulated once.
const Mask& fig10Cave() {
    static const Mask mask = [] {
        return caveMask(simulate(defaultScenario()), CaveExtent::kChannels);
    }();
    return mask;
}

void BM_SkeletonFig10(benchmark::State& state) {
    const Mask& mask = fig10Cave();
    morpho::Skeleton s;
    for (auto _ : state) {
        s = morpho::skeletonize(mask, 1.0);
        benchmark::DoNotOptimize(s.nodes.data());
    }
    reportSize(state, mask, s);
}
BENCHMARK(BM_SkeletonFig10)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
