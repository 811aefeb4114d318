// The least-resistance maximum flow as it was before its phases ran on a compacted graph: every
// phase ran Boykov–Kolmogorov over the whole network. Kept verbatim (namespace and name aside) as
// the reference the current solver must reproduce bit for bit (test_max_flow_identity.cpp), except
// that each phase's whole-network Boykov–Kolmogorov is the public `maxFlow` on a copy of the
// network holding the phase's capacities (the same unchanged runner, with the same arithmetic:
// flow = capacity − residual on the lower arc of each pair, mirrored), and that it reports no
// `solverBytes`.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include "flownet/flow_network.h"
#include "flownet/max_flow.h"

namespace cavesim::flownet::reference {

inline MaxFlowResult leastResistanceMaxFlow(const FlowNetwork& net, const LeastResistanceOptions& options = {}) {
    const std::size_t nodes = net.nodeCount();
    const std::size_t arcs = net.arcCount();
    MaxFlowResult out;
    out.flow.assign(arcs, 0.0);
    if (net.sources.empty() || net.protosinks.empty()) return out;
    std::vector<double>& flow = out.flow;

    double maxCap = 0;
    for (ArcId a = net.arcBegin[0]; a < net.arcBegin[net.voxelNodes]; ++a) maxCap = std::max(maxCap, net.capacity[a]);
    if (maxCap <= 0) return out;
    const double flowEps = 1e-12 * maxCap;  // residuals below this are round-off, not capacity
    constexpr double kInf = std::numeric_limits<double>::infinity();

    // Resistance of arc a: the network's, except on the arcs between the protosinks and the
    // super-sink (the sink's own arcs, [sinkBegin, end), and their reverses), whose costs are set
    // below in `sinkCost`, indexed by the sink's arc.
    const ArcId sinkBegin = net.arcBegin[net.sink];
    std::vector<double> sinkCost(arcs - sinkBegin, 0.0);
    const auto resistanceOf = [&](ArcId a) {
        if (a >= sinkBegin) return sinkCost[a - sinkBegin];
        if (net.arcTarget[a] == net.sink) return sinkCost[net.arcReverse[a] - sinkBegin];
        return net.resistance[a];
    };
    // Arc cost w and residual r of pushing along arc a given the current net flow: first cancel
    // flow running the other way (refunding its resistance), then add flow (paying it).
    const auto residualOf = [&](ArcId a, double& w) {
        const double f = flow[a];
        if (f < 0) {
            w = -resistanceOf(a);
            return -f;
        }
        w = resistanceOf(a);
        return net.capacity[a] - f;
    };

    // Dijkstra over residual arcs with reduced costs w + π(u) − π(v) (≥ 0 up to round-off).
    std::vector<double> pi(nodes, 0.0), dist(nodes);
    std::vector<std::uint8_t> settled(nodes);
    using Entry = std::pair<double, NodeId>;
    const auto dijkstra = [&](bool throughSink) {
        std::fill(dist.begin(), dist.end(), kInf);
        std::fill(settled.begin(), settled.end(), 0);
        std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
        dist[net.source] = 0;
        heap.push({0.0, net.source});
        while (!heap.empty()) {
            const auto [d, u] = heap.top();
            heap.pop();
            if (settled[u]) continue;
            settled[u] = 1;
            if (u == net.sink) break;  // early exit: the rest is at least this far
            for (ArcId a = net.arcBegin[u]; a < net.arcBegin[u + 1]; ++a) {
                const NodeId v = net.arcTarget[a];
                if (settled[v] || (!throughSink && v == net.sink)) continue;
                double w;
                if (residualOf(a, w) <= flowEps) continue;
                const double nd = d + std::max(0.0, w + pi[u] - pi[v]);
                if (nd < dist[v]) {
                    dist[v] = nd;
                    heap.push({nd, v});
                }
            }
        }
    };

    // Phase 0: least-resistance distances to every protosink; equalise the sink arcs.
    dijkstra(false);
    double longest = 0, nearest = kInf;
    for (NodeId p : net.protosinks)
        if (dist[p] < kInf) {
            longest = std::max(longest, dist[p]);
            nearest = std::min(nearest, dist[p]);
        }
    if (nearest == kInf) return out;  // no protosink reachable: the maximum flow is 0
    for (NodeId p : net.protosinks) {
        const ArcId a = net.arcBegin[p + 1] - 1;  // p → sink (its last arc)
        const double c = options.equalizeProtosinks && dist[p] < kInf ? longest - dist[p] : 0.0;
        sinkCost[net.arcReverse[a] - sinkBegin] = c;
    }
    const double toSink = options.equalizeProtosinks ? longest : nearest;
    for (std::size_t v = 0; v < nodes; ++v) pi[v] = std::min(dist[v], toSink);
    pi[net.sink] = toSink;
    const double tol = std::max(options.tolerance, 1e-9) * std::max(longest, 1e-300);

    FlowNetwork phaseNet = net;  // the network with each phase's capacities
    std::vector<double>& phaseCap = phaseNet.capacity;
    for (int phase = 1;; ++phase) {
        if (phase > 1) {
            dijkstra(true);
            if (!settled[net.sink]) break;  // no augmenting path: the flow is maximum
            const double dT = dist[net.sink];
            for (std::size_t v = 0; v < nodes; ++v) pi[v] += std::min(dist[v], dT);
        }
        out.phases = phase;
        const bool last = phase >= options.maxPhases;
        for (std::size_t u = 0; u < nodes; ++u)
            for (ArcId a = net.arcBegin[u]; a < net.arcBegin[u + 1]; ++a) {
                double w;
                const double r = residualOf(a, w);
                const bool tight = w + pi[u] - pi[net.arcTarget[a]] <= tol;
                // The last phase takes every residual arc: plain max flow on what is left.
                phaseCap[a] = r > flowEps && (tight || last) ? (last ? net.capacity[a] - flow[a] : r) : 0.0;
            }
        const MaxFlowResult pushed = maxFlow(phaseNet, MaxFlowAlgorithm::BoykovKolmogorov);
        for (ArcId a = 0; a < arcs; ++a) {
            const ArcId b = net.arcReverse[a];
            if (a < b) {
                flow[a] += pushed.flow[a];
                flow[b] = -flow[a];
            }
        }
        out.value += pushed.value;
        if (last) break;
    }
    out.cost = flowCost(net, flow);
    return out;
}

}  // namespace cavesim::flownet::reference
