/// @file flow_network.h
/// @brief The flow network of one stage-1 pressure zone (Pytel & Mann, JCGT 2015, §3.1): voxels
/// are nodes, neighbour pairs (26 or 6 per voxel) are arcs whose capacity comes from porosity, a super-source
/// feeds the source voxels and a super-sink drains the protosinks.
///
/// Build/solve pair: `buildFlowNetwork` → `FlowNetwork` (plain arrays, no Boost in this header)
/// → `maxFlow` (max_flow.h) → `traceProtochannels` (protochannels.h).
///
/// **Links.** Every voxel is linked to its 26 neighbours (faces, edges, corners; link length L = 1,
/// √2 or √3 voxels), or with `LinkStencil::kFace6` to its 6 face neighbours only. With face links
/// alone every path is a staircase along the grid axes and all staircases between two voxels are
/// equally long, so least-resistance routes and the protochannels traced from them run along the
/// axes; with 26 links a path can head in 26 directions and its resistance is its length.
///
/// **Capacity rule.** Two linked voxels a, b of the network are joined by a pair of arcs a→b and
/// b→a, each of capacity `min(R_a, R_b)^exponent / L` (R = porosity, index-space unit spacing):
/// a link is as open as its tighter end and conducts in inverse proportion to its length (Darcy:
/// flux = conductivity × head drop / length), so water crosses a bedding plane or fracture
/// (porosity 0.3) six times more easily than 0.05 rock at exponent 1, and 36 times at exponent 2.
/// Zero-capacity pairs are left out. The pair is one undirected edge of the paper's graph: net
/// flow a→b equals minus net flow b→a and is bounded by the capacity in either direction.
/// **Resistance** (the cost of a unit of flow, for the least-resistance max flow of max_flow.h)
/// is the inverse of the capacity, `L / min(R_a, R_b)^exponent` — a link's capacity is its
/// conductance, and a path's resistance in uniform rock is its Euclidean length along the links —
/// times `e^(2·resistanceJitter·(2u − 1))` with u a seeded hash of the pair.
///
/// **Terminals.** The super-source has an arc of capacity `terminalCapacity` (larger than the
/// sum of all voxel-arc capacities, so it never binds) to every source voxel. Every protosink has
/// an arc to the super-sink — unlimited too, or with `protosinkShare` its share of that fraction
/// of the source cut — and its arcs toward other voxels have capacity 0 (they exist only as
/// reverses): a protosink is where the water leaves, so no flow passes through it.
///
/// Traced paths are 26-connected and 1 voxel thick (face-connected with `kFace6`), as stage 2's
/// channels are. All arcs of a node are stored contiguously (CSR); each arc knows
/// its reverse, so incoming flow is read from a node's own arcs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/grid.h"

namespace cavesim::flownet {

/// Node ids are 32-bit: a network has at most 2^32 − 3 voxel nodes and 2^32 − 1 arcs.
using NodeId = std::uint32_t;
using ArcId = std::uint32_t;

/// A directed graph in CSR form with reverse arcs: the input of `maxFlow`.
struct FlowNetwork {
    /// Voxel nodes are 0 … voxelNodes−1; `source` = voxelNodes, `sink` = voxelNodes + 1.
    std::size_t voxelNodes = 0;
    NodeId source = 0;  ///< the super-source
    NodeId sink = 0;    ///< the super-sink
    /// Linear voxel index (in the grid the network was built from) of each voxel node, strictly
    /// increasing. Empty for networks made by `flowNetworkFromArcs`.
    std::vector<std::size_t> voxelOfNode;
    /// The grid `voxelOfNode` indexes (zero for networks made by `flowNetworkFromArcs`).
    Dims dims;
    std::vector<ArcId> arcBegin;    ///< arcs of node n: [arcBegin[n], arcBegin[n + 1]); size nodes + 1
    std::vector<NodeId> arcTarget;  ///< head of each arc
    std::vector<double> capacity;   ///< capacity of each arc, ≥ 0 (R^exponent / L between voxels)
    /// Resistance of each arc (cost per unit of flow), ≥ 0, equal on an arc and its reverse:
    /// L / min(R_a, R_b)^exponent between voxels L apart (the inverse of the capacity: a link's
    /// capacity is its conductance), times the jitter; 0 on terminal arcs.
    std::vector<double> resistance;
    std::vector<ArcId> arcReverse;   ///< the arc b→a of arc a→b
    std::vector<NodeId> sources;     ///< voxel nodes fed by the super-source, increasing
    std::vector<NodeId> protosinks;  ///< voxel nodes drained by the super-sink, increasing
    double terminalCapacity = 0;     ///< capacity of the super-source and super-sink arcs

