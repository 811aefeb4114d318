/// @file stage1.h
/// @brief Stage 1 of Pytel & Mann (JCGT 2015, §3.1, §5): pressure zones and protochannels.
///
///  1. **Pressure zones** (fast marching, src/fastmarch `marchLabelled`): one queue for all
///     sources' fronts; source i's front moves with speed p_i (its `pressure`), with `[stage1]
///     permeability = "porosity"` (the default) times R(x)/R̄ — the local porosity over the
///     domain's mean — so fronts hurry along fractures and bedding planes, crawl through
///     obstacles and never enter rock of porosity 0. Each voxel joins the front that reaches it
///     first as if each marched alone (ties: the lower source); voxels no front reaches keep zone
///     −1. In uniform rock this is the multiplicatively weighted Voronoi division: equal
///     pressures split on the bisector, 2 : 1 on an Apollonius sphere (paper Figure 5;
///     docs/model.md "Zones").
///  2. **Flow network per zone** (src/flownet/flow_network.h): the zone's voxels except sinks
///     (inactive in stage 1) and the voxels within `sinkGap` of a sink (Chebyshev distance: the
///     rock kept between protochannels and sinks; source voxels stay) are nodes; pairs of the 26
///     neighbours, L = 1, √2 or √3 apart, are edges of capacity min(R_a, R_b)^capacityExponent / L
///     and resistance 1/capacity × e^(2·resistanceNoise·(2u − 1)), u a seeded hash of the pair.
///     The super-source feeds the source voxels without limit.
///     **Protosinks** drain to the super-sink: with `protosinks = "boundary"` every voxel of the
///     zone's boundary — voxels with a face neighbour in another zone, and voxels on the grid
///     faces listed in `boundaryFaces` (default all but the top) — with `"clustered"` only the
///     boundary voxels within `clusterRadius` of `clusters` centres drawn from the seed, or of
///     the boundary voxels nearest the `aim` points (then the rest of the boundary is left out of
///     the network, so no channel runs along the zone's edge). Each protosink drains at most its
///     share of `protosinkShare` × the source capacity (in proportion to its porosity): the
///     paper's "idealized small-flow gradient", the same all over the boundary.
///     **Neighbourhood.** A zone with more network voxels than `networkVoxels` gets a network of
///     its `networkVoxels` voxels the zone's front reached first (arrival time of the zone march
///     at most the `networkVoxels`-th smallest, all on ties; source voxels always): an
///     iso-arrival-time ball around the source. Its edge counts as zone boundary (protosinks
///     there, as with a neighbouring zone). The reason is cost: time and memory of the max flow
///     grow with the network (`kStage1BytesPerNetworkVoxel`), docs/model.md "Stage 1".
///  3. **Max flow** (src/flownet/max_flow.h): the maximum flow of least total resistance, by
///     primal–dual phases of Dijkstra + Boost.Graph's Boykov–Kolmogorov max flow; flow cycles
///     are then cancelled. The file comment there says why a plain max flow is not enough.
///  4. **Protochannels** (src/flownet/protochannels.h): from the protosinks that receive flow,
///     strongest first, walk upstream along the flow's direction until a source voxel or
///     the tree is reached or touched; only voxels carrying at least `branchFlow` of the zone's
///     flow are marked. The result is a tree of 1-voxel channels rooted at the source that
///     branches outward. Traced voxels get the kProtochannel flag and porosity
///     max(R, protochannel_porosity) (the paper's display erosion; porosity0 keeps the initial
///     rock and the interim step resets it).
///
/// **Mirror frames.** Steps 2–4 make index-ordered choices where values tie (heap order, the
/// order of augmenting paths, cycle cancelling, tracing, the cluster nearest an aim point, the
/// resistance noise hashed from voxel indices). Each zone therefore solves its problem in a
/// canonical frame: the grid read with x and/or y reversed, whichever of the four readings of
/// the zone (network voxels, sources, boundary, porosity bits, aim points) is smallest. A
/// scenario mirrored in x, y or both reads the same in its frame, so its protochannels are the
/// mirror image voxel for voxel (test `Stage1.MirroredScenariosGiveMirroredProtochannelsAndCaves`).
/// A zone that is itself mirror-symmetric may still get an asymmetric tree.
///
/// Zones are solved in parallel (TBB), each independently, and merged in source order, so the
/// result is the same for any thread count. The random draws (cluster centres, then one seed for
/// the resistance noise) are taken from `rng` before the parallel part, zone by zone in source
/// order.
#pragma once

