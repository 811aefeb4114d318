// Fast marching on the Figure 10 grid: a full capped eikonal solve, an incremental update after a
// few voxels' rates fell, and three labelled fronts (stage-1 zones).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include <tbb/global_control.h>

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

/// The stage-2 pressure front at the scale of issue 13 (256×256×128, 8.4 M voxels): rock of rate
/// 0.5, a sink patch on the +x face, cap 2 · 0.5 · (nx + ny + nz). Arg: threads.
const Dims kLarge{256, 256, 128};

std::vector<Seed> largeSinkSeeds() {
    std::vector<Seed> seeds;
    for (int k = 0; k < 16; ++k)
        for (int j = 120; j < 136; ++j) seeds.push_back({kLarge.index(255, j, k), 0.0, 0});
    return seeds;
}

void BM_EikonalSolveLarge(benchmark::State& state) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    const Grid3<float> s(kLarge, 0.5f);
    const std::vector<Seed> seeds = largeSinkSeeds();
    for (auto _ : state) {
        EikonalField f;
        f.solve(kLarge, s, seeds, 640.0, Stencil::kAvalanche26);
        benchmark::DoNotOptimize(f.value().data.data());
    }
}
BENCHMARK(BM_EikonalSolveLarge)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// A channel (rate 0.001) grows from the sink into the block, 8 voxels per call over 16 calls, each
/// call the decrease-only update (what stage 2 does when its channels lengthen). Args: threads, and
/// whether the sink voxels have the channel rate from the start, as stage 2's rate field gives them
/// (1; then the queue's buckets are as narrow as a channel step from the first solve on) or the
/// rock's (0: the slowness is uniform at the solve).
void BM_EikonalDecreaseLarge(benchmark::State& state) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
    const std::vector<Seed> seeds = largeSinkSeeds();
    std::vector<std::vector<std::size_t>> calls(16);
    {
        std::mt19937_64 rng(7);
        std::uniform_int_distribution<int> step(-1, 1);
        Index3 tip{254, 128, 8};
        for (auto& call : calls)
            for (int c = 0; c < 8; ++c) {
                tip = {std::clamp(tip.i - 1 + step(rng), 1, kLarge.nx - 2),
                       std::clamp(tip.j + step(rng), 1, kLarge.ny - 2),
                       std::clamp(tip.k + step(rng), 1, kLarge.nz - 2)};
                call.push_back(kLarge.index(tip));
            }
    }
    std::size_t changed = 0;
    for (auto _ : state) {
        state.PauseTiming();
        Grid3<float> s(kLarge, 0.5f);
        if (state.range(1))
            for (const Seed& seed : seeds) s[seed.voxel] = 0.001f;
        EikonalField f;
        f.solve(kLarge, s, seeds, 640.0, Stencil::kAvalanche26);
        state.ResumeTiming();
        changed = 0;
        for (const auto& call : calls) {
            for (std::size_t v : call) s[v] = 0.001f;
            changed += f.decrease(s, call);
        }
    }
    state.counters["changed_voxels"] = double(changed);
}
BENCHMARK(BM_EikonalDecreaseLarge)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({1, 1})
    ->Args({2, 1})
    ->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ThreeLabelledFronts(benchmark::State& state) {
    const std::vector<Seed> seeds{
        {kDims.index(5, 10, 15), 0, 0}, {kDims.index(10, 50, 15), 0, 1}, {kDims.index(30, 30, 18), 0, 2}};
    for (auto _ : state) benchmark::DoNotOptimize(marchLabelled(kDims, nullptr, seeds, {1.0, 1.0, 1.5}));
}
BENCHMARK(BM_ThreeLabelledFronts)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