    std::size_t nodeCount() const { return voxelNodes + 2; }
    std::size_t arcCount() const { return arcTarget.size(); }
    /// Undirected voxel–voxel edges (arc pairs between voxel nodes).
    std::size_t voxelEdgeCount() const;
    /// Heap bytes held by the arrays above.
    std::size_t bytes() const;
};

/// Which neighbours are linked.
enum class LinkStencil {
    kFace6,  ///< the 6 face neighbours (length 1)
    kAll26,  ///< faces, edges and corners (lengths 1, √2, √3)
};

struct FlowNetworkOptions {
    LinkStencil links = LinkStencil::kAll26;  ///< which neighbours are linked
    double capacityExponent = 1.0;            ///< arc capacity = min(R_a, R_b)^exponent; (0, 8]
    /// Networks with more voxel nodes are refused (std::length_error) before anything is
    /// allocated; callers check first and name their own limit. [1, 2^32 − 3]
    std::size_t maxNodes = 4000000;
    /// Capacity of the protosinks' arcs to the super-sink, as a fraction of the source cut (the
    /// summed capacity of the arcs leaving the source voxels), split among the protosinks in
    /// proportion to R^exponent. 0 = unlimited (terminalCapacity). [0, 1e6]
    double protosinkShare = 0.0;
    /// Random variation of the link resistances: resistance × e^(2·jitter·(2u − 1)), u uniform
    /// in [0, 1) from a hash of the two voxels and `jitterSeed` (unresolved sub-voxel
    /// heterogeneity). Lattice paths whose direction lies between the link directions tie; a
    /// weak variation leaves the least-resistance routes gathered along the link directions
    /// (the grid axes and diagonals), a log-uniform one spread over a factor e² (jitter 0.5)
    /// lets them run in any direction. [0, 1]
    double resistanceJitter = 0.0;
    std::uint64_t jitterSeed = 0;  ///< seed of the resistance jitter
};

/// Builds the network of a set of voxels.
/// @param porosity    porosity R ∈ [0, 1] per voxel of the whole grid (index space)
/// @param voxels      the network's voxels as linear indices into `porosity`, strictly increasing
/// @param sources     voxels fed by the super-source: a subset of `voxels`, any order
/// @param protosinks  voxels drained by the super-sink: a subset of `voxels`, disjoint from `sources`
/// @throw cavesim::InternalError if a source or protosink is not in `voxels`, if the two overlap,
///        if `voxels` is not strictly increasing or out of the grid, or if an option is out of range
/// @throw std::length_error if `voxels.size()` exceeds `options.maxNodes` or the arc count overflows
FlowNetwork buildFlowNetwork(const Grid3<float>& porosity, const std::vector<std::size_t>& voxels,
                             const std::vector<std::size_t>& sources, const std::vector<std::size_t>& protosinks,
                             const FlowNetworkOptions& options = {});

/// One directed arc of a hand-made network.
struct ArcSpec {
    NodeId from = 0, to = 0;
    double capacity = 0;    ///< ≥ 0
    double resistance = 0;  ///< ≥ 0; an arc and its reverse must agree
};

/// A network from explicit arcs between `nodes` voxel nodes (for tests and other graphs): each
/// arc a→b of capacity c gets a reverse b→a of capacity 0 unless the list also holds b→a, in which
/// case the two are paired (an undirected edge). The super-source feeds `sources`, `protosinks`
/// drain to the super-sink (their own arcs are kept).
/// @throw cavesim::InternalError on a node id ≥ nodes, a negative capacity or resistance, a
///        self-loop, a repeated arc, or an arc and its reverse with different resistances
FlowNetwork flowNetworkFromArcs(std::size_t nodes, const std::vector<ArcSpec>& arcs, const std::vector<NodeId>& sources,
                                const std::vector<NodeId>& protosinks);

/// Node id of a voxel in a network built by `buildFlowNetwork`, or −1 if it is not a node.
std::int64_t nodeOfVoxel(const FlowNetwork& network, std::size_t voxel);

}  // namespace cavesim::flownet
