/// @file max_flow.cpp
/// @brief Max flow on a FlowNetwork through Boost.Graph (compressed sparse row topology, flow data
/// in plain vectors indexed by arc), flow-cycle cancellation and node balances.
#include "flownet/max_flow.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cstring>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>
#include <utility>

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/edmonds_karp_max_flow.hpp>
#include <boost/property_map/function_property_map.hpp>
#include <boost/property_map/property_map.hpp>

#include "core/check.h"

namespace cavesim::flownet {
namespace {

using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                 boost::no_property, NodeId, ArcId>;
using Edge = boost::graph_traits<Graph>::edge_descriptor;

/// Walks arcs of the network in CSR order as (tail, head) pairs: the sorted edge list Boost's CSR
/// constructor reads, without materialising it. The arcs are `arcs[k]` for k = 0, 1, …
/// (increasing; all arcs in order when `arcs` is null), their nodes renumbered through
/// `nodeMap` (kept as they are when null).
class ArcPairIterator {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = std::pair<NodeId, NodeId>;
    using difference_type = std::ptrdiff_t;
    using pointer = const value_type*;
    using reference = const value_type&;

    ArcPairIterator(const FlowNetwork& net, std::size_t k, std::size_t count, const ArcId* arcs = nullptr,
                    const NodeId* nodeMap = nullptr)
        : net_(&net), arcs_(arcs), nodeMap_(nodeMap), k_(k), count_(count) {
        settle();
    }
    reference operator*() const { return pair_; }
    pointer operator->() const { return &pair_; }
    ArcPairIterator& operator++() {
        ++k_;
        settle();
        return *this;
    }
    bool operator==(const ArcPairIterator& o) const { return k_ == o.k_; }
    bool operator!=(const ArcPairIterator& o) const { return k_ != o.k_; }

private:
    void settle() {
        if (k_ >= count_) return;
        const ArcId a = arcs_ ? arcs_[k_] : ArcId(k_);
        while (net_->arcBegin[tail_ + 1] <= a) ++tail_;
        const NodeId head = net_->arcTarget[a];
        pair_ = nodeMap_ ? value_type{nodeMap_[tail_], nodeMap_[head]} : value_type{tail_, head};
    }
    const FlowNetwork* net_;
    const ArcId* arcs_;
    const NodeId* nodeMap_;
    std::size_t k_;
    std::size_t count_;
    NodeId tail_ = 0;
    value_type pair_{0, 0};
};

void checkNetwork(const FlowNetwork& net) {
    CAVESIM_CHECK(net.arcBegin.size() == net.nodeCount() + 1 && net.arcBegin.back() == net.arcCount() &&
                      net.capacity.size() == net.arcCount() && net.resistance.size() == net.arcCount() &&
                      net.arcReverse.size() == net.arcCount() && net.source == NodeId(net.voxelNodes) &&
                      net.sink == NodeId(net.voxelNodes + 1),
                  "maxFlow: malformed flow network (" + std::to_string(net.nodeCount()) + " nodes, " +
                      std::to_string(net.arcCount()) + " arcs)");
}

/// Cost `w` and residual (returned) of pushing along an arc with net flow `fa`, capacity `cap`
/// and resistance `res`: first cancel flow running the other way (refunding its resistance),
/// then add flow (paying it).
double residualOf(double fa, double cap, double res, double& w) {
    w = fa < 0 ? -res : res;
    return fa < 0 ? -fa : cap - fa;
}

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
          g_(boost::edges_are_sorted, ArcPairIterator(net, 0, net.arcCount()),
             ArcPairIterator(net, net.arcCount(), net.arcCount()), net.nodeCount()),
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

/// A monotone priority queue of (distance, node) entries for Dijkstra (a radix heap): every push
/// is at least the last pop, distances are non-negative, and a non-negative double's bits order
/// like its value, so the entries sit in 65 buckets by the highest bit in which their key differs
/// from the last popped key. A pop takes bucket 0 (keys equal to the last) or else empties the
/// lowest non-empty bucket into lower ones around its smallest key; each entry moves at most 64
/// times and mostly far fewer, each move an append to a bucket's end — unlike a binary heap of the
/// whole front, whose sift-down walks a path of cache misses at every pop.
/// Equal distances leave in an order other than by node, which changes no distance (Dijkstra's
/// distances do not depend on the order of ties).
struct RadixHeap {
    using Entry = std::pair<std::uint64_t, NodeId>;
    std::array<std::vector<Entry>, 65> bucket;
    std::uint64_t last = 0;
    std::size_t count = 0;

