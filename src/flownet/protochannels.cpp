/// @file protochannels.cpp
/// @brief Protochannel tracing: upstream walks along maximal in-flow from the protosinks.
#include "flownet/protochannels.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/check.h"
#include "core/vec3.h"

namespace cavesim::flownet {
namespace {

enum : std::uint8_t { kFree = 0, kMarked = 1, kSourceNode = 2 };

}  // namespace

ProtochannelTree traceProtochannels(const FlowNetwork& net, const MaxFlowResult& result, const TraceOptions& options) {
    CAVESIM_CHECK(result.flow.size() == net.arcCount(), "traceProtochannels: " + std::to_string(result.flow.size()) +
                                                            " flow values for " + std::to_string(net.arcCount()) +
                                                            " arcs");
    CAVESIM_CHECK(options.minSinkFraction >= 0 && options.minSinkFraction <= 1 && options.minThroughFraction >= 0 &&
                      options.minThroughFraction <= 1 && options.minBranchVoxels >= 1,
                  "traceProtochannels: minSinkFraction and minThroughFraction must lie in [0, 1], minBranchVoxels "
                  ">= 1 (got " +
                      std::to_string(options.minSinkFraction) + ", " + std::to_string(options.minThroughFraction) +
                      ", " + std::to_string(options.minBranchVoxels) + ")");
    const std::vector<double>& flow = result.flow;
    const std::size_t n = net.voxelNodes;
    ProtochannelTree tree;

    std::vector<std::uint8_t> state(n, kFree);
    for (NodeId s : net.sources) state[s] = kSourceNode;

    // Upstream neighbour of v: the voxel whose arc into v carries the most flow (ties: lower id).
    const auto mostFlow = [&](NodeId v) -> std::int64_t {
        std::int64_t best = -1;
        double bestFlow = 0;
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) {
            const NodeId u = net.arcTarget[a];
            if (u >= n) continue;  // terminals
            const double in = -flow[a];
            if (in > bestFlow || (in == bestFlow && in > 0 && u < best)) {
                bestFlow = in;
                best = u;
            }
        }
        return best;
    };
    const bool directed = options.followFlowDirection && !net.voxelOfNode.empty() && net.dims.count() > 0;
    const auto position = [&](NodeId v) {
        const Index3 p = net.dims.coord(net.voxelOfNode[v]);
        return Vec3d{double(p.i), double(p.j), double(p.k)};
    };
    // Downstream flow direction through v: Σ |flow| × unit vector of each voxel arc, downstream.
    const auto flowDirection = [&](NodeId v) {
        const Vec3d pv = position(v);
        Vec3d sum{0, 0, 0};
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) {
            const NodeId u = net.arcTarget[a];
            if (u >= n || flow[a] == 0) continue;
            const Vec3d pu = position(u);
            const double len = distance(pv, pu);
            // Outflow v→u points along u − v; inflow u→v (flow[a] < 0) along v − u: both flow[a]·(u − v).
            for (int c = 0; c < 3; ++c) sum[c] += flow[a] * (pu[c] - pv[c]) / len;
        }
        return sum;
    };
    // h / |h| divided component by component (not vec3.h `normalized`, which multiplies by 1 / |h|).
    const auto normalised = [](Vec3d h) {
        const double len = norm(h);
        if (len > 0)
            for (double& c : h) c /= len;
        return h;
    };
    // The walk's state for the directed rule: heading (downstream, unit) and the digital-line point.
    Vec3d heading{0, 0, 0}, point{0, 0, 0};
    const auto startWalk = [&](NodeId v) {
        heading = normalised(flowDirection(v));
        point = position(v);
    };
    const auto upstream = [&](NodeId v) -> std::int64_t {
        if (!directed) return mostFlow(v);
        const Vec3d f = normalised(flowDirection(v));
        for (int c = 0; c < 3; ++c) heading[c] += 0.5 * f[c];
        heading = normalised(heading);
        const double longest = std::max({std::abs(heading[0]), std::abs(heading[1]), std::abs(heading[2])});
        if (!(longest > 0)) return mostFlow(v);
        Vec3d target = point;
        for (int c = 0; c < 3; ++c) target[c] -= heading[c] / longest;
        std::int64_t best = -1;
        double bestD = 0, bestFlow = 0;
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) {
            const NodeId u = net.arcTarget[a];
            if (u >= n) continue;
            const double in = -flow[a];
            if (!(in > 0)) continue;
            const Vec3d pu = position(u);
            const Vec3d off = sub(pu, target);
            const double dd = dot(off, off);
            if (best < 0 || dd < bestD || (dd == bestD && (in > bestFlow || (in == bestFlow && u < best)))) {
                best = u;
                bestD = dd;
                bestFlow = in;
            }
        }
        if (best >= 0) {
            // Keep the point on its line while the walk follows it; start afresh where it could not.
            const Vec3d pu = position(NodeId(best));
            const double off =
                std::max({std::abs(pu[0] - target[0]), std::abs(pu[1] - target[1]), std::abs(pu[2] - target[2])});
            point = off <= 0.5 ? target : pu;
        }
        return best;
    };
    // A source voxel or tree voxel linked to v, other than `from`; sources first, then
    // the one sending v the most flow, then the lower id. −1 if none.
    const auto contact = [&](NodeId v, NodeId from) -> std::int64_t {
        std::int64_t best = -1;
        int bestRank = -1;
        double bestFlow = 0;
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) {
            const NodeId u = net.arcTarget[a];
            if (u >= n || u == from || state[u] == kFree) continue;
            const int rank = state[u] == kSourceNode ? 1 : 0;
            const double in = -flow[a];
            if (rank > bestRank || (rank == bestRank && (in > bestFlow || (in == bestFlow && u < best)))) {
                best = u;
                bestRank = rank;
                bestFlow = in;
            }
        }
        return best;
    };

    // Protosinks by decreasing inflow (the flow on their arc to the super-sink).
    std::vector<std::pair<double, NodeId>> sinks;
    double largest = 0;
    for (NodeId p : net.protosinks) {
        double in = 0;
        for (ArcId a = net.arcBegin[p]; a < net.arcBegin[p + 1]; ++a)
            if (net.arcTarget[a] == net.sink) in += flow[a];
        if (in > 0) {
            sinks.push_back({in, p});
            largest = std::max(largest, in);
        }
    }
    tree.protosinksWithFlow = sinks.size();
    std::sort(sinks.begin(), sinks.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
    });

    const std::vector<double> through = throughFlow(net, result);
    const double minThrough = options.minThroughFraction * result.value;
    std::vector<NodeId> path, parents;
    for (const auto& [in, p] : sinks) {
        if (in < options.minSinkFraction * largest) break;
        if (directed) startWalk(p);
        std::int64_t first = upstream(p);
        NodeId from = p;
        for (std::size_t steps = 0;
             first >= 0 && state[std::size_t(first)] == kFree && through[std::size_t(first)] < minThrough; ++steps) {
            if (steps > n) {  // only with flow cycles: give the walk up
                first = -1;
                break;
            }
            from = NodeId(first);
            first = upstream(NodeId(first));
        }
        if (first < 0 || state[std::size_t(first)] != kFree) continue;
        path.clear();
        parents.clear();
        NodeId v = NodeId(first);
        bool attached = false;
        for (std::size_t steps = 0; steps <= n; ++steps) {
            path.push_back(v);
            const std::int64_t touch = options.joinOnContact ? contact(v, from) : -1;
            if (touch >= 0) {
                parents.push_back(NodeId(touch));
                attached = true;
                break;
            }
            const std::int64_t u = upstream(v);
            if (u < 0) break;  // no upstream flow: abandon
            parents.push_back(NodeId(u));
            if (state[std::size_t(u)] != kFree) {
                attached = true;
                break;
            }
            from = v;
            v = NodeId(u);
        }
        if (!attached) continue;
        if (path.size() < std::size_t(options.minBranchVoxels) && !tree.nodes.empty()) continue;
        for (std::size_t i = 0; i < path.size(); ++i) {
            state[path[i]] = kMarked;
            tree.nodes.push_back(path[i]);
            tree.parent.push_back(parents[i]);
        }
        ++tree.branches;
    }
    return tree;
}

}  // namespace cavesim::flownet
