/// @file stage1.cpp
/// @brief Stage 1 driver: zone division (fastmarch), per-zone flow networks solved in parallel
/// (flownet), protochannels written back into the domain.
#include "sim/stage1.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/memory.h"
#include "core/text.h"
#include "core/timer.h"
#include "fastmarch/fast_marching.h"
#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "flownet/protochannels.h"
#include "flownet/protosinks.h"

namespace cavesim {
namespace {

flownet::GridFaces gridFaces(const std::vector<GridFace>& list) {
    flownet::GridFaces faces{};
    for (const GridFace f : list) faces[std::size_t(f)] = true;
    return faces;
}

/// A mirror frame: the grid read with x and/or y reversed. Each frame is its own inverse.
struct Frame {
    bool flipX = false, flipY = false;
};
constexpr std::array<Frame, 4> kFrames{{{false, false}, {true, false}, {false, true}, {true, true}}};

/// The position of `f` in kFrames.
std::size_t frameIndex(Frame f) {
    return std::size_t(f.flipX) + 2 * std::size_t(f.flipY);
}

/// Voxel `v` of the grid seen in frame `f` (and back: the map is an involution).
std::size_t inFrame(const Dims& d, std::size_t v, Frame f) {
    Index3 p = d.coord(v);
    if (f.flipX) p.i = d.nx - 1 - p.i;
    if (f.flipY) p.j = d.ny - 1 - p.j;
    return d.index(p.i, p.j, p.k);
}

/// `list` mapped into frame `f`, increasing.
std::vector<std::size_t> listInFrame(const Dims& d, const std::vector<std::size_t>& list, Frame f) {
    std::vector<std::size_t> out;
    out.reserve(list.size());
    for (std::size_t v : list) out.push_back(inFrame(d, v, f));
    std::sort(out.begin(), out.end());
    return out;
}

/// Aim points (voxel units) seen in frame `f`.
std::vector<Vec3d> aimInFrame(const Dims& d, const std::vector<Vec3d>& aim, Frame f) {
    std::vector<Vec3d> out = aim;
    for (Vec3d& a : out) {
        if (f.flipX) a[0] = double(d.nx - 1) - a[0];
        if (f.flipY) a[1] = double(d.ny - 1) - a[1];
    }
    return out;
}

/// Voxel roles of one zone's network, the input of its flow problem besides porosity and aim.
enum ZoneRole : std::uint8_t { kOutside = 0, kNetworkVoxel = 1, kSourceVoxel = 2, kCandidateVoxel = 3 };

/// The frame in which a zone's flow problem reads smallest: the voxels in index order of the
/// frame, compared by (role, porosity bits), then the aim points. A zone and its mirror image
/// (x, y or both) read the same in their chosen frames, so every index-ordered choice of the
/// flow network (heap ties, augmenting-path order, cycle cancelling, tracing, cluster centres) is
/// made the same way for both and their protochannels are mirror images voxel for voxel. Ties
/// between frames mean the zone reads the same in both: either gives the same result.
Frame canonicalFrame(const Dims& d, const Grid3<std::uint8_t>& role, const Grid3<float>& porosity,
                     const std::vector<Vec3d>& aim) {
    const auto key = [&](std::size_t v) -> std::uint64_t {
        const std::uint8_t r = role[v];
        if (r == kOutside) return 0;
        std::uint32_t bits;
        std::memcpy(&bits, &porosity[v], sizeof bits);
        return (std::uint64_t(r) << 32) | bits;
    };
    // −1, 0, 1 as frame a reads smaller than, equal to or larger than frame b.
    const auto compare = [&](Frame a, Frame b) {
        for (std::size_t v = 0; v < d.count(); ++v) {
            const std::uint64_t ka = key(inFrame(d, v, a)), kb = key(inFrame(d, v, b));
            if (ka != kb) return ka < kb ? -1 : 1;
        }
        const std::vector<Vec3d> aa = aimInFrame(d, aim, a), ab = aimInFrame(d, aim, b);
        if (aa != ab) return aa < ab ? -1 : 1;
        return 0;
    };
    Frame best = kFrames[0];
    for (std::size_t f = 1; f < kFrames.size(); ++f) {
        if (kFrames[f].flipX && d.nx == 1) continue;
        if (kFrames[f].flipY && d.ny == 1) continue;
        if (compare(kFrames[f], best) < 0) best = kFrames[f];
    }
    return best;
}

/// The grid read in frame `f`.
template <typename T>
Grid3<T> gridInFrame(const Grid3<T>& g, Frame f) {
    Grid3<T> out(g.dims);
    for (std::size_t v = 0; v < g.size(); ++v) out[inFrame(g.dims, v, f)] = g[v];
    return out;
}

/// 1 where a voxel lies within Chebyshev distance `gap` of a sink voxel (sinks included):
/// a box dilation of the sinks, one running count per axis.
Grid3<std::uint8_t> nearSinks(const Domain& dom, int gap) {
    const Dims& d = dom.dims;
    Grid3<std::uint8_t> m(d, 0);
    for (const auto& sink : dom.sinkVoxels)
        for (std::size_t v : sink) m[v] = 1;
    const int extent[3] = {d.nx, d.ny, d.nz};
    const std::size_t stride[3] = {1, std::size_t(d.nx), std::size_t(d.nx) * std::size_t(d.ny)};
    std::vector<std::uint8_t> line;
    for (int axis = 0; axis < 3; ++axis) {
        const int len = extent[axis];
        line.resize(std::size_t(len));
        for (std::size_t start = 0; start < d.count(); ++start) {
            if ((start / stride[axis]) % std::size_t(len) != 0) continue;  // first voxel of a line only
            for (int t = 0; t < len; ++t) line[std::size_t(t)] = m[start + std::size_t(t) * stride[axis]];
            int count = 0;  // marked voxels in the window [t − gap, t + gap]
            for (int t = 0; t < std::min(gap, len); ++t) count += line[std::size_t(t)];
            for (int t = 0; t < len; ++t) {
                if (t + gap < len) count += line[std::size_t(t + gap)];
                if (t - gap - 1 >= 0) count -= line[std::size_t(t - gap - 1)];
                m[start + std::size_t(t) * stride[axis]] = count > 0;
            }
        }
    }
    return m;
}

/// What one zone needs and produces in the parallel part.
struct ZoneWork {
    /// Network voxels: the zone without the sinks and the voxels within `sinkGap` of them (but
    /// with its sources), increasing; in `frame` from step 2 on.
    std::vector<std::size_t> voxels;
    std::vector<std::size_t> sources;     ///< source voxels in the zone, increasing, in `frame`
    std::vector<std::size_t> protosinks;  ///< increasing, in `frame`
    Frame frame;                          ///< the zone's canonical mirror frame
    std::vector<std::size_t> traced;      ///< result: traced voxels, in `frame`
    ZoneStats stats;
};

}  // namespace

namespace {

/// The progress phase of the zone march.
const char* const kZonePhase = "stage 1: pressure zones";

/// The zone march: arrival time of the winning front and its label per voxel.
fastmarch::LabelledArrival zoneMarch(const Domain& domain, ZoneSpeed speed, const ProgressFn& progress = {}) {
    const Dims& d = domain.dims;
    std::vector<fastmarch::Seed> seeds;
    for (std::size_t s = 0; s < domain.sourceVoxels.size(); ++s)
        for (std::size_t v : domain.sourceVoxels[s]) seeds.push_back({v, 0.0, int(s)});
    if (seeds.empty()) {
        fastmarch::LabelledArrival none;
        none.time = Grid3<double>(d, std::numeric_limits<double>::infinity());
        none.label = Grid3<std::int32_t>(d, -1);
        return none;
    }

    // Front speed of source i at x: p_i · k(x). Uniform: k = 1. Porosity: k = R(x) / mean R, i.e.
    // slowness mean R / R(x), impassable where R = 0. Only ratios matter for who arrives first,
    // so the mean merely keeps the numbers near 1.
    Grid3<float> slowness;
    const Grid3<float>* slow = nullptr;
    if (speed == ZoneSpeed::kPorosity) {
        // Summed as integers (each R rounded to 2^-40), so the mean does not depend on the order
        // of the voxels: a mirrored block gets the same bits.
        __int128 sum = 0;
        for (float r : domain.porosity.data) sum += __int128(std::llround(std::ldexp(double(r), 40)));
        const double mean = std::ldexp(double(sum), -40) / double(domain.porosity.size());
        if (mean > 0) {
            slowness = Grid3<float>(d, 1.f);
            for (std::size_t v = 0; v < slowness.size(); ++v) {
                const double r = domain.porosity[v];
                slowness[v] = r > 0 ? float(mean / r) : std::numeric_limits<float>::infinity();
            }
            slow = &slowness;
        }
    }
    return fastmarch::marchLabelled(d, slow, seeds, domain.sourcePressure, progress, kZonePhase);
}

/// The neighbourhood of a zone's source (stage1.h): of the network voxels `voxels` (increasing),
/// those whose arrival time is at most the `limit`-th smallest (all of them on ties), so the
/// zone's sources (time 0) always. Increasing.
std::vector<std::size_t> neighbourhood(const std::vector<std::size_t>& voxels, const Grid3<double>& time,
                                       std::size_t limit) {
    if (voxels.size() <= limit || limit == 0) return voxels;
    std::vector<double> t;
    t.reserve(voxels.size());
    for (std::size_t v : voxels) t.push_back(time[v]);
    std::nth_element(t.begin(), t.begin() + std::ptrdiff_t(limit - 1), t.end());
    const double cut = t[limit - 1];
    std::vector<std::size_t> kept;
    kept.reserve(limit);
    for (std::size_t v : voxels)
        if (time[v] <= cut) kept.push_back(v);
    return kept;
}

}  // namespace

double stage1NetworkBytes(double networkVoxels) {
    return networkVoxels * kStage1BytesPerNetworkVoxel;
}

Grid3<std::int32_t> pressureZones(const Domain& domain, ZoneSpeed speed) {
    return zoneMarch(domain, speed).label;
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
    reportProgress(progress, kZonePhase, 0, long(d.count()));
    fastmarch::LabelledArrival march = zoneMarch(domain, g.permeability, progress);
    domain.zone = std::move(march.label);
    result.zoneSeconds = t0.seconds();
    reportProgress(progress, kZonePhase, long(d.count()), long(d.count()));

    // Sinks and the rock within `sinkGap` of them stay out of the networks: no protochannel comes
    // nearer to a sink than that, and stage 2 starts with every source cut off from the sinks.
    const Grid3<std::uint8_t> nearSink = nearSinks(domain, g.sinkGap);
    std::vector<ZoneWork> work(nSources);
    for (std::size_t v = 0; v < domain.zone.size(); ++v) {
        const std::int32_t z = domain.zone[v];
        if (z < 0) continue;
        ++result.zoneVoxels[std::size_t(z)];
        const bool source = domain.flags[v] & kSource;
        if (!(domain.flags[v] & kSink) && (!nearSink[v] || source)) work[std::size_t(z)].voxels.push_back(v);
    }
    const long networkCap = std::max(1L, g.networkVoxels);
    for (std::size_t z = 0; z < nSources; ++z) {
        if (result.zoneVoxels[z] > 0) ++result.zones;
        const long network = std::min(result.zoneVoxels[z], networkCap);
        if (network > g.maxGraphVoxels) {
            const std::string what = result.zoneVoxels[z] <= networkCap
                                         ? "the pressure zone of source " + std::to_string(z + 1) + " has " +
                                               withThousands(result.zoneVoxels[z]) + " voxels"
                                         : "the flow network of source " + std::to_string(z + 1) + " (its zone's " +
                                               withThousands(networkCap) +
                                               " voxels nearest the source, network_voxels) would have " +
                                               withThousands(network) + " voxels";
            throw Stage1LimitError(what + ", more than the limit of " + withThousands(g.maxGraphVoxels) +
                                       "; its flow network would need about " +
                                       withThousands(long(stage1NetworkBytes(double(network)) / 1e6)) +
                                       " MB. Raise the limit (up to 1e9) if the memory is there, lower "
                                       "network_voxels, or add sources to split the domain into smaller zones",
                                   int(z));
        }
    }
    // A zone larger than `networkVoxels`: its network is the neighbourhood of its source. The
    // zone's voxels left out are labelled nSources + z while the boundaries are found (another
    // zone to `zoneBoundary`, so the neighbourhood's edge drains like the zone's boundary) and
    // get their zone back afterwards.
    std::vector<std::size_t> leftOut;
    for (std::size_t z = 0; z < nSources; ++z) {
        if (long(work[z].voxels.size()) <= networkCap) continue;
        // The zone's own source voxels are seeds of its front (time 0): always within the cut.
        std::vector<std::size_t> kept = neighbourhood(work[z].voxels, march.time, std::size_t(networkCap));
        std::vector<std::size_t> out;
        std::set_difference(work[z].voxels.begin(), work[z].voxels.end(), kept.begin(), kept.end(),
                            std::back_inserter(out));
        for (std::size_t v : out) {
            domain.zone[v] = std::int32_t(nSources + z);
            leftOut.push_back(v);
        }
        work[z].voxels.swap(kept);
    }
    march.time = Grid3<double>();
    // Zones are solved in parallel: the largest networks that can run at once must fit in memory.
    {
        std::vector<long> sizes;
        for (const ZoneWork& w : work) sizes.push_back(long(w.voxels.size()));
        std::sort(sizes.begin(), sizes.end(), std::greater<>());
        const std::size_t atOnce =
            std::min<std::size_t>(sizes.size(), std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
        double need = 0;
        for (std::size_t k = 0; k < atOnce; ++k) need += stage1NetworkBytes(double(sizes[k]));
        const double limit = memoryLimitBytes();
        if (limit > 0 && need > 0.8 * limit)
            throw Stage1LimitError(
                "stage 1 would need about " + withThousands(long(need / 1e6)) + " MB for the flow networks of its " +
                    std::to_string(atOnce) + " largest pressure zone(s) solved at once, more than 80 % of the " +
                    withThousands(long(limit / 1e6)) +
                    " MB this process may use; make the domain smaller, add sources to split it into "
                    "smaller zones, or run with fewer threads (--threads)",
                -1);
    }

    // 2. Sources and protosinks per zone, in the zone's canonical mirror frame (sequential: the
    //    random cluster centres come from rng in source order, whatever the thread count).
    Grid3<std::uint8_t> role(d, kOutside);
    std::array<bool, 4> frameUsed{};
    for (std::size_t z = 0; z < nSources; ++z) {
        ZoneWork& w = work[z];
        w.stats.source = int(z);
        w.stats.voxels = result.zoneVoxels[z];
        for (std::size_t v : domain.sourceVoxels[z])
            if (domain.zone[v] == std::int32_t(z)) w.sources.push_back(v);
        std::sort(w.sources.begin(), w.sources.end());
        w.sources.erase(std::unique(w.sources.begin(), w.sources.end()), w.sources.end());
        // Overlapping source boxes: a voxel of source z may belong to a lower-numbered zone.
        std::vector<std::size_t> candidates;
        for (std::size_t v : flownet::zoneBoundary(domain.zone, w.voxels, int(z), faces))
            if (!(domain.flags[v] & kSource)) candidates.push_back(v);

        for (std::size_t v : w.voxels) role[v] = kNetworkVoxel;
        for (std::size_t v : w.sources) role[v] = kSourceVoxel;
        for (std::size_t v : candidates) role[v] = kCandidateVoxel;
        const std::vector<Vec3d> noAim;
        w.frame = canonicalFrame(d, role, domain.porosity, g.protosinks == ProtosinkMode::kClustered ? g.aim : noAim);
        for (std::size_t v : w.voxels) role[v] = kOutside;
        frameUsed[frameIndex(w.frame)] = true;
        w.voxels = listInFrame(d, w.voxels, w.frame);
        w.sources = listInFrame(d, w.sources, w.frame);
        candidates = listInFrame(d, candidates, w.frame);

        if (g.protosinks == ProtosinkMode::kClustered) {
            const auto centres =
                flownet::chooseClusterCentres(d, candidates, g.clusters, aimInFrame(d, g.aim, w.frame), rng);
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
        w.stats.protosinks = long(w.protosinks.size());
    }
    for (std::size_t v : leftOut) domain.zone[v] = std::int32_t(domain.zone[v] - std::int32_t(nSources));
    leftOut = std::vector<std::size_t>();
    // Porosity as each frame in use reads it.
    std::array<Grid3<float>, 4> framePorosity;
    for (std::size_t f = 1; f < kFrames.size(); ++f)
        if (frameUsed[f]) framePorosity[f] = gridInFrame(domain.porosity, kFrames[f]);
    const auto porosityIn = [&](Frame fr) -> const Grid3<float>& {
        const std::size_t f = frameIndex(fr);
        return f == 0 ? domain.porosity : framePorosity[f];
    };

    // 3. Networks, max flow and tracing, zone by zone in parallel.
    flownet::FlowNetworkOptions netOptions;
    netOptions.capacityExponent = g.capacityExponent;
    netOptions.maxNodes = std::size_t(std::max(1L, g.maxGraphVoxels));
    netOptions.protosinkShare = g.protosinkShare;
    netOptions.resistanceJitter = g.resistanceNoise;
    netOptions.jitterSeed = rng();
    flownet::TraceOptions traceOptions;
    traceOptions.minThroughFraction = g.branchFlow;
    // Zones done of all, from worker threads one at a time; also before every max-flow phase (a safe
    // point: the progress callback may stop the run there).
    std::mutex progressMutex;
    long done = 0;
    const auto networkProgress = [&](long finished) {
        std::lock_guard<std::mutex> lock(progressMutex);
        done += finished;
        reportProgress(progress, "stage 1: flow networks", done, long(nSources));
    };
    networkProgress(0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nSources, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t z = r.begin(); z != r.end(); ++z) {
            const Stopwatch tz;
            ZoneWork& w = work[z];
            if (!w.voxels.empty() && !w.sources.empty()) {
                const flownet::FlowNetwork net =
                    flownet::buildFlowNetwork(porosityIn(w.frame), w.voxels, w.sources, w.protosinks, netOptions);
                w.stats.buildSeconds = tz.seconds();
                flownet::LeastResistanceOptions solve;
                solve.beforePhase = [&] { networkProgress(0); };
                flownet::MaxFlowResult flow = flownet::leastResistanceMaxFlow(net, solve);
                w.stats.cyclesCancelled = long(flownet::cancelFlowCycles(net, flow));
                w.stats.solveSeconds = tz.seconds() - w.stats.buildSeconds;
                const flownet::ProtochannelTree tree = flownet::traceProtochannels(net, flow, traceOptions);
                w.stats.traceSeconds = tz.seconds() - w.stats.buildSeconds - w.stats.solveSeconds;
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
            networkProgress(1);
        }
    });

    // 4. Write back in source order.
    for (std::size_t z = 0; z < nSources; ++z) {
        for (std::size_t v : work[z].traced) domain.flags[inFrame(d, v, work[z].frame)] |= kProtochannel;
        result.protochannelVoxels += long(work[z].traced.size());
        result.perZone[z] = work[z].stats;
    }
    result.seconds = t0.seconds();
    return result;
}

}  // namespace cavesim