    static std::uint64_t keyOf(double d) {
        const double x = d + 0.0;  // −0 as +0
        std::uint64_t k;
        std::memcpy(&k, &x, sizeof k);
        return k;
    }
    static double valueOf(std::uint64_t k) {
        double d;
        std::memcpy(&d, &k, sizeof d);
        return d;
    }
    std::size_t slot(std::uint64_t k) const { return k == last ? 0 : std::size_t(64 - __builtin_clzll(k ^ last)); }

    bool empty() const { return count == 0; }
    void clear() {
        for (auto& b : bucket) b.clear();
        last = 0;
        count = 0;
    }
    void push(double d, NodeId v) {
        const std::uint64_t k = keyOf(d);
        assert(k >= last && "RadixHeap: a push below the last pop");  // Dijkstra's arcs add ≥ 0
        bucket[slot(k)].push_back({k, v});
        ++count;
    }
    /// Removes and returns an entry of the smallest distance (the queue is not empty).
    std::pair<double, NodeId> pop() {
        if (bucket[0].empty()) {
            std::size_t i = 1;
            while (bucket[i].empty()) ++i;
            std::uint64_t m = bucket[i][0].first;
            for (const Entry& e : bucket[i]) m = std::min(m, e.first);
            last = m;
            for (const Entry& e : bucket[i]) bucket[slot(e.first)].push_back(e);
            bucket[i].clear();
        }
        const Entry e = bucket[0].back();
        bucket[0].pop_back();
        --count;
        return {valueOf(e.first), e.second};
    }
    std::size_t bytes() const {
        std::size_t b = 0;
        for (const auto& v : bucket) b += v.capacity() * sizeof(Entry);
        return b;
    }
};

/// True when no arc is a self-loop, no two arcs of a node share a head (an arc pair is then the
/// only link between its two nodes) and every arc between voxel nodes has its reverse's
/// resistance (so either arc of a pair can tell the other's phase capacity): what
/// `PhaseSolver` needs to drop pairs.
bool canDropPairs(const FlowNetwork& net) {
    constexpr NodeId kNone = std::numeric_limits<NodeId>::max();
    std::vector<NodeId> seenFrom(net.nodeCount(), kNone);
    for (NodeId u = 0; u < net.nodeCount(); ++u)
        for (ArcId a = net.arcBegin[u]; a < net.arcBegin[u + 1]; ++a) {
            const NodeId v = net.arcTarget[a];
            if (v == u || seenFrom[v] == u || net.resistance[a] != net.resistance[net.arcReverse[a]]) return false;
            seenFrom[v] = u;
        }
    return true;
}

/// Boykov–Kolmogorov for one primal–dual phase, run on the part of the network that can matter:
/// the arc pairs with positive phase capacity in either direction, every arc pair of the two
/// terminals, and the nodes they touch. Nodes and arcs keep their relative order (a node's
/// arcs stay in network order), so the solver makes exactly the moves it makes on the whole
/// network, where a pair with zero capacity both ways is inert: Boost's
/// `boykov_kolmogorov_max_flow` only follows, grows along, adopts through or activates across an
/// arc whose residual is positive, and such a pair's residuals stay 0 (flow is only pushed
/// along parent arcs, which had positive residual when chosen). The one place it looks at arcs
/// regardless of residual — when an orphan finds no parent, its neighbours whose parent arc
/// comes from it become orphans — finds the same neighbours in the same order, because in a
/// simple network (no parallel arcs, no self-loops) that parent arc is the pair itself. The
/// terminal pairs are all kept because the first step (`augment_direct_paths`) walks the
/// source's and the sink's arcs and looks up each source neighbour's arc to the sink whatever
/// their residuals. Where `canDropPairs` fails every pair and node is kept.
///
/// Per phase the caller walks the network's nodes and arcs in order, calling `keep` for each
/// kept arc (with its phase capacity) and `endNode` after each node's arcs, then `run`.
class PhaseSolver {
public:
    explicit PhaseSolver(const FlowNetwork& net)
        : net_(net), keepAll_(!canDropPairs(net)), nodeMap_(net.nodeCount()), compactOf_(net.arcCount()) {}

