/// @file network.cpp
/// @brief Flow paths down the stage-2 pressure, mapped onto the skeleton, and the linkage events
/// read off them.
#include "morpho/network.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <queue>
#include <string>

#include "core/check.h"

namespace cavesim::morpho {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double distance(const SkeletonNode& a, const SkeletonNode& b) {
    return cavesim::distance(a.position, b.position);
}

struct Adjacency {
    std::vector<std::vector<int>> next;
    explicit Adjacency(const Skeleton& s) : next(s.nodes.size()) {
        for (const auto& e : s.edges) {
            next[std::size_t(e[0])].push_back(e[1]);
            next[std::size_t(e[1])].push_back(e[0]);
        }
        for (auto& n : next) std::sort(n.begin(), n.end());
    }
};

/// Connected component of every node (component ids in order of their smallest node).
std::vector<int> components(const Adjacency& adj) {
    std::vector<int> comp(adj.next.size(), -1);
    int c = 0;
    for (std::size_t start = 0; start < comp.size(); ++start) {
        if (comp[start] >= 0) continue;
        std::deque<int> queue{int(start)};
        comp[start] = c;
        while (!queue.empty()) {
            const int v = queue.front();
            queue.pop_front();
            for (int w : adj.next[std::size_t(v)])
                if (comp[std::size_t(w)] < 0) {
                    comp[std::size_t(w)] = c;
                    queue.push_back(w);
                }
        }
        ++c;
    }
    return comp;
}

/// Skeleton nodes a terminal (source or sink voxels) is joined to: a breadth-first search from the
/// terminal's voxels through cave voxels (26-connected), at most `maxSteps` steps; in every
/// skeleton component reached, the node reached first (ties: the lower node index).
std::vector<int> attach(const std::vector<std::size_t>& terminal, const Dims& d, const Grid3<std::uint8_t>& cave,
                        const Grid3<std::int32_t>& nodeAt, const std::vector<int>& comp, int maxSteps) {
    std::vector<int> stepOf(d.count(), -1);
    std::deque<std::size_t> queue;
    for (std::size_t v : terminal) {
        if (v >= d.count() || stepOf[v] >= 0) continue;
        stepOf[v] = 0;
        queue.push_back(v);
    }
    // Best node per component: (steps, node index).
    std::vector<std::pair<int, int>> best;
    auto offer = [&](std::size_t v, int steps) {
        const int n = nodeAt[v];
        if (n < 0) return;
        const int c = comp[std::size_t(n)];
        if (std::size_t(c) >= best.size()) best.resize(std::size_t(c) + 1, {std::numeric_limits<int>::max(), -1});
        best[std::size_t(c)] = std::min(best[std::size_t(c)], {steps, n});
    };
    for (std::size_t v : terminal)
        if (v < d.count()) offer(v, 0);
    while (!queue.empty()) {
        const std::size_t v = queue.front();
        queue.pop_front();
        const int steps = stepOf[v];
        if (steps >= maxSteps) continue;
        const Index3 p = d.coord(v);
        for (const auto& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            if (stepOf[w] >= 0 || !cave[w]) continue;
            stepOf[w] = steps + 1;
            offer(w, steps + 1);
            queue.push_back(w);
        }
    }
    std::vector<int> out;
    for (const auto& [steps, n] : best)
        if (n >= 0) out.push_back(n);
    std::sort(out.begin(), out.end());
    return out;
}

/// Shortest path (by length) from any of `from` to any node with target[n] >= 0, moving only to
/// neighbours whose pressure is not higher (`downhillOnly`) or freely. Returns the nodes, source
/// end first; empty when no target is reachable. Ties are broken by node index (deterministic).
std::vector<int> shortestPath(const Skeleton& s, const Adjacency& adj, const std::vector<double>& pressure,
                              const std::vector<int>& from, const std::vector<int>& target, bool downhillOnly) {
    const std::size_t n = s.nodes.size();
    std::vector<double> dist(n, kInf);
    std::vector<int> prev(n, -1);
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (int f : from) {
        dist[std::size_t(f)] = 0;
        heap.push({0.0, f});
    }
    while (!heap.empty()) {
        const auto [dv, v] = heap.top();
        heap.pop();
        if (dv != dist[std::size_t(v)]) continue;
        if (target[std::size_t(v)] >= 0) {
            std::vector<int> path;
            for (int x = v; x >= 0; x = prev[std::size_t(x)]) path.push_back(x);
            std::reverse(path.begin(), path.end());
            return path;
        }
        for (int w : adj.next[std::size_t(v)]) {
            if (downhillOnly && pressure[std::size_t(w)] > pressure[std::size_t(v)]) continue;
            const double dw = dv + distance(s.nodes[std::size_t(v)], s.nodes[std::size_t(w)]);
            if (dw < dist[std::size_t(w)] || (dw == dist[std::size_t(w)] && v < prev[std::size_t(w)])) {
                dist[std::size_t(w)] = dw;
                prev[std::size_t(w)] = v;
                heap.push({dw, w});
            }
        }
    }
    return {};
}

/// Nearest skeleton node of every cave voxel, through cave voxels (26-connected steps): a
/// breadth-first search from all node voxels at once; at equal steps the lower node index wins.
/// -1 for voxels no node reaches.
std::vector<int> nearestNodes(const Skeleton& s, const Dims& d, const Grid3<std::uint8_t>& cave) {
    std::vector<int> label(d.count(), -1);
    std::vector<int> stepOf(d.count(), -1);
    std::deque<std::size_t> queue;
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        const std::size_t v = s.nodes[n].voxel;
        if (label[v] >= 0) continue;  // two nodes on one voxel: the lower index
        label[v] = int(n);
        stepOf[v] = 0;
        queue.push_back(v);
    }
    // FIFO order: every voxel of step t is labelled (its minimum over the voxels of step t − 1)
    // before any of them spreads to step t + 1.
    while (!queue.empty()) {
        const std::size_t v = queue.front();
        queue.pop_front();
        const Index3 p = d.coord(v);
        for (const auto& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            if (!cave[w]) continue;
            if (stepOf[w] < 0) {
                stepOf[w] = stepOf[v] + 1;
                label[w] = label[v];
                queue.push_back(w);
            } else if (stepOf[w] == stepOf[v] + 1 && label[v] < label[w]) {
                label[w] = label[v];
            }
        }
    }
    return label;
}

