// Stage 2 on the Figure 10 grid (60×60×20, 240 iterations): the target is under 5 s on a
// 2-core machine. Reports time per voxel-iteration. Stage 2 starts from the stage-1 protochannels
// of the scenario, as in a run (stage 1 itself is outside the timed region).
#include <benchmark/benchmark.h>

#include "sim/scenario_io.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

namespace {

using namespace cavesim;

void BM_Stage2Fig10(benchmark::State& state) {
    Scenario s = defaultScenario();
    s.stage2.iterations = int(state.range(0));
    Rng rng(s.seed);
    Domain base = buildDomain(s, rng);
    runStage1(base, s.stage1, rng);
    for (auto _ : state) {
        state.PauseTiming();
        Domain d = base;
        prepareStage2(d, s.stage2);
        state.ResumeTiming();
        const Stage2Result r = runStage2(d, s.stage2);
        benchmark::DoNotOptimize(r.totalDrained);
    }
    const double voxelIterations = double(base.dims.count()) * double(s.stage2.iterations);
    // Seconds per voxel-iteration (printed with an SI prefix: "250n" is 250 ns).
    state.counters["per_voxel_iteration"] = benchmark::Counter(
        voxelIterations, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Stage2Fig10)->Arg(240)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Fig10Domain(benchmark::State& state) {
    const Scenario s = defaultScenario();
    for (auto _ : state) {
        Rng rng(s.seed);
        benchmark::DoNotOptimize(buildDomain(s, rng).porosity.data.data());
    }
}
BENCHMARK(BM_Fig10Domain)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
