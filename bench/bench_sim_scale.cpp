// Stage 2 at scale (issue 13): the Figure 10 scenario scaled by k (bench/fig10_scaled.py writes the
// same scenario as a file), per active voxel-iteration, peak memory per voxel, thread scaling; the
// transport sweep against a copy measured in the same run; the padding test.
#include <cstring>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "bench_scale_util.h"
#include "core/memory.h"
#include "sim/stage1.h"
#include "sim/stage2.h"
#include "sim/stage2_steps.h"

namespace {

using namespace cavesim;
using namespace cavesim::bench;

void stage2Run(benchmark::State& state, int k, int pad, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const Scenario s = scaledFig10(k, pad);
    Rng rng(s.seed);
    Domain base = buildDomain(s, rng);
    runStage1(base, s.stage1, rng);
    Stage2Result r;
    double peak = 0, before = 0;
    for (auto _ : state) {
        state.PauseTiming();
        Domain d = base;
        prepareStage2(d, s.stage2);
        resetPeak();
        before = statusKb("VmRSS:");
        state.ResumeTiming();
        r = runStage2(d, s.stage2);
        state.PauseTiming();
        peak = statusKb("VmHWM:");
        state.ResumeTiming();
    }
    const double n = double(base.dims.count());
    state.counters["voxels"] = n;
    state.counters["stage2_s"] = r.seconds;
    state.counters["pressure_s"] = r.pressureSeconds;
    state.counters["ns_per_voxel_it"] = r.seconds * 1e9 / (n * s.stage2.iterations);
    state.counters["ns_per_worked_voxel_it"] = (r.transportSeconds + r.erosionSeconds) * 1e9 / r.workedVoxelIterations;
    state.counters["worked_share"] = r.workedVoxelIterations / (n * s.stage2.iterations);
    state.counters["active_tile_share"] = double(r.activeTiles) / double(r.tiles);
    // The block's whole state during stage 2: the domain (25 bytes a voxel, already resident before)
    // plus everything stage 2 added at its peak.
    state.counters["stage2_bytes_per_voxel"] = 25.0 + (peak - before) * 1024.0 / n;
}

void BM_Stage2ScaledFig10(benchmark::State& state) {
    stage2Run(state, int(state.range(0)), 1, int(state.range(1)));
}
BENCHMARK(BM_Stage2ScaledFig10)
    ->Args({1, 2})
    ->Args({2, 2})
    ->Args({3, 2})
    ->Args({4, 2})
    ->Args({2, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

/// The padding test: fig10 (k = 1) in the corner of a 120×120×40 block (8× the volume) against
/// the plain block (BM_Stage2ScaledFig10/1/2).
void BM_Stage2PaddedFig10(benchmark::State& state) {
    stage2Run(state, 1, 2, 2);
}
BENCHMARK(BM_Stage2PaddedFig10)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

/// One core copying 256 MB: the memory bandwidth the transport sweep is compared with.
void BM_CopyBandwidth(benchmark::State& state) {
    const std::size_t bytes = std::size_t(256) << 20;
    std::vector<char> a(bytes, 1), b(bytes, 0);
    for (auto _ : state) {
        std::memcpy(b.data(), a.data(), bytes);
        benchmark::DoNotOptimize(b.data());
    }
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(2 * bytes));  // read + write
}
BENCHMARK(BM_CopyBandwidth)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The transport sweep (offers, acceptance, moving water) of fig10 k = 2 after 300 iterations, one
/// thread. Bytes: per worked voxel the fields it reads and writes once (water 8, porosity 4,
/// pressure 8, flags 1, norm and scale 16, incoming and accept 16, f_c 8, water written 8 = 69).
void BM_TransportSweep(benchmark::State& state) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    Scenario s = scaledFig10(2);
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    runStage1(d, s.stage1, rng);
    prepareStage2(d, s.stage2);
    s.stage2.iterations = 300;
    runStage2(d, s.stage2);
    // Rebuild the state of that moment: water from the domain, tiles from it, the pressure.
    stage2::Stage2State st(d.dims);
    for (std::size_t v = 0; v < st.water.size(); ++v) st.water[v] = d.water[v];
    stage2::activateWet(st);
    const Grid3<double> P = solvePressureFull(d, s.stage2);
    double worked = 0;
    for (auto _ : state) {
        state.PauseTiming();
        stage2::Stage2State copy = st;
        state.ResumeTiming();
        stage2::computeOffers(d, P, s.stage2.weight, copy);
        stage2::computeAcceptance(d, P, s.stage2.weight, copy);
        benchmark::DoNotOptimize(stage2::moveWater(d, P, s.stage2.weight, copy));
        state.PauseTiming();
        worked = 0;
        for (std::size_t sl = 0; sl < copy.activeTiles.size(); ++sl)
            for (std::uint8_t b : copy.workMask[sl]) worked += double(__builtin_popcount(b));
        state.ResumeTiming();
    }
    state.counters["worked_voxels"] = worked;
    state.SetBytesProcessed(std::int64_t(double(state.iterations()) * worked * 69.0));
}
BENCHMARK(BM_TransportSweep)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
