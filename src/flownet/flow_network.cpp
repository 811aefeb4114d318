/// @file flow_network.cpp
/// @brief Building the voxel flow network of a zone (CSR arcs with reverses and terminals).
#include "flownet/flow_network.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/check.h"

namespace cavesim::flownet {
namespace {

constexpr std::size_t kMaxVoxelNodes = std::numeric_limits<NodeId>::max() - 2;
constexpr std::size_t kMaxArcs = std::numeric_limits<ArcId>::max();

template <typename T>
std::size_t vectorBytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

/// SplitMix64 finaliser: a well-mixed 64-bit hash.
std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/// Uniform in [0, 1) from a voxel pair and a seed; the same for either order of the pair.
double unitHash(std::size_t lo, std::size_t hi, std::uint64_t seed) {
    const std::uint64_t h = mix(mix(mix(seed) ^ std::uint64_t(lo)) ^ std::uint64_t(hi));
    return double(h >> 11) * 0x1.0p-53;
}

/// Node roles while building.
enum Role : std::uint8_t { kPlain = 0, kSourceRole = 1, kProtosinkRole = 2 };

/// Maps voxels to node ids by binary search in the sorted voxel list; marks their role.
std::vector<NodeId> nodesOf(const std::vector<std::size_t>& voxels, const std::vector<std::size_t>& list,
                            const char* what) {
    std::vector<NodeId> out;
    out.reserve(list.size());
    for (std::size_t v : list) {
        const auto it = std::lower_bound(voxels.begin(), voxels.end(), v);
        CAVESIM_CHECK(it != voxels.end() && *it == v, std::string("buildFlowNetwork: a ") + what + " voxel (" +
                                                          std::to_string(v) + ") is not one of the network's voxels");
        out.push_back(NodeId(it - voxels.begin()));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

/// Fills `arcReverse` by pairing every arc a→b with the arc b→a (each pair exists exactly once).
void pairReverses(FlowNetwork& net) {
    net.arcReverse.assign(net.arcCount(), 0);
    const std::size_t nodes = net.nodeCount();
    for (std::size_t a = 0; a < nodes; ++a) {
        for (ArcId e = net.arcBegin[a]; e < net.arcBegin[a + 1]; ++e) {
            const NodeId b = net.arcTarget[e];
            if (b < a) continue;  // paired from the lower end
            ArcId r = net.arcBegin[b];
            while (r < net.arcBegin[b + 1] && net.arcTarget[r] != NodeId(a)) ++r;
            CAVESIM_CHECK(r != net.arcBegin[b + 1],
                          "flow network: the arc " + std::to_string(a) + "→" + std::to_string(b) + " has no reverse");
            net.arcReverse[e] = r;
            net.arcReverse[r] = e;
        }
    }
}

}  // namespace

std::size_t FlowNetwork::voxelEdgeCount() const {
    std::size_t n = 0;
    for (std::size_t a = 0; a < voxelNodes; ++a)
        for (ArcId e = arcBegin[a]; e < arcBegin[a + 1]; ++e)
            if (arcTarget[e] < voxelNodes && arcTarget[e] > a) ++n;
    return n;
}

std::size_t FlowNetwork::bytes() const {
    return vectorBytes(voxelOfNode) + vectorBytes(arcBegin) + vectorBytes(arcTarget) + vectorBytes(capacity) +
           vectorBytes(resistance) + vectorBytes(arcReverse) + vectorBytes(sources) + vectorBytes(protosinks);
}

FlowNetwork buildFlowNetwork(const Grid3<float>& porosity, const std::vector<std::size_t>& voxels,
                             const std::vector<std::size_t>& sources, const std::vector<std::size_t>& protosinks,
                             const FlowNetworkOptions& options) {
    CAVESIM_CHECK(
        options.capacityExponent > 0 && options.capacityExponent <= 8,
        "buildFlowNetwork: capacity exponent must lie in (0, 8], got " + std::to_string(options.capacityExponent));
    CAVESIM_CHECK(options.resistanceJitter >= 0 && options.resistanceJitter <= 1 && options.protosinkShare >= 0,
                  "buildFlowNetwork: resistance jitter must lie in [0, 1] (got " +
                      std::to_string(options.resistanceJitter) + "), protosink share >= 0 (got " +
                      std::to_string(options.protosinkShare) + ")");
    const std::size_t n = voxels.size();
    if (n > options.maxNodes || n > kMaxVoxelNodes)
        throw std::length_error("buildFlowNetwork: " + std::to_string(n) + " voxels exceed the limit of " +
                                std::to_string(std::min(options.maxNodes, kMaxVoxelNodes)) + " nodes");
    const Dims& d = porosity.dims;
    for (std::size_t i = 0; i < n; ++i) {
        CAVESIM_CHECK(voxels[i] < porosity.size() && (i == 0 || voxels[i] > voxels[i - 1]),
                      "buildFlowNetwork: voxels must be strictly increasing indices into the grid (entry " +
                          std::to_string(i) + " is " + std::to_string(voxels[i]) + ")");
    }

    FlowNetwork net;
    net.voxelNodes = n;
    net.source = NodeId(n);
    net.sink = NodeId(n + 1);
    net.voxelOfNode = voxels;
    net.dims = d;
    net.sources = nodesOf(voxels, sources, "source");
    net.protosinks = nodesOf(voxels, protosinks, "protosink");
    std::vector<std::uint8_t> role(n, kPlain);
    for (NodeId s : net.sources) role[s] = kSourceRole;
    for (NodeId p : net.protosinks) {
        CAVESIM_CHECK(role[p] != kSourceRole,
                      "buildFlowNetwork: voxel " + std::to_string(voxels[p]) + " is both a source and a protosink");
        role[p] = kProtosinkRole;
    }

    // Per-voxel capacity factor R^exponent: min(R_a, R_b)^e = min(R_a^e, R_b^e) for e > 0.
    std::vector<double> open(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double r = std::clamp(double(porosity[voxels[i]]), 0.0, 1.0);
        open[i] = options.capacityExponent == 1.0 ? r : std::pow(r, options.capacityExponent);
    }

    // Link offsets: the 6 face neighbours, or all 26 (lengths 1, √2, √3).
    std::vector<NeighbourOffset> offsets;
    if (options.links == LinkStencil::kFace6)
        offsets.assign(faceNeighbours().begin(), faceNeighbours().end());
    else
        offsets.assign(allNeighbours().begin(), allNeighbours().end());
    const std::size_t nOff = offsets.size();
    // Node of each voxel in [voxels.front(), voxels.back()] (kNone where the voxel is not a node).
    constexpr NodeId kNone = std::numeric_limits<NodeId>::max();
    const std::size_t lo = n ? voxels.front() : 0;
    std::vector<NodeId> nodeAt(n ? voxels.back() - lo + 1 : 0, kNone);
    for (std::size_t i = 0; i < n; ++i) nodeAt[voxels[i] - lo] = NodeId(i);
    const auto neighbour = [&](const Index3& p, const NeighbourOffset& o) -> NodeId {
        if (!d.contains(p.i + o.di, p.j + o.dj, p.k + o.dk)) return kNone;
        const std::size_t w = d.index(p.i + o.di, p.j + o.dj, p.k + o.dk);
        return (w >= lo && w - lo < nodeAt.size()) ? nodeAt[w - lo] : kNone;
    };
    // An undirected pair is kept when it can carry flow in at least one direction.
    const auto kept = [&](std::size_t a, std::size_t b) {
        return std::min(open[a], open[b]) > 0 && !(role[a] == kProtosinkRole && role[b] == kProtosinkRole);
    };

    // Pass 1: neighbours of every node (kNone where none or dropped) and arc counts.
    std::vector<NodeId> nbr(n * nOff, kNone);
    net.arcBegin.assign(n + 3, 0);
    std::size_t arcs = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Index3 p = d.coord(voxels[i]);
        std::size_t deg = role[i] == kPlain ? 0 : 1;  // terminal arc
        for (std::size_t f = 0; f < nOff; ++f) {
            const NodeId j = neighbour(p, offsets[f]);
            if (j != kNone && kept(i, j)) {
                nbr[i * nOff + f] = j;
                ++deg;
            }
        }
        net.arcBegin[i] = ArcId(arcs);
        arcs += deg;
        if (arcs > kMaxArcs) throw std::length_error("buildFlowNetwork: more than 2^32 − 1 arcs");
    }
    nodeAt.clear();
    nodeAt.shrink_to_fit();
    net.arcBegin[n] = ArcId(arcs);
    arcs += net.sources.size();
    net.arcBegin[n + 1] = ArcId(arcs);
    arcs += net.protosinks.size();
    if (arcs > kMaxArcs) throw std::length_error("buildFlowNetwork: more than 2^32 − 1 arcs");
    net.arcBegin[n + 2] = ArcId(arcs);

    // Pass 2: targets, capacities (conductance R^e / length) and resistances (length / R^e);
    // terminal capacities fixed once the voxel total is known.
    net.arcTarget.resize(arcs);
    net.capacity.assign(arcs, 0.0);
    net.resistance.assign(arcs, 0.0);
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        ArcId e = net.arcBegin[i];
        for (std::size_t f = 0; f < nOff; ++f) {
            const NodeId j = nbr[i * nOff + f];
            if (j == kNone) continue;
            net.arcTarget[e] = j;
            const double length = offsets[f].length;
            const double link = std::min(open[i], open[std::size_t(j)]);
            const double c = role[i] == kProtosinkRole ? 0.0 : link / length;
            net.capacity[e] = c;
            net.resistance[e] = length / link;
            if (options.resistanceJitter > 0) {
                const std::size_t a = std::min(voxels[i], voxels[std::size_t(j)]);
                const std::size_t b = std::max(voxels[i], voxels[std::size_t(j)]);
                net.resistance[e] *=
                    std::exp(2.0 * options.resistanceJitter * (2.0 * unitHash(a, b, options.jitterSeed) - 1.0));
            }
            total += c;
            ++e;
        }
        if (role[i] == kSourceRole) net.arcTarget[e] = net.source;  // reverse of source→i, capacity 0
        if (role[i] == kProtosinkRole) net.arcTarget[e] = net.sink;
    }
    nbr.clear();
    nbr.shrink_to_fit();
    net.terminalCapacity = total + 1.0;
    for (std::size_t s = 0; s < net.sources.size(); ++s) {
        const ArcId e = net.arcBegin[n] + ArcId(s);
        net.arcTarget[e] = net.sources[s];
        net.capacity[e] = net.terminalCapacity;
    }
    double sourceCut = 0, sinkOpen = 0;
    for (NodeId s : net.sources)
        for (ArcId e = net.arcBegin[s]; e < net.arcBegin[s + 1]; ++e)
            if (net.arcTarget[e] < n && role[net.arcTarget[e]] != kSourceRole) sourceCut += net.capacity[e];
    for (NodeId p : net.protosinks) sinkOpen += open[p];
    for (std::size_t s = 0; s < net.protosinks.size(); ++s) {
        const NodeId p = net.protosinks[s];
        net.arcTarget[net.arcBegin[n + 1] + ArcId(s)] = p;  // reverse of p→sink, capacity 0
        double c = net.terminalCapacity;
        if (options.protosinkShare > 0 && sinkOpen > 0)
            c = std::min(c, options.protosinkShare * sourceCut * open[p] / sinkOpen);
        net.capacity[net.arcBegin[p + 1] - 1] = c;
    }
    pairReverses(net);
    return net;
}

FlowNetwork flowNetworkFromArcs(std::size_t nodes, const std::vector<ArcSpec>& arcs, const std::vector<NodeId>& sources,
                                const std::vector<NodeId>& protosinks) {
    CAVESIM_CHECK(nodes <= kMaxVoxelNodes, "flowNetworkFromArcs: too many nodes (" + std::to_string(nodes) + ")");
    std::map<std::pair<NodeId, NodeId>, std::pair<double, double>> cap;  // capacity, resistance
    for (const ArcSpec& a : arcs) {
        const std::string arc = std::to_string(a.from) + "→" + std::to_string(a.to);
        CAVESIM_CHECK(a.from < nodes && a.to < nodes, "flowNetworkFromArcs: arc " + arc + ": node id out of range");
        CAVESIM_CHECK(a.from != a.to, "flowNetworkFromArcs: arc " + arc + " is a self-loop");
        CAVESIM_CHECK(a.capacity >= 0 && std::isfinite(a.capacity),
                      "flowNetworkFromArcs: arc " + arc + ": capacity must be finite and >= 0");
        CAVESIM_CHECK(a.resistance >= 0 && std::isfinite(a.resistance),
                      "flowNetworkFromArcs: arc " + arc + ": resistance must be finite and >= 0");
        CAVESIM_CHECK(cap.emplace(std::make_pair(a.from, a.to), std::make_pair(a.capacity, a.resistance)).second,
                      "flowNetworkFromArcs: repeated arc " + arc);
    }
    // Every arc with its reverse (capacity 0 if not given, same resistance).
    for (const ArcSpec& a : arcs) {
        const auto it = cap.emplace(std::make_pair(a.to, a.from), std::make_pair(0.0, a.resistance)).first;
        CAVESIM_CHECK(it->second.second == a.resistance, "flowNetworkFromArcs: the arc " + std::to_string(a.from) +
                                                             "→" + std::to_string(a.to) +
                                                             " and its reverse have different resistances");
    }

    FlowNetwork net;
    net.voxelNodes = nodes;
    net.source = NodeId(nodes);
    net.sink = NodeId(nodes + 1);
    net.sources = sources;
    net.protosinks = protosinks;
    for (auto* list : {&net.sources, &net.protosinks}) {
        std::sort(list->begin(), list->end());
        list->erase(std::unique(list->begin(), list->end()), list->end());
        for (NodeId v : *list)
            CAVESIM_CHECK(v < nodes, "flowNetworkFromArcs: terminal node id " + std::to_string(v) + " out of range");
    }
    double total = 1.0;
    for (const auto& kv : cap) total += kv.second.first;
    net.terminalCapacity = total;

    struct Out {
        NodeId to;
        double capacity, resistance;
    };
    std::vector<std::vector<Out>> out(nodes + 2);
    for (const auto& [key, cr] : cap) out[key.first].push_back({key.second, cr.first, cr.second});
    for (NodeId s : net.sources) {
        out[net.source].push_back({s, total, 0.0});
        out[s].push_back({net.source, 0.0, 0.0});
    }
    for (NodeId p : net.protosinks) {
        out[p].push_back({net.sink, total, 0.0});
        out[net.sink].push_back({p, 0.0, 0.0});
    }
    net.arcBegin.assign(nodes + 3, 0);
    for (std::size_t v = 0; v < nodes + 2; ++v) {
        net.arcBegin[v + 1] = net.arcBegin[v] + ArcId(out[v].size());
        for (const Out& o : out[v]) {
            net.arcTarget.push_back(o.to);
            net.capacity.push_back(o.capacity);
            net.resistance.push_back(o.resistance);
        }
    }
    pairReverses(net);
    return net;
}

std::int64_t nodeOfVoxel(const FlowNetwork& network, std::size_t voxel) {
    const auto& v = network.voxelOfNode;
    const auto it = std::lower_bound(v.begin(), v.end(), voxel);
    return (it != v.end() && *it == voxel) ? std::int64_t(it - v.begin()) : -1;
}

}  // namespace cavesim::flownet
