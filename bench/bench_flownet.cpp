// Stage 1 on the default scenario (scenarios/fig10.toml: 60 × 60 × 20, 3 sources) — the issue's
// target is under 2 s on 2 cores — and the max-flow solvers on one zone-like network: plain
// Boykov–Kolmogorov, Edmonds–Karp (same value, for comparison) and the least-resistance flow
// stage 1 uses, plus protochannel tracing.
#include <benchmark/benchmark.h>

#include <random>

#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "flownet/protochannels.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage1.h"

namespace {

using namespace cavesim;
using namespace cavesim::flownet;

void BM_Stage1Fig10(benchmark::State& state) {
    const Scenario s = defaultScenario();
    Rng rng0(s.seed);
    const Domain built = buildDomain(s, rng0);
    const Rng after = rng0;
    long protochannels = 0;
    for (auto _ : state) {
        state.PauseTiming();
        Domain d = built;
        Rng rng = after;
        state.ResumeTiming();
        const Stage1Result r = runStage1(d, s.stage1, rng);
        protochannels = r.protochannelVoxels;
        benchmark::DoNotOptimize(r.perZone.data());
    }
    state.counters["protochannel_voxels"] = double(protochannels);
}
BENCHMARK(BM_Stage1Fig10)->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);

/// An n × n × n/2 block of noisy rock, a source in the middle, protosinks on the five lower
/// faces: a stand-in for one pressure zone.
FlowNetwork zoneNetwork(int n) {
    const Dims d{n, n, n / 2};
    std::mt19937 gen(17);
    std::uniform_real_distribution<float> u(0.03f, 0.07f);
    Grid3<float> R(d);
    for (auto& r : R.data) r = u(gen);
    std::vector<std::size_t> voxels(d.count()), rim;
    const std::size_t src = d.index(n / 2, n / 2, n / 4);
    for (std::size_t v = 0; v < d.count(); ++v) {
        voxels[v] = v;
        const Index3 p = d.coord(v);
        if (v != src && (p.i == 0 || p.j == 0 || p.k == 0 || p.i == n - 1 || p.j == n - 1)) rim.push_back(v);
    }
    FlowNetworkOptions o;
    o.protosinkShare = 0.5;
    o.resistanceJitter = 0.5;
    o.jitterSeed = 3;
    return buildFlowNetwork(R, voxels, {src}, rim, o);
}

void BM_BuildNetwork(benchmark::State& state) {
    for (auto _ : state) {
        const FlowNetwork net = zoneNetwork(int(state.range(0)));
        benchmark::DoNotOptimize(net.arcTarget.data());
    }
}
BENCHMARK(BM_BuildNetwork)->Arg(24)->Arg(40)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MaxFlowBoykovKolmogorov(benchmark::State& state) {
    const FlowNetwork net = zoneNetwork(int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(maxFlow(net, MaxFlowAlgorithm::BoykovKolmogorov).value);
}
BENCHMARK(BM_MaxFlowBoykovKolmogorov)->Arg(24)->Arg(40)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MaxFlowEdmondsKarp(benchmark::State& state) {
    const FlowNetwork net = zoneNetwork(int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(maxFlow(net, MaxFlowAlgorithm::EdmondsKarp).value);
}
BENCHMARK(BM_MaxFlowEdmondsKarp)->Arg(24)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MaxFlowLeastResistance(benchmark::State& state) {
    const FlowNetwork net = zoneNetwork(int(state.range(0)));
    int phases = 0;
    for (auto _ : state) {
        const MaxFlowResult r = leastResistanceMaxFlow(net);
        phases = r.phases;
        benchmark::DoNotOptimize(r.value);
    }
    state.counters["phases"] = phases;
}
BENCHMARK(BM_MaxFlowLeastResistance)->Arg(24)->Arg(40)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_TraceProtochannels(benchmark::State& state) {
    const FlowNetwork net = zoneNetwork(int(state.range(0)));
    MaxFlowResult flow = leastResistanceMaxFlow(net);
    cancelFlowCycles(net, flow);
    TraceOptions o;
    o.minThroughFraction = 0.02;
    for (auto _ : state) benchmark::DoNotOptimize(traceProtochannels(net, flow, o).nodes.size());
}
BENCHMARK(BM_TraceProtochannels)->Arg(40)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