/// The skeleton path along a voxel path: each voxel's nearest node, repeats dropped, two nodes
/// that are not neighbours joined by the shortest skeleton path between them, and any node met
/// twice cut back to its first visit (the path is simple). Empty when no voxel has a node or two
/// consecutive nodes are not connected.
std::vector<int> nodesAlong(const Skeleton& s, const Adjacency& adj, const std::vector<int>& nearest,
                            const std::vector<std::size_t>& voxels) {
    std::vector<int> walk;
    std::vector<int> single(s.nodes.size(), -1);
    const std::vector<double> flat(s.nodes.size(), 0.0);
    for (std::size_t v : voxels) {
        const int n = nearest[v];
        if (n < 0 || (!walk.empty() && walk.back() == n)) continue;
        if (!walk.empty()) {
            const auto& next = adj.next[std::size_t(walk.back())];
            if (!std::binary_search(next.begin(), next.end(), n)) {
                single[std::size_t(n)] = 0;
                const std::vector<int> gap = shortestPath(s, adj, flat, {walk.back()}, single, false);
                single[std::size_t(n)] = -1;
                if (gap.empty()) return {};
                walk.insert(walk.end(), gap.begin() + 1, gap.end() - 1);
            }
        }
        walk.push_back(n);
    }
    std::vector<int> path;
    std::vector<int> at(s.nodes.size(), -1);  // position of a node on `path`
    for (int n : walk) {
        if (at[std::size_t(n)] >= 0) {
            const std::size_t keep = std::size_t(at[std::size_t(n)]) + 1;
            for (std::size_t t = keep; t < path.size(); ++t) at[std::size_t(path[t])] = -1;
            path.resize(keep);
            continue;
        }
        at[std::size_t(n)] = int(path.size());
        path.push_back(n);
    }
    return path;
}