    /// Whether every pair is kept (the caller then keeps every arc).
    bool keepsAll() const { return keepAll_; }

    /// Starts a phase.
    void begin() {
        orig_.clear();
        cap_.clear();
    }

    /// Keeps arc `a` (the next kept arc in network order) with phase capacity `cap`.
    void keep(ArcId a, double cap) {
        compactOf_[a] = ArcId(orig_.size());
        orig_.push_back(a);
        cap_.push_back(cap);
    }

    /// Ends node `u`'s arcs; `kept` tells whether any of them was kept.
    void endNode(NodeId u, bool kept) { nodeMap_[u] = kept || keepAll_ || u >= net_.voxelNodes; }

    /// Max flow with the kept arcs' capacities, added to `flow` kept exactly antisymmetric:
    /// `flow[a] += cap[a] − residual[a]` on the lower arc a of each kept pair,
    /// `flow[reverse] = −flow[a]`. Returns the value.
    double run(std::vector<double>& flow) {
        constexpr NodeId kNone = std::numeric_limits<NodeId>::max();
        const FlowNetwork& net = net_;
        const ArcId* rev = net.arcReverse.data();
        NodeId kept = 0;
        for (NodeId& m : nodeMap_) m = m ? kept++ : kNone;
        const std::size_t keptArcs = orig_.size();
        crev_.resize(keptArcs);
        res_.resize(keptArcs);
        for (std::size_t k = 0; k < keptArcs; ++k) {
            const ArcId b = rev[orig_[k]];
            crev_[k] = compactOf_[b];
            CAVESIM_CHECK(crev_[k] < keptArcs && orig_[crev_[k]] == b,
                          "leastResistanceMaxFlow: a phase kept an arc without its reverse");
        }

        Graph g(boost::edges_are_sorted, ArcPairIterator(net, 0, keptArcs, orig_.data(), nodeMap_.data()),
                ArcPairIterator(net, keptArcs, keptArcs), kept);
        predecessor_.resize(kept);
        color_.resize(kept);
        distance_.assign(kept, 0);
        const auto edgeIndex = get(boost::edge_index, g);
        const auto vertexIndex = get(boost::vertex_index, g);
        const auto capMap = boost::make_iterator_property_map(cap_.cbegin(), edgeIndex);
        const auto resMap = boost::make_iterator_property_map(res_.begin(), edgeIndex);
        const auto revMap = boost::make_function_property_map<Edge, Edge>(CompactReverse{&g, &crev_});
        const auto predMap = boost::make_iterator_property_map(predecessor_.begin(), vertexIndex);
        const auto colorMap = boost::make_iterator_property_map(color_.begin(), vertexIndex);
        const auto distMap = boost::make_iterator_property_map(distance_.begin(), vertexIndex);
        const double value = boost::boykov_kolmogorov_max_flow(g, capMap, resMap, revMap, predMap, colorMap, distMap,
                                                               vertexIndex, nodeMap_[net.source], nodeMap_[net.sink]);
        // Pairs the phase left alone are skipped: adding +0 would not change the lower arc's
        // flow (never −0: it starts at +0 and each phase adds a capacity minus a residual,
        // never −0), and the reverse already holds its negative.
        for (std::size_t k = 0; k < keptArcs; ++k) {
            if (cap_[k] == res_[k]) continue;
            const ArcId a = orig_[k];
            const ArcId b = rev[a];
            if (a < b) {
                flow[a] += cap_[k] - res_[k];
                flow[b] = -flow[a];
            }
        }
        peakBytes_ = std::max(peakBytes_, bytesOf(nodeMap_) + bytesOf(compactOf_) + bytesOf(orig_) + bytesOf(crev_) +
                                              bytesOf(cap_) + bytesOf(res_) + bytesOf(predecessor_) + bytesOf(color_) +
                                              bytesOf(distance_) + (kept + 1 + orig_.size()) * sizeof(NodeId) +
                                              kept * (sizeof(long) + 1));
        return value;
    }

