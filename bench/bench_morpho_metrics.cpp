// Network metrics and morphometric indices on synthetic caves of about 5,000 skeleton nodes
// (section for bench_morpho.cpp; runs standalone with benchmark_main).
//  - Cave: an 8×8 lattice of junctions joined by wiggling passages of 44 inner nodes (4,992 nodes,
//    64 reduced nodes): the shape of a real skeleton, mostly degree-2 chains.
//  - Junctions: a 17×17×17 grid graph (4,913 nodes, all of degree ≥ 3): the worst case for the
//    all-pairs work on the reduced graph (BFS for spl, Brandes for cpd).
#include <benchmark/benchmark.h>

#include <cmath>

#include "morpho/graph_metrics.h"
#include "morpho/morphometry.h"

namespace {

using cavesim::Dims;
using cavesim::Grid3;
using namespace cavesim::morpho;

constexpr int kJunctions = 8;   // per side
constexpr int kSpacing = 45;    // voxels between junctions
constexpr double kVoxel = 0.5;  // metres

struct Cave {
    Skeleton skeleton;
    Grid3<std::uint8_t> mask;
};

/// Passages along x and y between lattice junctions, wiggling sideways by up to 2 voxels; the mask
/// holds the 3×3-voxel tube around each node.
Cave latticeCave() {
    Cave c;
    const int n = (kJunctions - 1) * kSpacing + 1 + 6;
    c.mask = Grid3<std::uint8_t>(Dims{n, n, 6}, 0);
    auto addNode = [&](double i, double j, double k) {
        c.skeleton.nodes.push_back({{(i + 0.5) * kVoxel, (j + 0.5) * kVoxel, (k + 0.5) * kVoxel}, kVoxel, 0});
        for (int dk = -1; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    c.mask.at(int(std::lround(i)) + di, int(std::lround(j)) + dj, int(std::lround(k)) + dk) = 1;
        return int(c.skeleton.nodes.size()) - 1;
    };
    std::vector<int> junction(kJunctions * kJunctions);
    for (int b = 0; b < kJunctions; ++b)
        for (int a = 0; a < kJunctions; ++a)
            junction[a + kJunctions * b] = addNode(3 + a * kSpacing, 3 + b * kSpacing, 2);
    auto passage = [&](int from, int to, int a, int b, bool alongX) {
        int prev = from;
        for (int s = 1; s < kSpacing; ++s) {
            const double t = double(s) / kSpacing;
            const double side = 2.0 * std::sin(3.14159265358979 * t * (1 + (a + b) % 3));
            const double lift = 1.0 * std::sin(3.14159265358979 * t);
            const double i = 3 + a * kSpacing + (alongX ? s : side);
            const double j = 3 + b * kSpacing + (alongX ? side : s);
            const int v = addNode(i, j, 2 + lift);
            c.skeleton.edges.push_back({prev, v});
            prev = v;
        }
        c.skeleton.edges.push_back({std::min(prev, to), std::max(prev, to)});
    };
    for (int b = 0; b < kJunctions; ++b)
        for (int a = 0; a < kJunctions; ++a) {
            if (a + 1 < kJunctions) passage(junction[a + kJunctions * b], junction[a + 1 + kJunctions * b], a, b, true);
            if (b + 1 < kJunctions)
                passage(junction[a + kJunctions * b], junction[a + kJunctions * (b + 1)], a, b, false);
        }
    return c;
}

Skeleton gridGraph(int m) {
    Skeleton s;
    auto id = [m](int i, int j, int k) { return i + m * (j + m * k); };
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                s.nodes.push_back({{i + 0.1 * std::sin(j + k), j + 0.1 * std::cos(i), k * 1.0}, 0.5, 0});
                if (i + 1 < m) s.edges.push_back({id(i, j, k), id(i + 1, j, k)});
                if (j + 1 < m) s.edges.push_back({id(i, j, k), id(i, j + 1, k)});
                if (k + 1 < m) s.edges.push_back({id(i, j, k), id(i, j, k + 1)});
            }
    return s;
}

void BM_GraphMetrics_Cave5k(benchmark::State& state) {
    const Cave c = latticeCave();
    for (auto _ : state) benchmark::DoNotOptimize(computeGraphMetrics(c.skeleton));
    state.counters["nodes"] = double(c.skeleton.nodes.size());
}
BENCHMARK(BM_GraphMetrics_Cave5k)->Unit(benchmark::kMillisecond);

void BM_Morphometry_Cave5k(benchmark::State& state) {
    const Cave c = latticeCave();
    for (auto _ : state) benchmark::DoNotOptimize(computeMorphometry(c.mask, c.skeleton, kVoxel));
    state.counters["voxels"] = double(c.mask.size());
}
BENCHMARK(BM_Morphometry_Cave5k)->Unit(benchmark::kMillisecond);

void BM_MetricsAndMorphometry_Cave5k(benchmark::State& state) {
    const Cave c = latticeCave();
    for (auto _ : state) {
        benchmark::DoNotOptimize(computeGraphMetrics(c.skeleton));
        benchmark::DoNotOptimize(computeMorphometry(c.mask, c.skeleton, kVoxel));
    }
    state.counters["nodes"] = double(c.skeleton.nodes.size());
}
BENCHMARK(BM_MetricsAndMorphometry_Cave5k)->Unit(benchmark::kMillisecond);

void BM_GraphMetrics_AllJunctions5k(benchmark::State& state) {
    const Skeleton s = gridGraph(17);
    for (auto _ : state) benchmark::DoNotOptimize(computeGraphMetrics(s));
    state.counters["nodes"] = double(s.nodes.size());
}
BENCHMARK(BM_GraphMetrics_AllJunctions5k)->Unit(benchmark::kMillisecond);

}  // namespace