/// Troughs of the phreatic loops along an elevation profile: every descent followed by a rise of
/// at least `rise` (index units). Returns the positions (in `z`) of the loop bottoms.
std::vector<std::size_t> loopTroughs(const std::vector<double>& z, double rise) {
    std::vector<std::size_t> out;
    if (z.empty()) return out;
    bool descending = false;
    double peak = z[0], trough = z[0];
    std::size_t troughAt = 0;
    for (std::size_t t = 1; t < z.size(); ++t) {
        if (!descending) {
            if (z[t] >= peak) {
                peak = z[t];
            } else {
                descending = true;
                trough = z[t];
                troughAt = t;
            }
        } else if (z[t] < trough) {
            trough = z[t];
            troughAt = t;
        } else if (z[t] >= trough + rise) {
            out.push_back(troughAt);
            descending = false;
            peak = z[t];
        }
    }
    return out;
}

}  // namespace

Descent descendPressure(const Grid3<std::uint8_t>& cave, const Grid3<float>& pressure, std::size_t start,
                        const std::vector<char>& exit) {
    const Dims& d = cave.dims;
    CAVESIM_CHECK(cave.data.size() == d.count() && pressure.dims == d && pressure.data.size() == d.count() &&
                      exit.size() == d.count(),
                  "descendPressure: cave, pressure and exit grids do not match");
    CAVESIM_CHECK(start < d.count(), "descendPressure: start voxel " + std::to_string(start) + " outside the grid");
    Descent out;
    std::size_t v = start;
    out.voxels.push_back(v);
    while (!exit[v]) {
        const Index3 p = d.coord(v);
        const double pv = pressure[v];
        double bestSlope = 0, bestP = 0;
        std::size_t best = d.count();
        for (const auto& o : allNeighbours()) {
            const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
            if (!d.contains(i, j, k)) continue;
            const std::size_t w = d.index(i, j, k);
            const double pw = pressure[w];
            if (!cave[w] || !(pw < pv)) continue;
            const double slope = (pv - pw) / o.length;
            if (best == d.count() || slope > bestSlope ||
                (slope == bestSlope && (pw < bestP || (pw == bestP && w < best)))) {
                best = w;
                bestSlope = slope;
                bestP = pw;
            }
        }
        if (best == d.count()) return out;  // a pit: no lower cave neighbour
        v = best;
        out.voxels.push_back(v);
    }
    out.reachedExit = true;
    return out;
}

