// The least-resistance maximum flow as it was before its phases ran on a compacted graph: every
// phase ran Boykov–Kolmogorov over the whole network. Kept verbatim (namespace and name aside) as
// the reference the current solver must reproduce bit for bit (test_max_flow_identity.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/edmonds_karp_max_flow.hpp>
#include <boost/property_map/function_property_map.hpp>
#include <boost/property_map/property_map.hpp>

#include "flownet/flow_network.h"
#include "flownet/max_flow.h"

namespace cavesim::flownet::reference {

using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                 boost::no_property, NodeId, ArcId>;
using Edge = boost::graph_traits<Graph>::edge_descriptor;

/// Walks the network's arcs in CSR order as (tail, head) pairs: the sorted edge list Boost's CSR
/// constructor reads, without materialising it.
class ArcPairIterator {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = std::pair<NodeId, NodeId>;
    using difference_type = std::ptrdiff_t;
    using pointer = const value_type*;
    using reference = const value_type&;

    ArcPairIterator(const FlowNetwork& net, ArcId arc) : net_(&net), arc_(arc) { settle(); }
    reference operator*() const { return pair_; }
    pointer operator->() const { return &pair_; }
    ArcPairIterator& operator++() {
        ++arc_;
        settle();
        return *this;
    }
    bool operator==(const ArcPairIterator& o) const { return arc_ == o.arc_; }
    bool operator!=(const ArcPairIterator& o) const { return arc_ != o.arc_; }

private:
    void settle() {
        if (arc_ >= net_->arcCount()) return;
        while (net_->arcBegin[tail_ + 1] <= arc_) ++tail_;
        pair_ = {tail_, net_->arcTarget[arc_]};
    }
    const FlowNetwork* net_;
    ArcId arc_;
    NodeId tail_ = 0;
    value_type pair_{0, 0};
};

template <typename T>
std::size_t bytesOf(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

/// The reverse of an arc as a Boost edge descriptor, computed on demand from the network's
/// `arcReverse` (no per-arc array of descriptors).
struct ReverseEdge {
    const FlowNetwork* net;
    Edge operator()(const Edge& e) const {
        const ArcId a = ArcId(e.idx);
        return Edge(net->arcTarget[a], net->arcReverse[a]);
    }
};

/// The network's topology as a Boost CSR graph, with the vertex maps the solvers need. Arc data
/// (capacities, residuals) stay in plain vectors indexed by arc and are passed per solve; the
/// reverse-edge map reads the network's `arcReverse`.
class BoostSolver {
public:
    explicit BoostSolver(const FlowNetwork& net)
        : net_(net),
          g_(boost::edges_are_sorted, ArcPairIterator(net, 0), ArcPairIterator(net, ArcId(net.arcCount())),
             net.nodeCount()),
          predecessor_(net.nodeCount()),
          color_(net.nodeCount()),
          distance_(net.nodeCount(), 0) {}

    /// Max flow with capacities `cap`; `res` receives the residual capacities. Returns the value.
    double run(const std::vector<double>& cap, std::vector<double>& res, MaxFlowAlgorithm algorithm) {
        const auto edgeIndex = get(boost::edge_index, g_);
        const auto vertexIndex = get(boost::vertex_index, g_);
        const auto capMap = boost::make_iterator_property_map(cap.cbegin(), edgeIndex);
        const auto resMap = boost::make_iterator_property_map(res.begin(), edgeIndex);
        const auto revMap = boost::make_function_property_map<Edge, Edge>(ReverseEdge{&net_});
        const auto predMap = boost::make_iterator_property_map(predecessor_.begin(), vertexIndex);
        const auto colorMap = boost::make_iterator_property_map(color_.begin(), vertexIndex);
        if (algorithm == MaxFlowAlgorithm::EdmondsKarp)
            return boost::edmonds_karp_max_flow(g_, net_.source, net_.sink, capMap, resMap, revMap, colorMap, predMap);
        std::fill(distance_.begin(), distance_.end(), 0L);
        const auto distMap = boost::make_iterator_property_map(distance_.begin(), vertexIndex);
        return boost::boykov_kolmogorov_max_flow(g_, capMap, resMap, revMap, predMap, colorMap, distMap, vertexIndex,
                                                 net_.source, net_.sink);
    }

    /// Topology (4 B per arc and node), vertex maps, and Boykov–Kolmogorov's own per-vertex
    /// arrays (time stamp, two flags).
    std::size_t bytes() const {
        return bytesOf(predecessor_) + bytesOf(color_) + bytesOf(distance_) +
               (net_.nodeCount() + 1 + net_.arcCount()) * sizeof(NodeId) + net_.nodeCount() * (sizeof(long) + 1);
    }

private:
    const FlowNetwork& net_;
    Graph g_;
    std::vector<Edge> predecessor_;
    std::vector<boost::default_color_type> color_;
    std::vector<long> distance_;
};

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

    BoostSolver solver(net);
    std::vector<double> phaseCap(arcs), phaseRes(arcs);
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
        const double pushed = solver.run(phaseCap, phaseRes, MaxFlowAlgorithm::BoykovKolmogorov);
        for (ArcId a = 0; a < arcs; ++a) {
            const ArcId b = net.arcReverse[a];
            if (a < b) {
                flow[a] += phaseCap[a] - phaseRes[a];
                flow[b] = -flow[a];
            }
        }
        out.value += pushed;
        if (last) break;
    }
    out.solverBytes = solver.bytes() + bytesOf(sinkCost) + bytesOf(pi) + bytesOf(dist) + bytesOf(settled) +
                      bytesOf(phaseCap) + bytesOf(phaseRes);
    out.cost = flowCost(net, flow);
    return out;
}

}  // namespace cavesim::flownet::reference
