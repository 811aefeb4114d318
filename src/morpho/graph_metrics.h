/// @file graph_metrics.h
/// @brief Network metrics of the cave's centreline (Collon et al. 2017, Geomorphology 283, the set
/// that karstnet, KarstNSim and Paris et al. report): geometry of the branches (mean length,
/// coefficient of variation, length entropy, tortuosity, orientation entropy) and topology of the
/// reduced graph (mean degree, degree assortativity, mean shortest path, central point dominance).
/// Definitions: Collon et al. 2017 and the conventions below; reference ranges of 34 surveyed caves:
/// `realCaveRanges()` (morpho/reference_ranges.h).
///
/// All lengths are in metres, computed from the node positions of the `Skeleton` (world space);
/// the metrics never look at voxels.
///
/// Conventions where the definitions leave a choice (each follows karstnet, whose code produced the
/// reference ranges, unless said otherwise):
///  - **Branch**: a maximal chain of skeleton edges whose inner nodes have degree 2; its ends have
///    degree ≠ 2. A component that is a pure cycle (every node of degree 2) is one branch, anchored
///    at its lowest-index node. A branch whose two ends are the same node is a *loop branch*.
///    Isolated nodes (degree 0) are in no branch.
///  - **Reduced graph**: the nodes of degree ≠ 2, one edge per branch, kept *simple* so that a loop
///    stays a loop: a loop branch is cut into 3 edges at 2 of its own inner nodes (a ring becomes a
///    triangle), and when several branches join the same two nodes, each of them with ≥ 2 edges is
///    cut in 2 at its middle node (the single-edge one, if any, stays whole). Isolated skeleton
///    nodes are isolated nodes of the reduced graph and count in `k_mean` (karstnet builds its graph
///    from the edge list and never sees them).
///  - `cv_len` uses the *sample* standard deviation (n − 1) (karstnet uses n):
///    undefined for fewer than 2 branches.
///  - `h_len`: bin b = ⌊10·l/l_max⌋ (b = 9 for l = l_max); a value less than 1e-9 of a bin width
///    below a bin edge counts in the upper bin, so round-off does not move lengths that sit on an edge.
///  - `h_or`: azimuth measured clockwise from +y (north) towards +x (east), folded to [0°, 180°);
///    bin b = ⌊azimuth/10°⌋ with the same 1e-9 tolerance (an azimuth of 179.9999999999° is 0°).
///    An edge's weight is its horizontal length, so vertical edges carry none.
///  - `axis_aligned_share`: the share of horizontal edge length whose azimuth lies within 5° of the
///    x or y axis (the same weights as `h_or`; a value within 1e-9° of 5° counts as aligned). Not one
///    of Collon et al.'s metrics: it shows grid bias, a staircase along the voxel axes. Directions
///    spread evenly give 40°/360° = 0.111; surveyed caves (Huttes, Sakany) about 0.10.
///  - `tortuosity`: mean over the non-loop branches whose ends are apart (straight distance
///    > 1e-12 · length); undefined when there is none (e.g. a ring).
///  - `spl`: hop distances in the reduced graph, Σ_c n_c·spl_c / Σ_c n_c over the components with
///    ≥ 2 nodes (spl_c: mean over the ordered pairs of distinct nodes of component c).
///  - `r_k`: Pearson correlation over the 2·E ordered edge ends of the reduced graph; 1 when all
///    the degrees at edge ends are equal; undefined without edges.
///  - `cpd`: Freeman's central point dominance Σ(b_max − b_i)/(n − 1) of the betweenness b_i
///    normalised by 2/((n − 1)(n − 2)) (shortest paths counted once per unordered pair), over all
///    n nodes of the reduced graph (every component): 0 for n = 2, undefined for n < 2. This is the
///    normalisation of Boost's relative_betweenness_centrality + central_point_dominance and of
///    networkx (karstnet); the betweenness itself is computed here by Brandes' algorithm on a
///    compressed adjacency, fused with the BFS of `spl` and parallel over sources (Boost's
///    brandes_betweenness_centrality takes seconds on 5,000 junctions); the tests check it against Boost.
///  - `spl` and `cpd` of a reduced graph of more than kExactPairsNodes nodes are estimates from a
///    fixed sample of BFS sources (see kPairSources; `pair_sources` says how many were used).
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "morpho/reference_ranges.h"
#include "morpho/skeleton_graph.h"

