/// @file protochannels.h
/// @brief Protochannels from a maximum flow (Pytel & Mann, JCGT 2015, §3.1, Figure 6a): walk
/// upstream from the protosinks along the paths of maximal flow, building a tree rooted at the
/// source that branches outward.
///
/// The paper: "Following the path of maximal flow from a source creates a single protochannel.
/// [...] to create a number of branching protochannels, it is better to instead follow paths of
/// maximal flow from the sinks. Otherwise [...] the protochannels clump into a mass." Our rule:
///
///  1. Protosinks that receive flow are taken in order of decreasing inflow (ties: lower node),
///     so the strongest branches are traced first and weaker ones join them.
///  2. From a protosink the walk steps upstream, against the flow, again and again, until it
///     reaches a source voxel or a voxel already in the tree. Each step goes to a neighbour whose
///     arc into the current voxel carries flow. Which one (`followFlowDirection`, networks built
///     on a grid): the walk keeps a heading, the mean direction of the flow through the voxels it
///     has passed (each voxel's flow vector: Σ over its arcs of |flow| × the arc's unit vector,
///     downstream; the heading is updated as h ← normalise(h + flow direction / 2)), and a point that
///     advances one voxel per step along the heading's longest axis (a digital line, as Bresenham
///     draws one); it steps to the upstream neighbour nearest that point (ties: more flow, then
///     lower node). So a channel runs straight along the flow in any direction, not in the few
///     directions of the links: with the plain rule (the neighbour sending the most flow, ties:
///     lower node), trunks gather along the 26 link directions. The protosink itself is never marked: it is the zone's
///     edge, so (with every boundary voxel a protosink or left out of the network, as stage 1 builds it) channels of
///     neighbouring zones never touch.
///  3. **Gathering** (`minThroughFraction`): voxels through which less than this fraction of the
///     total flow passes are walked over but not marked; a branch begins where the walk first
///     meets enough flow. A flow that reaches every protosink passes through nearly every voxel,
///     so marking all walks would fill the zone; this is the flow-accumulation threshold by which
///     channel networks are extracted from terrain, and it makes the tree's tips end where a
///     branch gathers too little water.
///  4. **Joining** (`joinOnContact`): a branch also ends as soon as the current voxel is linked
///     (a network neighbour: 26 or 6 per voxel, flow_network.h) to a source voxel or a tree voxel
///     other than the one it came from, and attaches
///     there. A maximum flow on a grid fills many parallel paths; without this rule side-by-side
///     paths would each become a channel and fuse into a slab. With it channels are 1 voxel
///     thick and run side by side only where they join (a branch never continues along a channel
///     it touches), and parallel flow is gathered into one trunk.
///  5. Branches that add fewer than `minBranchVoxels` voxels are dropped (stubs on the side of a
///     channel), except the tree's first branch.
///
/// Only voxels that carry flow are marked, and every marked voxel drains into a source along
/// `parent` links between network neighbours. The walk needs a cycle-free flow (`cancelFlowCycles`):
/// positive-flow arcs then form a DAG and every walk ends. A walk that finds no upstream arc (a
/// round-off remnant of flow) is abandoned.
#pragma once

#include <cstddef>
#include <vector>

#include "flownet/flow_network.h"
#include "flownet/max_flow.h"

namespace cavesim::flownet {

struct TraceOptions {
    /// Rule 3: voxels with less through-flow than this fraction of the flow value are not
    /// marked; [0, 1]. 0 marks every walk.
    double minThroughFraction = 0.0;
    /// Protosinks receiving less than this fraction of the largest protosink inflow start no
    /// walk; [0, 1]. 0 walks from every protosink that receives flow.
    double minSinkFraction = 0.0;
    /// Rule 5: a branch shorter than this (in voxels) is dropped, except the tree's first; ≥ 1.
    int minBranchVoxels = 1;
    /// Rule 4; switching it off leaves the plain walk (for comparison and tests).
    bool joinOnContact = true;
    /// Rule 2: walk along the flow's direction (needs a network built on a grid; networks from
    /// `flowNetworkFromArcs` always take the most flow).
    bool followFlowDirection = true;
};

/// The traced tree. `parent[i]` is the node the voxel `nodes[i]` drains from: an earlier marked
/// node or a source voxel node (the root). Parent and child are network neighbours.
struct ProtochannelTree {
    std::vector<NodeId> nodes;           ///< marked voxel nodes, in marking order
    std::vector<NodeId> parent;          ///< same order
    std::size_t branches = 0;            ///< branches kept
    std::size_t protosinksWithFlow = 0;  ///< protosinks that received flow
};

/// Traces the protochannels of a zone.
/// @param network  the zone's network (voxel-voxel arcs are face-adjacent voxels)
/// @param flow     a cycle-free maximum flow on it (`maxFlow` then `cancelFlowCycles`)
/// @throw cavesim::InternalError if `flow` does not match `network` or the options are out of range
ProtochannelTree traceProtochannels(const FlowNetwork& network, const MaxFlowResult& flow,
                                    const TraceOptions& options = {});

}  // namespace cavesim::flownet