NetworkCounts analyseNetwork(const Skeleton& s, const NetworkInput& in, const NetworkOptions& opt) {
    const Dims& d = in.dims;
    CAVESIM_CHECK(in.cave && in.cave->dims == d, "analyseNetwork: cave grid missing or not matching dims");
    CAVESIM_CHECK(!in.pressure || in.pressure->dims == d, "analyseNetwork: pressure grid does not match dims");
    NetworkCounts out;
    out.sourcesTotal = int(in.sources.size());
    for (std::size_t si = 0; si < in.sources.size(); ++si) {
        FlowPath fp;
        fp.source = int(si);
        out.paths.push_back(fp);
    }
    if (s.nodes.empty()) return out;

    Grid3<std::int32_t> nodeAt(d, -1);
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        CAVESIM_CHECK(s.nodes[n].voxel < d.count(), "analyseNetwork: skeleton node " + std::to_string(n) +
                                                        " stands on voxel " + std::to_string(s.nodes[n].voxel) +
                                                        ", outside the grid");
        nodeAt[s.nodes[n].voxel] = std::int32_t(n);
    }
    const Adjacency adj(s);
    const std::vector<int> comp = components(adj);
    std::vector<double> pressure(s.nodes.size(), 0.0);
    if (in.pressure)
        for (std::size_t n = 0; n < s.nodes.size(); ++n) pressure[n] = (*in.pressure)[s.nodes[n].voxel];

    // Sink attachments: target[node] = sink index.
    std::vector<int> target(s.nodes.size(), -1);
    for (std::size_t k = 0; k < in.sinks.size(); ++k)
        for (int n : attach(in.sinks[k], d, *in.cave, nodeAt, comp, opt.attachDistance))
            if (target[std::size_t(n)] < 0) target[std::size_t(n)] = int(k);

    // Exits: cave voxels that are a sink voxel or touch one (sinks are not cave), with the lowest
    // sink index they touch.
    std::vector<char> exit;
    std::vector<int> exitSink;
    std::vector<int> nearest;
    out.oriented = in.pressure != nullptr;
    if (out.oriented) {
        exit.assign(d.count(), 0);
        exitSink.assign(d.count(), -1);
        for (std::size_t k = 0; k < in.sinks.size(); ++k)
            for (std::size_t v : in.sinks[k]) {
                if (v >= d.count()) continue;
                const Index3 p = d.coord(v);
                auto mark = [&](std::size_t w) {
                    if (!(*in.cave)[w]) return;
                    exit[w] = 1;
                    if (exitSink[w] < 0 || int(k) < exitSink[w]) exitSink[w] = int(k);
                };
                mark(v);
                for (const auto& o : allNeighbours()) {
                    const int i = p.i + o.di, j = p.j + o.dj, kk = p.k + o.dk;
                    if (d.contains(i, j, kk)) mark(d.index(i, j, kk));
                }
            }
        nearest = nearestNodes(s, d, *in.cave);
    }

    // One flow path per source.
    for (std::size_t si = 0; si < in.sources.size(); ++si) {
        FlowPath& fp = out.paths[si];
        if (out.oriented) {
            // Start where the water leaves the source: the lowest-pressure cave voxel among the
            // source's voxels and their 26 neighbours (ties: the lower index).
            std::size_t start = d.count();
            for (std::size_t v : in.sources[si]) {
                if (v >= d.count()) continue;
                const Index3 p = d.coord(v);
                auto offer = [&](std::size_t w) {
                    if (!(*in.cave)[w]) return;
                    const float pw = (*in.pressure)[w];
                    if (start == d.count() || pw < (*in.pressure)[start] || (pw == (*in.pressure)[start] && w < start))
                        start = w;
                };
                offer(v);
                for (const auto& o : allNeighbours()) {
                    const int i = p.i + o.di, j = p.j + o.dj, k = p.k + o.dk;
                    if (d.contains(i, j, k)) offer(d.index(i, j, k));
                }
            }
            if (start < d.count()) {
                Descent descent = descendPressure(*in.cave, *in.pressure, start, exit);
                if (descent.reachedExit) {
                    fp.nodes = nodesAlong(s, adj, nearest, descent.voxels);
                    if (!fp.nodes.empty()) {
                        fp.sink = exitSink[descent.voxels.back()];
                        fp.voxels = std::move(descent.voxels);
                    }
                }
            }
        }
        if (fp.nodes.empty()) {
            // Fallback: the shortest skeleton path between the attached nodes, downhill if possible.
            const std::vector<int> from = attach(in.sources[si], d, *in.cave, nodeAt, comp, opt.attachDistance);
            if (from.empty()) continue;
            fp.nodes = shortestPath(s, adj, pressure, from, target, true);
            if (fp.nodes.empty()) {
                fp.nodes = shortestPath(s, adj, pressure, from, target, false);
                fp.downhill = false;
            }
            if (fp.nodes.empty()) continue;
            fp.sink = target[std::size_t(fp.nodes.back())];
            fp.fallback = out.oriented;
            if (fp.fallback) ++out.fallbackPaths;
        }
        ++out.sourcesConnected;
        // Elevation in voxel units from the smoothed node positions (a voxel staircase at a junction
        // is not a rise); without a voxel size, the node's voxel row.
        std::vector<double> z;
        for (int n : fp.nodes)
            z.push_back(in.voxelSize > 0 ? s.nodes[std::size_t(n)].position[2] / in.voxelSize - 0.5
                                         : double(d.coord(s.nodes[std::size_t(n)].voxel).k));
        for (std::size_t t : loopTroughs(z, opt.loopRise)) fp.loopTroughs.push_back(fp.nodes[t]);
    }

    // Joins between the paths of different sources, before the sink end.
    std::vector<int> confluenceNodes, troughNodes;
    for (std::size_t a = 0; a < out.paths.size(); ++a) {
        FlowPath& pa = out.paths[a];
        troughNodes.insert(troughNodes.end(), pa.loopTroughs.begin(), pa.loopTroughs.end());
        if (!pa.sink) continue;
        std::size_t bestPos = pa.nodes.size();
        for (std::size_t b = 0; b < out.paths.size(); ++b) {
            const FlowPath& pb = out.paths[b];
            if (a == b || !pb.sink) continue;
            std::vector<int> other(pb.nodes.begin(), pb.nodes.end());
            std::sort(other.begin(), other.end());
            // First node of a's path on b's path, the sink end excluded.
            for (std::size_t t = 0; t + 1 < pa.nodes.size(); ++t) {
                if (!std::binary_search(other.begin(), other.end(), pa.nodes[t])) continue;
                confluenceNodes.push_back(pa.nodes[t]);
                const auto& ci = in.connectedIteration;
                const bool known = a < ci.size() && b < ci.size() && ci[a] && ci[b];
                if (known && *ci[b] < *ci[a] && t < bestPos) {
                    bestPos = t;
                    pa.capturedBy = int(b);
                    pa.joinNode = pa.nodes[t];
                }
                break;
            }
        }
        if (pa.capturedBy) ++out.tributaryCaptures;
    }
    std::sort(confluenceNodes.begin(), confluenceNodes.end());
    out.confluences = int(std::unique(confluenceNodes.begin(), confluenceNodes.end()) - confluenceNodes.begin());
    std::sort(troughNodes.begin(), troughNodes.end());
    out.phreaticLoops = int(std::unique(troughNodes.begin(), troughNodes.end()) - troughNodes.begin());
    return out;
}