namespace cavesim::morpho {

/// A skeleton with fewer branches than this is too small for network statistics: its metrics are
/// reported, but not compared with the ranges of real caves (`GraphMetrics::too_small`).
inline constexpr long kMinNetworkBranches = 10;

/// The network metrics of Collon et al. 2017 (`report.json` "graph_metrics"). A metric that is undefined
/// for the graph (e.g. `r_k` without edges, `cv_len` of one branch) is empty and serialised as null.
struct GraphMetrics {
    std::optional<double> k_mean;  ///< mean degree of the reduced graph
    std::optional<double> r_k;     ///< degree assortativity of the reduced graph, in [−1, 1]
    std::optional<double> spl;     ///< mean shortest-path length of the reduced graph, hops
    std::optional<double> cpd;     ///< central point dominance of the reduced graph, in [0, 1]
    std::optional<double> h_or;    ///< orientation entropy of the skeleton edges, in [0, 1]
    /// share of horizontal edge length within 5° of the x or y axis, in [0, 1] (grid bias)
    std::optional<double> axis_aligned_share;
    std::optional<double> len_mean_m;  ///< mean branch length, metres
    std::optional<double> cv_len;      ///< sample standard deviation / mean of branch lengths
    std::optional<double> h_len;       ///< length entropy of the branches, in [0, 1]
    std::optional<double> tortuosity;  ///< mean length / straight distance over non-loop branches, ≥ 1

    long branches = 0;       ///< branches of the skeleton (loop branches included)
    bool too_small = true;   ///< branches < kMinNetworkBranches: too small for network statistics
    long loop_branches = 0;  ///< branches whose two ends are the same node
    long loops = 0;          ///< independent cycles of the skeleton: edges − nodes + components
    long components = 0;     ///< connected components of the skeleton (isolated nodes included)
    long reduced_nodes = 0;  ///< nodes of the reduced graph
    long reduced_edges = 0;  ///< edges of the reduced graph
    /// Breadth-first searches behind `spl` and `cpd`: `reduced_nodes` when they are exact, fewer
    /// (about kPairSources) when they are estimated from a sample of sources.
    long pair_sources = 0;
};

/// Up to this many reduced nodes `spl` and `cpd` are exact (one BFS per node, O(n·E)); beyond, they
/// are estimated from about kPairSources evenly spread sources (O(kPairSources·E), near-linear), each
/// standing for n_c / k_c nodes of its component (Brandes & Pich 2007, "Centrality estimation in
/// large networks"). Deterministic: the sample depends on the graph only.
inline constexpr int kExactPairsNodes = 4096;
inline constexpr int kPairSources = 2048;

/// One branch of the skeleton: the node chain from one end to the other.
struct Branch {
    std::vector<int> nodes;  ///< skeleton node indices, front and back are the ends (equal for a loop branch)
    double length_m = 0.0;   ///< sum of the edge lengths, metres
    bool loop() const { return nodes.front() == nodes.back(); }
};

/// The reduced graph: simple, undirected; every node is a skeleton node.
struct ReducedGraph {
    std::vector<int> nodes;                 ///< skeleton index of each reduced node, increasing
    std::vector<std::array<int, 2>> edges;  ///< pairs of reduced-node indices (positions in `nodes`), a < b
};

/// Throws cavesim::InternalError unless every edge joins two distinct nodes that exist, no edge is
/// listed twice (in either orientation) and every position is finite.
void validateSkeleton(const Skeleton& skeleton);

/// The branches of the skeleton, in a deterministic order: first those starting at the nodes of
/// degree ≠ 2 (by node index, then by neighbour index), then the pure cycles (by lowest node index).
/// @throw cavesim::InternalError on an invalid skeleton (see `validateSkeleton`)
std::vector<Branch> findBranches(const Skeleton& skeleton);

/// The reduced graph of the skeleton (conventions in the file comment).
/// @throw cavesim::InternalError on an invalid skeleton
ReducedGraph reduceSkeleton(const Skeleton& skeleton);

/// All network metrics of the skeleton. Cost O(E log E) for the geometry plus O(n·m) for the
/// all-pairs searches on the reduced graph (n nodes, m edges).
/// @throw cavesim::InternalError on an invalid skeleton
GraphMetrics computeGraphMetrics(const Skeleton& skeleton);

/// Share of the horizontal length of the skeleton's edges whose azimuth lies within `toleranceDeg`
/// of the x or y axis (each edge weighted by its horizontal length, as `h_or`); empty when no edge
/// has horizontal length. An even spread of directions gives 4 · 2 · toleranceDeg / 360°.
/// @param toleranceDeg  degrees, in [0, 45]
/// @throw cavesim::InternalError on an invalid skeleton or tolerance
std::optional<double> axisAlignedShare(const Skeleton& skeleton, double toleranceDeg = 5.0);

/// {"k_mean", "r_k", "spl", "cpd", "h_or", "axis_aligned_share", "len_mean_m", "cv_len", "h_len", "tortuosity", the
/// counts, "too_small" (fewer than kMinNetworkBranches branches)}; undefined metrics are null.
nlohmann::json toJson(const GraphMetrics& m);

}  // namespace cavesim::morpho
