/// @file stage1.cpp
/// @brief Stage 1 driver: zone division (fastmarch), per-zone flow networks solved in parallel
/// (flownet), protochannels written back into the domain.
#include "sim/stage1.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/timer.h"
#include "core/memory.h"
#include "fastmarch/fast_marching.h"
#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "flownet/protochannels.h"
#include "flownet/protosinks.h"

namespace cavesim {
namespace {

/// Peak heap bytes per zone voxel of network and solver (measured: about 430 on 6-neighbour zones).
constexpr double kBytesPerVoxel = 450;

/// What one zone needs and produces in the parallel part.
struct ZoneWork {
    std::vector<std::size_t> voxels;      ///< network voxels: the zone without sinks, increasing
    std::vector<std::size_t> sources;     ///< source voxels in the zone
    std::vector<std::size_t> protosinks;  ///< increasing
    std::vector<std::size_t> traced;      ///< result: traced voxels
    ZoneStats stats;
};

flownet::GridFaces gridFaces(const std::vector<GridFace>& list) {
    flownet::GridFaces faces{};
    for (const GridFace f : list) faces[std::size_t(f)] = true;
    return faces;
}

std::string withThousands(long v) {
    std::string s = std::to_string(v);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

}  // namespace

Grid3<std::int32_t> pressureZones(const Domain& domain, ZoneSpeed speed) {
    const Dims& d = domain.dims;
    std::vector<fastmarch::Seed> seeds;
    for (std::size_t s = 0; s < domain.sourceVoxels.size(); ++s)
        for (std::size_t v : domain.sourceVoxels[s]) seeds.push_back({v, 0.0, int(s)});
    if (seeds.empty()) return Grid3<std::int32_t>(d, -1);

    // Front speed of source i at x: p_i · k(x). Uniform: k = 1. Porosity: k = R(x) / mean R, i.e.
    // slowness mean R / R(x), impassable where R = 0. Only ratios matter for who arrives first,
    // so the mean merely keeps the numbers near 1.
    Grid3<float> slowness;
    const Grid3<float>* slow = nullptr;
    if (speed == ZoneSpeed::kPorosity) {
        double sum = 0;
        for (float r : domain.porosity.data) sum += r;
        const double mean = sum / double(domain.porosity.size());
        if (mean > 0) {
            slowness = Grid3<float>(d, 1.f);
            for (std::size_t v = 0; v < slowness.size(); ++v) {
                const double r = domain.porosity[v];
                slowness[v] = r > 0 ? float(mean / r) : std::numeric_limits<float>::infinity();
            }
            slow = &slowness;
        }
    }
    return fastmarch::marchLabelled(d, slow, seeds, domain.sourcePressure).label;
}

Grid3<float> stage1DisplayPorosity(const Domain& domain, double protochannelPorosity) {
    Grid3<float> shown = domain.porosity;
    const float raised = float(protochannelPorosity);
    for (std::size_t v = 0; v < shown.size(); ++v)
        if (domain.flags[v] & kProtochannel) shown[v] = std::max(shown[v], raised);
    return shown;
}

Stage1Result runStage1(Domain& domain, const Stage1Options& g, Rng& rng, const ProgressFn& progress) {
    const Stopwatch t0;
    const Dims& d = domain.dims;
    const std::size_t nSources = domain.sourceVoxels.size();
    Stage1Result result;
    result.zoneVoxels.assign(nSources, 0);
    result.perZone.resize(nSources);
    const flownet::GridFaces faces = gridFaces(g.boundaryFaces);

    // 1. Zones.
    reportProgress(progress, "stage 1: pressure zones", 0, 1);
    domain.zone = pressureZones(domain, g.permeability);
    result.zoneSeconds = t0.seconds();
    reportProgress(progress, "stage 1: pressure zones", 1, 1);

    std::vector<ZoneWork> work(nSources);
    for (std::size_t v = 0; v < domain.zone.size(); ++v) {
        const std::int32_t z = domain.zone[v];
        if (z < 0) continue;
        ++result.zoneVoxels[std::size_t(z)];
        if (!(domain.flags[v] & kSink)) work[std::size_t(z)].voxels.push_back(v);
    }
    for (std::size_t z = 0; z < nSources; ++z) {
        if (result.zoneVoxels[z] > 0) ++result.zones;
        if (result.zoneVoxels[z] > g.maxGraphVoxels) {
            throw Stage1LimitError("the pressure zone of source " + std::to_string(z + 1) + " has " +
                                       withThousands(result.zoneVoxels[z]) + " voxels, more than the limit of " +
                                       withThousands(g.maxGraphVoxels) + "; its flow network would need about " +
                                       withThousands(long(double(result.zoneVoxels[z]) * kBytesPerVoxel / 1e6)) +
                                       " MB. Raise the limit (up to 1e9) if the memory is there, or add sources to "
                                       "split the domain into smaller zones",
                                   int(z));
        }
    }
    // Zones are solved in parallel: the largest ones that can run at once must fit in memory.
    {
        std::vector<long> sizes(result.zoneVoxels.begin(), result.zoneVoxels.end());
        std::sort(sizes.begin(), sizes.end(), std::greater<>());
        const std::size_t atOnce = std::min<std::size_t>(sizes.size(), std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
        double need = 0;
        for (std::size_t k = 0; k < atOnce; ++k) need += double(sizes[k]) * kBytesPerVoxel;
        const double limit = memoryLimitBytes();
        if (limit > 0 && need > 0.8 * limit)
            throw Stage1LimitError("stage 1 would need about " + withThousands(long(need / 1e6)) +
                             " MB for the flow networks of its " + std::to_string(atOnce) +
                             " largest pressure zone(s) solved at once, more than 80 % of the " +
                             withThousands(long(limit / 1e6)) +
                             " MB this process may use; make the domain smaller, add sources to split it into "
                             "smaller zones, or run with fewer threads (--threads)",
                                   -1);
    }

    // 2. Sources and protosinks per zone (sequential: the random cluster centres come from rng
    //    in source order, whatever the thread count).
    for (std::size_t z = 0; z < nSources; ++z) {
        ZoneWork& w = work[z];
        w.stats.source = int(z);
        w.stats.voxels = result.zoneVoxels[z];
        for (std::size_t v : domain.sourceVoxels[z])
            if (domain.zone[v] == std::int32_t(z)) w.sources.push_back(v);
        // Overlapping source boxes: a voxel of source z may belong to a lower-numbered zone.
        std::vector<std::size_t> candidates;
        for (std::size_t v : flownet::zoneBoundary(domain.zone, w.voxels, int(z), faces))
            if (!(domain.flags[v] & kSource)) candidates.push_back(v);
        if (g.protosinks == ProtosinkMode::kClustered) {
            const auto centres = flownet::chooseClusterCentres(d, candidates, g.clusters, g.aim, rng);
            w.protosinks = flownet::clusterProtosinks(d, candidates, centres, g.clusterRadius);
            // The rest of the boundary is left out of the network: channels stay off the zone's edge.
            std::vector<std::size_t> drop;
            std::set_difference(candidates.begin(), candidates.end(), w.protosinks.begin(), w.protosinks.end(),
                                std::back_inserter(drop));
            std::vector<std::size_t> kept;
            kept.reserve(w.voxels.size() - drop.size());
            std::set_difference(w.voxels.begin(), w.voxels.end(), drop.begin(), drop.end(), std::back_inserter(kept));
            w.voxels.swap(kept);
        } else {
            w.protosinks = std::move(candidates);
        }
        std::sort(w.sources.begin(), w.sources.end());
        w.stats.protosinks = long(w.protosinks.size());
    }

    // 3. Networks, max flow and tracing, zone by zone in parallel.
    flownet::FlowNetworkOptions netOptions;
    netOptions.capacityExponent = g.capacityExponent;
    netOptions.maxNodes = std::size_t(std::max(1L, g.maxGraphVoxels));
    netOptions.protosinkShare = g.protosinkShare;
    netOptions.resistanceJitter = g.resistanceNoise;
    netOptions.jitterSeed = rng();
    flownet::TraceOptions traceOptions;
    traceOptions.minThroughFraction = g.branchFlow;
    std::mutex progressMutex;
    std::atomic<long> done{0};
    reportProgress(progress, "stage 1: flow networks", 0, long(nSources));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nSources, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t z = r.begin(); z != r.end(); ++z) {
            const Stopwatch tz;
            ZoneWork& w = work[z];
            if (!w.voxels.empty() && !w.sources.empty()) {
                const flownet::FlowNetwork net =
                    flownet::buildFlowNetwork(domain.porosity, w.voxels, w.sources, w.protosinks, netOptions);
                flownet::MaxFlowResult flow = flownet::leastResistanceMaxFlow(net);
                w.stats.cyclesCancelled = long(flownet::cancelFlowCycles(net, flow));
                const flownet::ProtochannelTree tree = flownet::traceProtochannels(net, flow, traceOptions);
                w.stats.graphNodes = long(net.voxelNodes);
                w.stats.graphEdges = long(net.voxelEdgeCount());
                w.stats.graphBytes = long(net.bytes() + flow.solverBytes + flow.flow.capacity() * sizeof(double));
                w.stats.maxFlow = flow.value;
                w.stats.phases = flow.phases;
                w.stats.flowResistance = flow.cost;
                w.stats.protosinksWithFlow = long(tree.protosinksWithFlow);
                w.stats.branches = long(tree.branches);
                w.traced.reserve(tree.nodes.size());
                for (flownet::NodeId n : tree.nodes) w.traced.push_back(net.voxelOfNode[n]);
                w.stats.protochannelVoxels = long(w.traced.size());
            }
            w.stats.seconds = tz.seconds();
            std::lock_guard<std::mutex> lock(progressMutex);
            reportProgress(progress, "stage 1: flow networks", ++done, long(nSources));
        }
    });

    // 4. Write back in source order.
    for (std::size_t z = 0; z < nSources; ++z) {
        for (std::size_t v : work[z].traced) domain.flags[v] |= kProtochannel;
        result.protochannelVoxels += long(work[z].traced.size());
        result.perZone[z] = work[z].stats;
    }
    result.seconds = t0.seconds();
    return result;
}

}  // namespace cavesim