    /// Peak heap bytes over the phases run: node and arc maps, the compacted topology, vertex
    /// maps and Boykov–Kolmogorov's per-vertex arrays (time stamp, two flags).
    std::size_t bytes() const { return peakBytes_; }

    /// Frees the buffers (`bytes` keeps the peak); no phase may run afterwards.
    void release() {
        for (auto* v : {&nodeMap_, &orig_, &crev_}) std::vector<NodeId>().swap(*v);
        std::vector<ArcId>().swap(compactOf_);
        std::vector<double>().swap(cap_);
        std::vector<double>().swap(res_);
        std::vector<Edge>().swap(predecessor_);
        std::vector<boost::default_color_type>().swap(color_);
        std::vector<long>().swap(distance_);
    }

private:
    /// The reverse of a compacted arc as a Boost edge descriptor.
    struct CompactReverse {
        const Graph* g;
        const std::vector<ArcId>* crev;
        Edge operator()(const Edge& e) const { return Edge(boost::target(e, *g), (*crev)[e.idx]); }
    };

    const FlowNetwork& net_;
    bool keepAll_;
    std::vector<NodeId> nodeMap_;   ///< compacted id of each network node (max = dropped)
    std::vector<ArcId> compactOf_;  ///< compacted id of each kept network arc (stale for the others)
    std::vector<ArcId> orig_;       ///< network arc of each compacted arc, increasing
    std::vector<ArcId> crev_;       ///< compacted reverse of each compacted arc
    std::vector<double> cap_;       ///< capacity of each compacted arc
    std::vector<double> res_;       ///< residual capacity of each compacted arc
    std::vector<Edge> predecessor_;
    std::vector<boost::default_color_type> color_;
    std::vector<long> distance_;
    std::size_t peakBytes_ = 0;
};

}  // namespace

MaxFlowResult maxFlow(const FlowNetwork& net, MaxFlowAlgorithm algorithm) {
    checkNetwork(net);
    MaxFlowResult out;
    out.flow.assign(net.arcCount(), 0.0);
    out.phases = 1;
    if (net.sources.empty() || net.protosinks.empty()) return out;  // nothing can flow
    BoostSolver solver(net);
    std::vector<double>& residual = out.flow;  // residual capacities first, flows afterwards
    out.value = solver.run(net.capacity, residual, algorithm);
    // Net flow of each pair, taken from the arc with the lower index and mirrored (exactly antisymmetric).
    for (ArcId a = 0; a < net.arcCount(); ++a) {
        const ArcId b = net.arcReverse[a];
        if (a < b) {
            residual[a] = net.capacity[a] - residual[a];
            residual[b] = -residual[a];
        }
    }
    out.solverBytes = solver.bytes();
    out.cost = flowCost(net, out.flow);
    return out;
}

MaxFlowResult leastResistanceMaxFlow(const FlowNetwork& net, const LeastResistanceOptions& options) {
    checkNetwork(net);
    CAVESIM_CHECK(options.tolerance >= 0 && options.tolerance <= 0.1 && options.maxPhases >= 1,
                  "leastResistanceMaxFlow: tolerance must lie in [0, 0.1] (got " + std::to_string(options.tolerance) +
                      "), maxPhases >= 1 (got " + std::to_string(options.maxPhases) + ")");
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
    // below in `sinkCost`, indexed by the sink's arc. The loops below read the network through
    // plain pointers (the vectors do not change size).
    const ArcId sinkBegin = net.arcBegin[net.sink];
    std::vector<double> sinkCost(arcs - sinkBegin, 0.0);
    const ArcId* const arcBegin = net.arcBegin.data();
    const NodeId* const arcTarget = net.arcTarget.data();
    const ArcId* const arcReverse = net.arcReverse.data();
    const double* const capacity = net.capacity.data();
    const double* const resistance = net.resistance.data();
    const double* const sinkCostOf = sinkCost.data();
    const NodeId sink = net.sink;
    double* const f = flow.data();

    // Dijkstra over residual arcs with reduced costs w + π(u) − π(v) (≥ 0 up to round-off).
    // The queue (storage reused by every phase) is monotone: a node leaves it at its final
    // distance, the minimum over the same sums whatever the order in which nodes of equal
    // distance leave. A popped entry that is no longer its node's distance is stale (the node
    // left earlier); a node that has left is never lowered again (its distance is at most the
    // popped one, and arcs add ≥ 0), so it needs no mark of its own. The sink is reached iff it
    // is settled (`dist` finite). With the early exit at the sink, a node at exactly the sink's
    // distance may or may not have left, but the potentials take min(dist, dT) and every
    // unsettled distance is at least dT, so they are the same either way.
    std::vector<double> pi(nodes, 0.0), dist(nodes);
    RadixHeap heap;
    const auto dijkstra = [&](bool throughSink) {
        std::fill(dist.begin(), dist.end(), kInf);
        double* const d = dist.data();
        const double* const p = pi.data();
        const double* const fl = f;
        const double* const cap = capacity;
        const double* const res = resistance;
        const double* const sc = sinkCostOf;
        const ArcId* const first = arcBegin;
        const NodeId* const head = arcTarget;
        const ArcId* const rev = arcReverse;
        const NodeId to = sink;
        const ArcId scBegin = sinkBegin;
        const double eps = flowEps;
        heap.clear();
        d[net.source] = 0;
        heap.push(0.0, net.source);
        while (!heap.empty()) {
            const auto [du, u] = heap.pop();
            if (du != d[u]) continue;  // stale
            if (u == to) break;        // early exit: the rest is at least this far
            const double pu = p[u];
            for (ArcId a = first[u], end = first[u + 1]; a < end; ++a) {
                const NodeId v = head[a];
                double resV;
                if (v == to) {
                    if (!throughSink) continue;
                    resV = sc[rev[a] - scBegin];
                } else {
                    resV = res[a];
                }
                double w;
                if (residualOf(fl[a], cap[a], resV, w) <= eps) continue;
                const double nd = du + std::max(0.0, w + pu - p[v]);
                if (nd < d[v]) {
                    d[v] = nd;
                    heap.push(nd, v);
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

    // Every pair's net flow as the phases leave it on pairs they do not touch: the lower arc's
    // +0 and its reverse's −0 (the phase solver updates only the pairs it keeps).
    for (ArcId a = 0; a < arcs; ++a)
        if (a < net.arcReverse[a]) flow[net.arcReverse[a]] = -flow[a];
    PhaseSolver solver(net);
    const bool keepAll = solver.keepsAll();
    // 1 where an arc has its reverse's capacity (most voxel arcs): the reverse's capacity is
    // then read from the arc itself rather than gathered.
    std::vector<std::uint8_t> capSymmetric(arcs);
    std::size_t compactBytes = 0;  // peak of the compacted phases
    std::size_t lastBytes = 0;     // the last phase's, when it is the plain max flow
    for (ArcId a = 0; a < arcs; ++a) capSymmetric[a] = capacity[a] == capacity[arcReverse[a]];
    const NodeId voxels = NodeId(net.voxelNodes);
    for (int phase = 1;; ++phase) {
        if (options.beforePhase) options.beforePhase();
        if (phase > 1) {
            dijkstra(true);
            if (dist[net.sink] == kInf) break;  // no augmenting path: the flow is maximum
            const double dT = dist[net.sink];
            for (std::size_t v = 0; v < nodes; ++v) pi[v] += std::min(dist[v], dT);
        }
        out.phases = phase;
        if (phase >= options.maxPhases) {
            // The last phase takes every residual arc (plain max flow on what is left), nearly
            // every pair: it runs on the whole network, the phase solver's buffers freed first.
            compactBytes = solver.bytes() + bytesOf(capSymmetric);
            solver.release();
            std::vector<std::uint8_t>().swap(capSymmetric);
            std::vector<double> phaseCap(arcs), phaseRes(arcs);
            for (ArcId a = 0; a < arcs; ++a) {
                const double r = f[a] < 0 ? -f[a] : capacity[a] - f[a];
                phaseCap[a] = r > flowEps ? capacity[a] - f[a] : 0.0;
            }
            BoostSolver whole(net);
            out.value += whole.run(phaseCap, phaseRes, MaxFlowAlgorithm::BoykovKolmogorov);
            for (ArcId a = 0; a < arcs; ++a) {
                const ArcId b = arcReverse[a];
                if (a < b) {
                    f[a] += phaseCap[a] - phaseRes[a];
                    f[b] = -f[a];
                }
            }
            lastBytes = whole.bytes() + bytesOf(phaseCap) + bytesOf(phaseRes);
            break;
        }
        const double* const p = pi.data();
        // Phase capacity of every arc: its residual where it is tight (on a least-resistance
        // path), 0 elsewhere. An arc is handed to the solver when it or its reverse has
        // capacity; the reverse's is worked out here from this arc (its flow is −f, its
        // resistance the same) with the same arithmetic as at its own turn.
        solver.begin();
        for (NodeId u = 0; u < nodes; ++u) {
            const double pu = p[u];
            bool any = false;
            for (ArcId a = arcBegin[u], end = arcBegin[u + 1]; a < end; ++a) {
                const NodeId v = arcTarget[a];
                const double fa = f[a];
                double c;
                if (u >= voxels || v >= voxels || keepAll) {  // terminal pairs are always kept
                    // Resistance: the sink's own arcs and the arcs into it have the sink costs.
                    const double resA = a >= sinkBegin ? sinkCostOf[a - sinkBegin]
                                        : v == sink    ? sinkCostOf[arcReverse[a] - sinkBegin]
                                                       : resistance[a];
                    double w;
                    const double r = residualOf(fa, capacity[a], resA, w);
                    c = r > flowEps && w + pu - p[v] <= tol ? r : 0.0;
                } else {
                    // Between voxels: this arc costs w, its reverse (flow −fa, same resistance) wb.
                    const double pv = p[v];
                    const double w = fa < 0 ? -resistance[a] : resistance[a];
                    const double wb = fa > 0 ? -resistance[a] : resistance[a];
                    const bool tight = w + pu - pv <= tol;
                    const bool tightB = wb + pv - pu <= tol;
                    if (!(tight || tightB)) continue;  // neither arc can carry phase flow
                    const double r = fa < 0 ? -fa : capacity[a] - fa;
                    c = r > flowEps && tight ? r : 0.0;
                    if (!(c > 0)) {  // kept anyway when the reverse has phase capacity
                        const double fb = -fa;
                        if (!tightB) continue;
                        const double capB = capSymmetric[a] ? capacity[a] : capacity[arcReverse[a]];
                        if (!((fb < 0 ? -fb : capB - fb) > flowEps)) continue;
                    }
                }
                solver.keep(a, c);
                any = true;
            }
            solver.endNode(u, any);
        }
        out.value += solver.run(flow);
    }
    if (compactBytes == 0) compactBytes = solver.bytes() + bytesOf(capSymmetric);
    out.solverBytes =
        std::max(compactBytes, lastBytes) + bytesOf(sinkCost) + bytesOf(pi) + bytesOf(dist) + heap.bytes();
    out.cost = flowCost(net, flow);
    return out;
}

double flowCost(const FlowNetwork& net, const std::vector<double>& flow) {
    double c = 0;
    for (ArcId a = 0; a < net.arcCount(); ++a)
        if (flow[a] > 0) c += net.resistance[a] * flow[a];
    return c;
}

std::size_t cancelFlowCycles(const FlowNetwork& net, MaxFlowResult& result) {
    checkNetwork(net);
    std::vector<double>& flow = result.flow;
    CAVESIM_CHECK(flow.size() == net.arcCount(), "cancelFlowCycles: " + std::to_string(flow.size()) +
                                                     " flow values for " + std::to_string(net.arcCount()) + " arcs");
    const std::size_t nodes = net.nodeCount();
    enum : std::uint8_t { kWhite = 0, kOnStack = 1, kDone = 2 };
    std::vector<std::uint8_t> state(nodes, kWhite);
    std::vector<ArcId> next(net.arcBegin.begin(), net.arcBegin.end() - 1);  // next arc to try per node
    std::vector<ArcId> entry(nodes, 0);  // arc by which a node on the stack was entered
    std::vector<NodeId> stack;
    std::size_t cancelled = 0;

    for (NodeId root = 0; root < nodes; ++root) {
        if (state[root] != kWhite) continue;
        state[root] = kOnStack;
        stack.push_back(root);
        while (!stack.empty()) {
            const NodeId v = stack.back();
            ArcId& a = next[v];
            while (a < net.arcBegin[v + 1] && (flow[a] <= 0 || state[net.arcTarget[a]] == kDone)) ++a;
            if (a == net.arcBegin[v + 1]) {
                state[v] = kDone;
                stack.pop_back();
                continue;
            }
            const NodeId w = net.arcTarget[a];
            if (state[w] == kWhite) {
                state[w] = kOnStack;
                entry[w] = a;
                stack.push_back(w);
                continue;
            }
            // A cycle: w → … → v → w along the stack. Reduce it by its smallest flow.
            std::size_t pos = stack.size() - 1;
            while (stack[pos] != w) --pos;
            double delta = flow[a];
            for (std::size_t s = pos + 1; s < stack.size(); ++s) delta = std::min(delta, flow[entry[stack[s]]]);
            const auto reduce = [&](ArcId e) {
                flow[e] = flow[e] == delta ? 0.0 : flow[e] - delta;
                flow[net.arcReverse[e]] = -flow[e];
            };
            reduce(a);
            for (std::size_t s = pos + 1; s < stack.size(); ++s) reduce(entry[stack[s]]);
            ++cancelled;
            // Resume the search at the first node whose stack arc was zeroed (or at v itself).
            std::size_t cut = stack.size();
            for (std::size_t s = pos + 1; s < stack.size(); ++s)
                if (flow[entry[stack[s]]] <= 0) {
                    cut = s;
                    break;
                }
            for (std::size_t s = cut; s < stack.size(); ++s) state[stack[s]] = kWhite;
            stack.resize(cut);
        }
    }
    return cancelled;
}

std::vector<double> netInflow(const FlowNetwork& net, const MaxFlowResult& result) {
    std::vector<double> in(net.nodeCount(), 0.0);
    for (std::size_t v = 0; v < net.nodeCount(); ++v)
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) in[v] -= result.flow[a];
    return in;
}

std::vector<double> throughFlow(const FlowNetwork& net, const MaxFlowResult& result) {
    std::vector<double> in(net.nodeCount(), 0.0);
    for (std::size_t v = 0; v < net.nodeCount(); ++v)
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a)
            if (result.flow[a] < 0) in[v] -= result.flow[a];
    return in;
}

}  // namespace cavesim::flownet
