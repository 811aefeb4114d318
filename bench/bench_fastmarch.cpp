// Fast marching on the Figure 10 grid: a full capped eikonal solve, an incremental update after a
// few voxels' rates fell, and three labelled fronts (stage-1 zones).
#include <benchmark/benchmark.h>

#include <random>

#include "fastmarch/fast_marching.h"

namespace {

using namespace cavesim;
using namespace cavesim::fastmarch;

const Dims kDims{60, 60, 20};

void BM_EikonalFullSolve(benchmark::State& state) {
    Grid3<float> s(kDims, 0.5f);
    const std::vector<Seed> seeds{{kDims.index(57, 30, 2), 0.0, 0}};
    for (auto _ : state) {
        EikonalField f;
        f.solve(kDims, s, seeds, 1e9, Stencil(state.range(0)));
        benchmark::DoNotOptimize(f.value().data.data());
    }
}
// Arg 0: face-neighbour fast marching (kFace6); 1: the stage-2 avalanche stencil (kAvalanche26).
BENCHMARK(BM_EikonalFullSolve)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EikonalDecrease(benchmark::State& state) {
    Grid3<float> s(kDims, 0.5f);
    const std::vector<Seed> seeds{{kDims.index(57, 30, 2), 0.0, 0}};
    std::mt19937_64 rng(1);
    std::uniform_int_distribution<std::size_t> pick(0, kDims.count() - 1);
    for (auto _ : state) {
        state.PauseTiming();
        EikonalField f;
        f.solve(kDims, s, seeds, 1e9, Stencil(state.range(1)));
        Grid3<float> t = s;
        std::vector<std::size_t> changed;
        for (int c = 0; c < int(state.range(0)); ++c) {
            const std::size_t q = pick(rng);
            t[q] = 0.001f;
            changed.push_back(q);
        }
        state.ResumeTiming();
        benchmark::DoNotOptimize(f.decrease(t, changed));
    }
}
BENCHMARK(BM_EikonalDecrease)
    ->Args({10, 0})
    ->Args({100, 0})
    ->Args({10, 1})
    ->Args({100, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_ThreeLabelledFronts(benchmark::State& state) {
    const std::vector<Seed> seeds{{kDims.index(5, 10, 15), 0, 0}, {kDims.index(10, 50, 15), 0, 1},
                                  {kDims.index(30, 30, 18), 0, 2}};
    for (auto _ : state) benchmark::DoNotOptimize(marchLabelled(kDims, nullptr, seeds, {1.0, 1.0, 1.5}));
}
BENCHMARK(BM_ThreeLabelledFronts)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