#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "sim/domain.h"
#include "sim/options.h"

namespace cavesim {

/// Peak heap bytes of one flow network and its solver per network voxel (26-neighbour links:
/// the network's arcs with capacity, resistance, target and reverse, Boost's CSR topology, the
/// flow and the two per-phase arrays of the least-resistance max flow, and the per-node arrays;
/// measured, bench/README.md "Stage 1 at scale"). Used by the memory check before the networks
/// are built and by the pre-flight estimate (sim/preflight.h).
constexpr double kStage1BytesPerNetworkVoxel = 1450;

/// Peak bytes of one zone's network and solver with `networkVoxels` voxels.
double stage1NetworkBytes(double networkVoxels);

/// Size, flow and outcome of one zone's network.
struct ZoneStats {
    int source = 0;               ///< source index (scenario order)
    long voxels = 0;              ///< voxels in the zone
    long graphNodes = 0;          ///< voxel nodes of the network (the zone without its sinks, or its neighbourhood)
    long graphEdges = 0;          ///< undirected voxel–voxel edges with positive capacity
    long graphBytes = 0;          ///< peak heap bytes of network and solver
    double maxFlow = 0;           ///< max-flow value (capacity units: porosity^exponent)
    long protosinks = 0;          ///< protosink voxels
    long protochannelVoxels = 0;  ///< voxels traced
    double seconds = 0;           ///< wall time of build, solve and trace
    double buildSeconds = 0;      ///< of it: building the network
    double solveSeconds = 0;      ///< of it: least-resistance max flow and cycle cancelling
    double traceSeconds = 0;      ///< of it: tracing the protochannels
    long protosinksWithFlow = 0;  ///< protosinks that received flow
    long branches = 0;            ///< branches of the protochannel tree
    long cyclesCancelled = 0;     ///< flow cycles removed before tracing
    int phases = 0;               ///< primal–dual phases of the least-resistance max flow
    double flowResistance = 0;    ///< Σ resistance × |flow| of the solution
};

struct Stage1Result {
    int zones = 0;                   ///< zones that hold at least one voxel
    std::vector<long> zoneVoxels;    ///< voxels per source, scenario order
    long protochannelVoxels = 0;     ///< voxels traced in all zones
    std::vector<ZoneStats> perZone;  ///< one per source, scenario order
    double seconds = 0;              ///< wall time of the whole stage
    double zoneSeconds = 0;          ///< wall time of the zone division
};

/// A stage-1 limit exceeded by the scenario (user input, exit 2): a network (zone or
/// neighbourhood) larger than `Stage1Options::maxGraphVoxels`, or networks that would not fit in
/// memory. The message says what to change; `source` is the index of the offending source (−1 for
/// the memory limit), so the caller can point at the scenario entry and key.
class Stage1LimitError : public InputError {
public:
    Stage1LimitError(const std::string& message, int source) : InputError(message), source(source) {}
    int source;
};

/// Runs stage 1 on a freshly built domain: sets domain.zone (source index, −1 none) and flags
/// traced voxels kProtochannel. Porosity is not changed (the display of protochannels as opened
/// channels, `Stage1Options::protochannelPorosity`, is the outputs' business: `stage1DisplayPorosity`).
/// Deterministic for the rng state and any thread count.
/// @throw Stage1LimitError if a network would have more voxels than `options.maxGraphVoxels` (the
///        zone, or at most `networkVoxels` of it; checked before any network is built) or the
///        networks solved at once would not fit in memory
Stage1Result runStage1(Domain& domain, const Stage1Options& options, Rng& rng, const ProgressFn& progress = {});

/// The zone division alone (step 1): zone label per voxel (source index, −1 none).
Grid3<std::int32_t> pressureZones(const Domain& domain, ZoneSpeed speed);

/// The porosity after stage 1 as the paper displays it: protochannel voxels opened to at least
/// `protochannelPorosity` ("display erosion"), every other voxel as it is.
Grid3<float> stage1DisplayPorosity(const Domain& domain, double protochannelPorosity);

}  // namespace cavesim
