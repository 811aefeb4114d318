// Stage 1's pressure-zone division alone (`pressureZones`, the labelled march of all sources) on
// scenarios/scale_512.toml (512×512×128, six sources) and on the Figure 10 scenario scaled by k,
// with the process's user CPU time and the rise of resident memory during the march (VmHWM after
// `clear_refs` 5). Building the domain is not timed. `BM_ZoneMarchScale512Unequal`: the same
// block with unequal source pressures.
#include <string>

#include <benchmark/benchmark.h>

#include "bench_scale_util.h"
#include "sim/stage1.h"

namespace {

using namespace cavesim;
using namespace cavesim::bench;

void zoneMarch(benchmark::State& state, const Scenario& s) {
    Rng rng(s.seed);
    const Domain domain = buildDomain(s, rng);
    double peak = 0, before = 0, cpu = 0;
    long zoned = 0;
    for (auto _ : state) {
        state.PauseTiming();
        resetPeak();
        before = statusKb("VmRSS:");
        const double c0 = cpuSeconds();
        state.ResumeTiming();
        const Grid3<std::int32_t> zone = pressureZones(domain, s.stage1.permeability);
        state.PauseTiming();
        cpu = cpuSeconds() - c0;
        peak = statusKb("VmHWM:");
        zoned = 0;
        for (std::int32_t z : zone.data) zoned += z >= 0;
        state.ResumeTiming();
    }
    state.counters["user_cpu_s"] = cpu;
    state.counters["rise_MB"] = (peak - before) / 1e3;
    state.counters["voxels"] = double(domain.dims.count());
    state.counters["zoned_voxels"] = double(zoned);
}

void BM_ZoneMarchScale512(benchmark::State& state) {
    zoneMarch(state, parseScenarioFile(std::string(CAVESIM_SOURCE_DIR) + "/scenarios/scale_512.toml"));
}
BENCHMARK(BM_ZoneMarchScale512)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// The same block with unequal pressures (3, 1.5, 1, 1, 2, 1, in the scenario's order): the
// stronger fronts cross the weaker zones, as per-source minima require.
void BM_ZoneMarchScale512Unequal(benchmark::State& state) {
    Scenario s = parseScenarioFile(std::string(CAVESIM_SOURCE_DIR) + "/scenarios/scale_512.toml");
    const double pressure[] = {3.0, 1.5, 1.0, 1.0, 2.0, 1.0};
    for (std::size_t i = 0; i < s.sources.size(); ++i) s.sources[i].pressure = pressure[i % 6];
    zoneMarch(state, s);
}
BENCHMARK(BM_ZoneMarchScale512Unequal)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_ZoneMarchScaledFig10(benchmark::State& state) {
    zoneMarch(state, scaledFig10(int(state.range(0))));
}
BENCHMARK(BM_ZoneMarchScaledFig10)->DenseRange(1, 3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
