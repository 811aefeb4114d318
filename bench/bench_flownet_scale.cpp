// Stage 1 at scale (issue 13 item 4): the Figure 10 scenario scaled by k (bench/fig10_scaled.py
// writes the same scenario as a file), stage 1 alone — zones, flow networks, max flow, tracing —
// with its wall time, the CPU time of the process, and the rise of resident memory during the
// stage (VmHWM after `clear_refs` 5) per voxel of the largest zone's network.
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_scale_util.h"
#include "sim/stage1.h"

namespace {

using namespace cavesim;
using namespace cavesim::bench;

void BM_Stage1ScaledFig10(benchmark::State& state) {
    const Scenario s = scaledFig10(int(state.range(0)));
    Rng rng0(s.seed);
    const Domain built = buildDomain(s, rng0);
    const Rng after = rng0;
    Stage1Result r;
    double peak = 0, before = 0, cpu = 0;
    for (auto _ : state) {
        state.PauseTiming();
        Domain d = built;
        Rng rng = after;
        resetPeak();
        before = statusKb("VmRSS:");
        const double c0 = cpuSeconds();
        state.ResumeTiming();
        r = runStage1(d, s.stage1, rng);
        state.PauseTiming();
        cpu = cpuSeconds() - c0;
        peak = statusKb("VmHWM:");
        state.ResumeTiming();
    }
    std::vector<long> sizes;
    for (const ZoneStats& z : r.perZone) sizes.push_back(z.graphNodes);
    std::sort(sizes.begin(), sizes.end(), std::greater<>());
    const double twoLargest = double(sizes.size() > 1 ? sizes[0] + sizes[1] : sizes.empty() ? 0 : sizes[0]);
    long nodes = 0, protochannels = 0;
    double build = 0, solve = 0, trace = 0;
    for (const ZoneStats& z : r.perZone) {
        nodes = std::max(nodes, z.graphNodes);
        protochannels += z.protochannelVoxels;
        build += z.buildSeconds;
        solve += z.solveSeconds;
        trace += z.traceSeconds;
    }
    state.counters["user_cpu_s"] = cpu;
    state.counters["zones_s"] = r.zoneSeconds;
    state.counters["build_s"] = build;
    state.counters["maxflow_s"] = solve;
    state.counters["trace_s"] = trace;
    state.counters["largest_network"] = double(nodes);
    state.counters["rise_MB"] = (peak - before) / 1e3;
    // Two zones are solved at once (two threads): the rise per voxel of the two largest networks.
    state.counters["bytes_per_network_voxel"] = twoLargest > 0 ? (peak - before) * 1e3 / twoLargest : 0;
    state.counters["protochannel_voxels"] = double(protochannels);
}
BENCHMARK(BM_Stage1ScaledFig10)->DenseRange(1, 3)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
