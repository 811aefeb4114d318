/// @file max_flow.h
/// @brief Maximum flow through a `FlowNetwork` with Boost.Graph (Pytel & Mann, JCGT 2015, §3.1:
/// "the Ford–Fulkerson flow network algorithm"), the least-resistance choice among maximum flows,
/// and removal of flow cycles.
///
/// **Which maximum flow.** Inside a voxel zone the maximum flow is far from unique: the value is
/// fixed by the minimum cut (usually right around the source, or the protosinks), but away from
/// the cut countless routings carry it. Plain augmenting-path solvers return whichever routing
/// their search order produces — Boykov–Kolmogorov and Edmonds–Karp route along the fewest hops,
/// giving straight axis-aligned spokes and flow sliding along the zone's edge, shapes of the
/// algorithm rather than of the rock. Stage 1 therefore takes, among all maximum flows, the one
/// of **least resistance** (each arc's resistance = 1/capacity, so water prefers porous rock and
/// fractures): `leastResistanceMaxFlow`, a min-cost max-flow by the primal–dual method. Each
/// phase finds least-resistance distances with Dijkstra's algorithm (reduced costs, Johnson
/// potentials) and then pushes a maximum flow through the arcs that lie on least-resistance paths
/// with `boost::boykov_kolmogorov_max_flow`. Phases repeat until no augmenting path is left, so
/// the result is a maximum flow — an augmenting-path method of the Ford–Fulkerson family. Each
/// phase's Boykov–Kolmogorov runs on a copy of the network holding only the arc pairs with phase
/// capacity (typically a tenth of them) and the terminals' pairs, in network order; a pair
/// without capacity either way is inert in Boost's algorithm, so the flows are bit for bit those
/// of a run over the whole network (max_flow.cpp argues it, a test checks it).
///
/// **Why Boykov–Kolmogorov** for the inner (and the plain) max flow: it keeps two search trees,
/// grown from source and sink, and reuses them after every augmentation instead of searching the
/// whole graph again; on grid graphs (its design target, from vision) it is much faster than
/// Edmonds–Karp (`boost::edmonds_karp_max_flow`, Ford–Fulkerson with breadth-first paths, one
/// BFS over the whole zone per augmenting path) with the same flow value (tests check they agree;
/// bench/bench_flownet.cpp times both). Boost's push–relabel is not offered: its preflow
/// bookkeeping compares floating-point excesses with zero and is not safe with real capacities.
///
/// **Flow.** Results hold the net flow on every arc, antisymmetric (`flow[a] = −flow[reverse[a]]`)
/// and within capacity. `cancelFlowCycles` removes circulations, so walking upstream along
/// positive in-flow always ends at a source (protochannels.h relies on this).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "flownet/flow_network.h"

namespace cavesim::flownet {

enum class MaxFlowAlgorithm {
    BoykovKolmogorov,  ///< search-tree reuse, fastest on voxel grids
    EdmondsKarp,       ///< Ford–Fulkerson with BFS paths: O(V E²), the textbook reference
};

struct MaxFlowResult {
    double value = 0;             ///< total flow from super-source to super-sink
    std::vector<double> flow;     ///< net flow on each arc (index = ArcId)
    double cost = 0;              ///< Σ resistance × |flow| over arc pairs (each pair counted once)
    int phases = 0;               ///< primal–dual phases (leastResistanceMaxFlow), 1 for plain solvers
    std::size_t solverBytes = 0;  ///< peak heap bytes of the solver on top of the network and `flow`
};

/// A maximum flow from `network.source` to `network.sink`, as the chosen Boost.Graph algorithm
/// routes it.
MaxFlowResult maxFlow(const FlowNetwork& network, MaxFlowAlgorithm algorithm = MaxFlowAlgorithm::BoykovKolmogorov);

struct LeastResistanceOptions {
    /// An arc counts as lying on a least-resistance path when its reduced cost is at most this
    /// fraction of the longest least-resistance distance to a protosink. Larger values batch
    /// nearly-equal paths into one phase (fewer phases, flow within this tolerance of the least
    /// resistance); [0, 0.1].
    double tolerance = 1e-3;
    /// Every protosink equally attractive: the sink arc of protosink p costs D − d(p), where d(p)
    /// is its least-resistance distance from the sources and D the largest such distance, so
    /// every protosink is reached at the same total cost and which protosinks receive flow is
    /// not decided by distance (the paper's uniform "small-flow gradient" on the zone boundary).
    /// When every protosink can be fed, the routing is the same either way. Off: sink arcs cost 0.
    bool equalizeProtosinks = true;
    /// After this many phases the remaining augmenting paths are found by plain
    /// Boykov–Kolmogorov (still a maximum flow, no longer least-resistance); ≥ 1.
    int maxPhases = 100;
    /// Called before every phase (the solve's safe points: a large zone takes seconds to minutes).
    /// It may throw (e.g. `Cancelled`) to stop the solve; nothing is left half-done. Empty = none.
    std::function<void()> beforePhase;
};

/// The maximum flow of least total resistance (see the file comment).
/// @throw cavesim::InternalError if the options are out of range or the network is malformed
MaxFlowResult leastResistanceMaxFlow(const FlowNetwork& network, const LeastResistanceOptions& options = {});

/// Removes every directed cycle of positive flow (depth-first search; each cycle found is reduced
/// by its smallest arc flow, which zeroes that arc). Flow value, conservation and capacity bounds
/// are kept; afterwards the arcs with positive flow form a DAG. Worst case O(V·E), about O(E) on
/// voxel zones.
/// @return the number of cycles cancelled
std::size_t cancelFlowCycles(const FlowNetwork& network, MaxFlowResult& result);

/// Net inflow of every node: Σ over its arcs of −flow. Zero up to round-off at every node but the
/// super-source (−value) and the super-sink (+value).
std::vector<double> netInflow(const FlowNetwork& network, const MaxFlowResult& result);

/// Through-flow of every node: Σ of its positive incoming arc flows (terminal arcs included).
std::vector<double> throughFlow(const FlowNetwork& network, const MaxFlowResult& result);

/// Σ resistance × |flow| over arc pairs: the total resistance a flow meets.
double flowCost(const FlowNetwork& network, const std::vector<double>& flow);

}  // namespace cavesim::flownet