nlohmann::json toJson(const NetworkCounts& c, const Skeleton& s) {
    auto pos = [&](int n) {
        const auto& p = s.nodes[std::size_t(n)].position;
        return nlohmann::json::array({p[0], p[1], p[2]});
    };
    nlohmann::json paths = nlohmann::json::array();
    for (const FlowPath& fp : c.paths) {
        double length = 0;
        for (std::size_t t = 1; t < fp.nodes.size(); ++t)
            length += distance(s.nodes[std::size_t(fp.nodes[t - 1])], s.nodes[std::size_t(fp.nodes[t])]);
        nlohmann::json loops = nlohmann::json::array();
        for (int n : fp.loopTroughs) loops.push_back(pos(n));
        paths.push_back({{"source", fp.source},
                         {"connected", fp.sink.has_value()},
                         {"sink", fp.sink ? nlohmann::json(*fp.sink) : nlohmann::json(nullptr)},
                         {"length_m", length},
                         {"downhill", fp.downhill},
                         {"fallback", fp.fallback},
                         {"descent_voxels", fp.voxels.size()},
                         {"loop_troughs_m", loops},
                         {"captured_by", fp.capturedBy ? nlohmann::json(*fp.capturedBy) : nlohmann::json(nullptr)},
                         {"join_m", fp.joinNode ? pos(*fp.joinNode) : nlohmann::json(nullptr)}});
    }
    return {{"sources_total", c.sourcesTotal},
            {"sources_connected", c.sourcesConnected},
            {"confluences", c.confluences},
            {"tributary_captures", c.tributaryCaptures},
            {"phreatic_loops", c.phreaticLoops},
            {"fallback_paths", c.fallbackPaths},
            {"fallback_fraction", c.oriented && c.sourcesConnected > 0
                                      ? nlohmann::json(double(c.fallbackPaths) / double(c.sourcesConnected))
                                      : nlohmann::json(nullptr)},
            {"paths", paths}};
}

}  // namespace cavesim::morpho
