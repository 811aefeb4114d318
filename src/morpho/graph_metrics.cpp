// Network metrics of the centreline graph (Collon et al. 2017). Conventions: graph_metrics.h.
#include "morpho/graph_metrics.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/check.h"
#include "core/vec3.h"

namespace cavesim::morpho {
namespace {

/// Fraction of a histogram bin below an edge that still counts in the upper bin (round-off guard).
constexpr double kBinEdgeTolerance = 1e-9;

double distance(const SkeletonNode& a, const SkeletonNode& b) {
    return cavesim::distance(a.position, b.position);
}

/// Compressed adjacency of an undirected simple graph; each node's neighbours sorted by index.
struct Adjacency {
    std::vector<int> offset;     ///< n + 1 entries
    std::vector<int> neighbour;  ///< 2·E entries
    std::vector<int> edge;       ///< edge id of each entry

    int degree(int v) const { return offset[std::size_t(v) + 1] - offset[std::size_t(v)]; }
};

Adjacency buildAdjacency(int n, const std::vector<std::array<int, 2>>& edges) {
    Adjacency adj;
    adj.offset.assign(std::size_t(n) + 1, 0);
    for (const auto& e : edges) {
        ++adj.offset[std::size_t(e[0]) + 1];
        ++adj.offset[std::size_t(e[1]) + 1];
    }
    for (int v = 0; v < n; ++v) adj.offset[std::size_t(v) + 1] += adj.offset[std::size_t(v)];
    adj.neighbour.resize(edges.size() * 2);
    adj.edge.resize(edges.size() * 2);
    std::vector<int> fill(adj.offset.begin(), adj.offset.end() - 1);
    for (std::size_t id = 0; id < edges.size(); ++id) {
        const int a = edges[id][0], b = edges[id][1];
        adj.neighbour[std::size_t(fill[std::size_t(a)])] = b;
        adj.edge[std::size_t(fill[std::size_t(a)]++)] = int(id);
        adj.neighbour[std::size_t(fill[std::size_t(b)])] = a;
        adj.edge[std::size_t(fill[std::size_t(b)]++)] = int(id);
    }
    // Sort each node's entries by neighbour index so walks do not depend on the edge order.
    std::vector<std::pair<int, int>> tmp;
    for (int v = 0; v < n; ++v) {
        const int lo = adj.offset[std::size_t(v)], hi = adj.offset[std::size_t(v) + 1];
        tmp.clear();
        for (int p = lo; p < hi; ++p) tmp.emplace_back(adj.neighbour[std::size_t(p)], adj.edge[std::size_t(p)]);
        std::sort(tmp.begin(), tmp.end());
        for (int p = lo; p < hi; ++p) {
            adj.neighbour[std::size_t(p)] = tmp[std::size_t(p - lo)].first;
            adj.edge[std::size_t(p)] = tmp[std::size_t(p - lo)].second;
        }
    }
    return adj;
}

/// Connected components: label per node, count.
int labelComponents(const Adjacency& adj, int n, std::vector<int>& label) {
    label.assign(std::size_t(n), -1);
    std::vector<int> stack;
    int count = 0;
    for (int s = 0; s < n; ++s) {
        if (label[std::size_t(s)] >= 0) continue;
        label[std::size_t(s)] = count;
        stack.assign(1, s);
        while (!stack.empty()) {
            const int v = stack.back();
            stack.pop_back();
            for (int p = adj.offset[std::size_t(v)]; p < adj.offset[std::size_t(v) + 1]; ++p) {
                const int w = adj.neighbour[std::size_t(p)];
                if (label[std::size_t(w)] < 0) {
                    label[std::size_t(w)] = count;
                    stack.push_back(w);
                }
            }
        }
        ++count;
    }
    return count;
}

/// Edges with a < b (the validated skeleton may list either orientation).
std::vector<std::array<int, 2>> orientedEdges(const Skeleton& s) {
    std::vector<std::array<int, 2>> edges(s.edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        edges[i] = {std::min(s.edges[i][0], s.edges[i][1]), std::max(s.edges[i][0], s.edges[i][1])};
    return edges;
}

std::vector<Branch> branchesOf(const Skeleton& s, const std::vector<std::array<int, 2>>& edges, const Adjacency& adj) {
    const int n = int(s.nodes.size());
    std::vector<char> used(edges.size(), 0);
    std::vector<Branch> branches;
    auto walk = [&](int start, int p) {
        Branch br;
        br.nodes.push_back(start);
        int cur = start;
        while (true) {
            const int e = adj.edge[std::size_t(p)];
            const int next = adj.neighbour[std::size_t(p)];
            used[std::size_t(e)] = 1;
            br.length_m += distance(s.nodes[std::size_t(cur)], s.nodes[std::size_t(next)]);
            br.nodes.push_back(next);
            if (adj.degree(next) != 2 || next == start) break;
            // Leave `next` by its other edge.
            const int q = adj.offset[std::size_t(next)];
            p = adj.edge[std::size_t(q)] == e ? q + 1 : q;
            cur = next;
        }
        branches.push_back(std::move(br));
    };
    for (int v = 0; v < n; ++v) {
        if (adj.degree(v) == 2) continue;
        for (int p = adj.offset[std::size_t(v)]; p < adj.offset[std::size_t(v) + 1]; ++p)
            if (!used[std::size_t(adj.edge[std::size_t(p)])]) walk(v, p);
    }
    // What is left are components in which every node has degree 2: pure cycles.
    for (int v = 0; v < n; ++v) {
        if (adj.degree(v) != 2) continue;
        const int p = adj.offset[std::size_t(v)];
        if (!used[std::size_t(adj.edge[std::size_t(p)])]) walk(v, p);
    }
    return branches;
}

ReducedGraph reduce(int n, const Adjacency& adj, const std::vector<Branch>& branches) {
    // Cut points of each branch: positions in its node chain that become reduced nodes.
    std::vector<std::vector<std::size_t>> cuts(branches.size());
    std::vector<std::pair<std::uint64_t, std::size_t>> byEnds;  // non-loop branches keyed by their end pair
    for (std::size_t b = 0; b < branches.size(); ++b) {
        const auto& nodes = branches[b].nodes;
        if (branches[b].loop()) continue;
        const auto lo = std::uint64_t(std::min(nodes.front(), nodes.back()));
        const auto hi = std::uint64_t(std::max(nodes.front(), nodes.back()));
        byEnds.emplace_back((lo << 32) | hi, b);
    }
    std::sort(byEnds.begin(), byEnds.end());
    std::vector<char> parallel(branches.size(), 0);
    for (std::size_t i = 0; i < byEnds.size();) {
        std::size_t j = i;
        while (j < byEnds.size() && byEnds[j].first == byEnds[i].first) ++j;
        if (j - i > 1)
            for (std::size_t k = i; k < j; ++k) parallel[byEnds[k].second] = 1;
        i = j;
    }
    std::vector<char> kept(std::size_t(n), 0);
    for (int v = 0; v < n; ++v) kept[std::size_t(v)] = adj.degree(v) != 2;
    for (std::size_t b = 0; b < branches.size(); ++b) {
        const std::size_t m = branches[b].nodes.size() - 1;  // edges in the chain
        if (branches[b].loop()) {
            // A simple graph's cycle has m ≥ 3 edges, so 0 < k < 2k < m.
            const std::size_t k = (m + 1) / 3;
            cuts[b] = {0, k, 2 * k, m};
        } else if (parallel[b] && m >= 2) {
            cuts[b] = {0, (m + 1) / 2, m};
        } else {
            cuts[b] = {0, m};
        }
        for (std::size_t c : cuts[b]) kept[std::size_t(branches[b].nodes[c])] = 1;
    }
    ReducedGraph g;
    std::vector<int> id(std::size_t(n), -1);
    for (int v = 0; v < n; ++v)
        if (kept[std::size_t(v)]) {
            id[std::size_t(v)] = int(g.nodes.size());
            g.nodes.push_back(v);
        }
    for (std::size_t b = 0; b < branches.size(); ++b)
        for (std::size_t c = 0; c + 1 < cuts[b].size(); ++c) {
            const int a = id[std::size_t(branches[b].nodes[cuts[b][c]])];
            const int z = id[std::size_t(branches[b].nodes[cuts[b][c + 1]])];
            g.edges.push_back({std::min(a, z), std::max(a, z)});
        }
    std::sort(g.edges.begin(), g.edges.end());
    return g;
}

/// Shannon entropy of the weights' frequencies in base `base`; the weights sum to `total` > 0.
double entropy(const std::vector<double>& weights, double total, double base) {
    double h = 0.0;
    for (double w : weights)
        if (w > 0.0) {
            const double p = w / total;
            h -= p * std::log(p);
        }
    return h / std::log(base);
}

std::optional<double> orientationEntropy(const Skeleton& s, const std::vector<std::array<int, 2>>& edges) {
    std::vector<double> bins(18, 0.0);
    double total = 0.0;
    for (const auto& e : edges) {
        const auto& a = s.nodes[std::size_t(e[0])].position;
        const auto& b = s.nodes[std::size_t(e[1])].position;
        const double dx = b[0] - a[0], dy = b[1] - a[1];
        const double horizontal = std::hypot(dx, dy);
        if (horizontal == 0.0) continue;                      // vertical edge: no azimuth, no weight
        double azimuth = std::atan2(dx, dy) * (180.0 / kPi);  // clockwise from +y, (−180°, 180°]
        if (azimuth < 0.0) azimuth += 180.0;
        if (azimuth >= 180.0) azimuth -= 180.0;
        const int bin = int(std::floor(azimuth / 10.0 + kBinEdgeTolerance)) % 18;
        bins[std::size_t(bin)] += horizontal;
        total += horizontal;
    }
    if (!(total > 0.0)) return std::nullopt;
    return entropy(bins, total, 18.0);
}

std::optional<double> axisShareOf(const Skeleton& s, const std::vector<std::array<int, 2>>& edges, double tol) {
    double aligned = 0.0, total = 0.0;
    for (const auto& e : edges) {
        const auto& a = s.nodes[std::size_t(e[0])].position;
        const auto& b = s.nodes[std::size_t(e[1])].position;
        const double dx = std::abs(b[0] - a[0]), dy = std::abs(b[1] - a[1]);
        const double horizontal = std::hypot(dx, dy);
        if (horizontal == 0.0) continue;
        // Angle to the nearer of the two axes, in [0°, 45°].
        const double off = std::atan2(std::min(dx, dy), std::max(dx, dy)) * (180.0 / kPi);
        if (off <= tol + 1e-9) aligned += horizontal;
        total += horizontal;
    }
    if (!(total > 0.0)) return std::nullopt;
    return aligned / total;
}

/// What one breadth-first search per source gives on an unweighted graph (Brandes 2001).
struct AllPairs {
    std::vector<long long>
        distanceSum;  ///< per source (index into the sources): Σ hop distances to the nodes it reaches
    std::vector<double>
        dependency;  ///< per node: Σ over sources s of weight_s · δ_s(v) (= 2 × betweenness, undirected, when exact)
};

/// Brandes' betweenness and the hop-distance sums in one pass: for each of `sources` a BFS counting
/// shortest paths (σ), then the dependencies δ accumulated in reverse BFS order, times the source's
/// weight. Predecessors are the neighbours one hop closer, so no lists are stored. Sources are split
/// into blocks fixed by their number alone, each block accumulates into its own vector and the
/// blocks are summed in order: the result does not depend on the number of threads.
AllPairs allPairs(const Adjacency& adj, int n, const std::vector<int>& sources, const std::vector<double>& weight) {
    AllPairs out;
    const int count = int(sources.size());
    out.distanceSum.assign(std::size_t(count), 0);
    out.dependency.assign(std::size_t(n), 0.0);
    if (n == 0 || count == 0) return out;
    const int blockSize = std::max(32, (count + 63) / 64);  // ≤ 64 partial vectors
    const int blocks = (count + blockSize - 1) / blockSize;
    std::vector<std::vector<double>> partial(static_cast<std::size_t>(blocks));
    tbb::parallel_for(tbb::blocked_range<int>(0, blocks), [&](const tbb::blocked_range<int>& range) {
        std::vector<int> dist(std::size_t(n), -1), order;
        std::vector<double> sigma(std::size_t(n), 0.0), delta(std::size_t(n), 0.0);
        order.reserve(std::size_t(n));
        for (int b = range.begin(); b != range.end(); ++b) {
            std::vector<double>& acc = partial[std::size_t(b)];
            acc.assign(std::size_t(n), 0.0);
            for (int si = b * blockSize; si < std::min(count, (b + 1) * blockSize); ++si) {
                const int s = sources[std::size_t(si)];
                const double w = weight[std::size_t(si)];
                order.assign(1, s);
                dist[std::size_t(s)] = 0;
                sigma[std::size_t(s)] = 1.0;
                long long sum = 0;
                for (std::size_t head = 0; head < order.size(); ++head) {
                    const int v = order[head];
                    const int dv = dist[std::size_t(v)];
                    sum += dv;
                    for (int p = adj.offset[std::size_t(v)]; p < adj.offset[std::size_t(v) + 1]; ++p) {
                        const int x = adj.neighbour[std::size_t(p)];
                        if (dist[std::size_t(x)] < 0) {
                            dist[std::size_t(x)] = dv + 1;
                            order.push_back(x);
                        }
                        if (dist[std::size_t(x)] == dv + 1) sigma[std::size_t(x)] += sigma[std::size_t(v)];
                    }
                }
                out.distanceSum[std::size_t(si)] = sum;
                for (std::size_t idx = order.size(); idx-- > 1;) {
                    const int x = order[idx];
                    const double share = (1.0 + delta[std::size_t(x)]) / sigma[std::size_t(x)];
                    for (int p = adj.offset[std::size_t(x)]; p < adj.offset[std::size_t(x) + 1]; ++p) {
                        const int v = adj.neighbour[std::size_t(p)];
                        if (dist[std::size_t(v)] == dist[std::size_t(x)] - 1)
                            delta[std::size_t(v)] += sigma[std::size_t(v)] * share;
                    }
                    acc[std::size_t(x)] += w * delta[std::size_t(x)];  // w is 1 when exact: the same sum
                }
                for (int v : order) {
                    dist[std::size_t(v)] = -1;
                    sigma[std::size_t(v)] = 0.0;
                    delta[std::size_t(v)] = 0.0;
                }
            }
        }
    });
    for (const auto& acc : partial)
        for (int v = 0; v < n; ++v) out.dependency[std::size_t(v)] += acc[std::size_t(v)];
    return out;
}

/// The BFS sources of `allPairs` and their weights: every node (weight 1) up to kExactPairsNodes
/// nodes; beyond, per component c of n_c nodes, k_c = ⌈kPairSources · n_c / n⌉ nodes evenly spaced
/// in index order (all of them when n_c ≤ k_c), each weighted n_c / k_c (Brandes & Pich 2007).
void pairSources(const std::vector<int>& label, int components, std::vector<int>& sources,
                 std::vector<double>& weight) {
    const int n = int(label.size());
    sources.clear();
    weight.clear();
    if (n <= kExactPairsNodes) {
        for (int v = 0; v < n; ++v) sources.push_back(v);
        weight.assign(std::size_t(n), 1.0);
        return;
    }
    std::vector<std::vector<int>> members(static_cast<std::size_t>(components));
    for (int v = 0; v < n; ++v) members[std::size_t(label[std::size_t(v)])].push_back(v);
    for (const auto& m : members) {
        const long long nc = static_cast<long long>(m.size());
        const long long kc = std::min(nc, (static_cast<long long>(kPairSources) * nc + n - 1) / n);
        for (long long i = 0; i < kc; ++i) {
            sources.push_back(m[std::size_t(i * nc / kc)]);
            weight.push_back(double(nc) / double(kc));
        }
    }
}

/// Freeman's central point dominance from the summed dependencies (each unordered pair counted
/// twice): b = dependency/2 · 2/((n−1)(n−2)), cpd = Σ(b_max − b)/(n − 1). Same normalisation as
/// Boost's relative_betweenness_centrality + central_point_dominance and networkx/karstnet.
std::optional<double> centralPointDominance(const std::vector<double>& dependency) {
    const std::size_t n = dependency.size();
    if (n < 2) return std::nullopt;
    if (n == 2) return 0.0;  // nobody lies between two others (and the normalisation would divide by 0)
    const double scale = 1.0 / (double(n - 1) * double(n - 2));
    const double bmax = *std::max_element(dependency.begin(), dependency.end()) * scale;
    double sum = 0.0;
    for (double d : dependency) sum += bmax - d * scale;
    return sum / double(n - 1);
}

GraphMetrics metricsOf(const Skeleton& s) {
    const int n = int(s.nodes.size());
    const auto edges = orientedEdges(s);
    const Adjacency adj = buildAdjacency(n, edges);
    const std::vector<Branch> branches = branchesOf(s, edges, adj);
    GraphMetrics m;

    std::vector<int> label;
    m.components = labelComponents(adj, n, label);
    m.loops = long(edges.size()) - long(n) + m.components;
    m.branches = long(branches.size());
    m.too_small = m.branches < kMinNetworkBranches;

    // Branch geometry.
    if (!branches.empty()) {
        double sum = 0.0, lmax = 0.0;
        for (const auto& b : branches) {
            sum += b.length_m;
            lmax = std::max(lmax, b.length_m);
            m.loop_branches += b.loop() ? 1 : 0;
        }
        const double mean = sum / double(branches.size());
        m.len_mean_m = mean;
        if (branches.size() >= 2 && mean > 0.0) {
            double ss = 0.0;
            for (const auto& b : branches) ss += (b.length_m - mean) * (b.length_m - mean);
            m.cv_len = std::sqrt(ss / double(branches.size() - 1)) / mean;
        }
        if (lmax > 0.0) {
            std::vector<double> bins(10, 0.0);
            for (const auto& b : branches) {
                const int bin = std::min(9, int(std::floor(10.0 * b.length_m / lmax + kBinEdgeTolerance)));
                bins[std::size_t(bin)] += 1.0;
            }
            m.h_len = entropy(bins, double(branches.size()), 10.0);
        }
        double tsum = 0.0;
        long tcount = 0;
        for (const auto& b : branches) {
            if (b.loop()) continue;
            const double chord = distance(s.nodes[std::size_t(b.nodes.front())], s.nodes[std::size_t(b.nodes.back())]);
            if (!(chord > 1e-12 * b.length_m)) continue;  // ends coincide: no straight distance
            tsum += b.length_m / chord;
            ++tcount;
        }
        if (tcount > 0) m.tortuosity = tsum / double(tcount);
    }
    m.h_or = orientationEntropy(s, edges);
    m.axis_aligned_share = axisShareOf(s, edges, 5.0);

    // Topology of the reduced graph.
    const ReducedGraph g = reduce(n, adj, branches);
    const int rn = int(g.nodes.size());
    const long long re = static_cast<long long>(g.edges.size());
    m.reduced_nodes = rn;
    m.reduced_edges = long(re);
    if (rn == 0) return m;
    const Adjacency radj = buildAdjacency(rn, g.edges);
    m.k_mean = 2.0 * double(re) / double(rn);

    if (re > 0) {
        // Pearson correlation over the 2E ordered edge ends, in exact integer sums:
        // r = (M·Σxy − (Σx)²) / (M·Σx² − (Σx)²), M = 2E.
        long long sx = 0, sxx = 0, sxy = 0;
        for (const auto& e : g.edges) {
            const long long da = radj.degree(e[0]), db = radj.degree(e[1]);
            sx += da + db;
            sxx += da * da + db * db;
            sxy += 2 * da * db;
        }
        // 128-bit products: M·Σx² can pass 2^63 on a star of a million leaves.
        const __int128 M = 2 * re;
        const __int128 den = M * sxx - __int128(sx) * sx;
        m.r_k = den == 0 ? 1.0 : double(M * sxy - __int128(sx) * sx) / double(den);
    }

    std::vector<int> rlabel;
    const int rcomp = labelComponents(radj, rn, rlabel);
    std::vector<long long> size(std::size_t(rcomp), 0);
    for (int v = 0; v < rn; ++v) ++size[std::size_t(rlabel[std::size_t(v)])];
    std::vector<int> sources;
    std::vector<double> sourceWeight;
    pairSources(rlabel, rcomp, sources, sourceWeight);
    m.pair_sources = long(sources.size());
    const AllPairs all = allPairs(radj, rn, sources, sourceWeight);
    // Σ over a component's sources of their distance sums: exact integers when every node is a
    // source, else each sampled source stands for n_c / k_c of them.
    std::vector<long long> sums(std::size_t(rcomp), 0);
    std::vector<double> estimated(std::size_t(rcomp), 0.0);
    for (std::size_t i = 0; i < sources.size(); ++i) {
        const int c = rlabel[std::size_t(sources[i])];
        sums[std::size_t(c)] += all.distanceSum[i];
        estimated[std::size_t(c)] += sourceWeight[i] * double(all.distanceSum[i]);
    }
    const bool exact = int(sources.size()) == rn;
    double weighted = 0.0;
    long long weight = 0;
    for (int c = 0; c < rcomp; ++c) {
        const long long nc = size[std::size_t(c)];
        if (nc < 2) continue;
        const double total = exact ? double(sums[std::size_t(c)]) : estimated[std::size_t(c)];
        weighted += total / double(nc - 1);  // n_c · spl_c
        weight += nc;
    }
    if (weight > 0) m.spl = weighted / double(weight);

    m.cpd = centralPointDominance(all.dependency);
    return m;
}

}  // namespace

void validateSkeleton(const Skeleton& skeleton) {
    CAVESIM_CHECK(skeleton.nodes.size() <= std::size_t(INT_MAX),
                  "skeleton: " + std::to_string(skeleton.nodes.size()) + " nodes, more than an int indexes");
    CAVESIM_CHECK(skeleton.edges.size() <= std::size_t(INT_MAX / 2),
                  "skeleton: " + std::to_string(skeleton.edges.size()) + " edges, more than an int indexes");
    const int n = int(skeleton.nodes.size());
    for (std::size_t i = 0; i < skeleton.nodes.size(); ++i)
        for (double c : skeleton.nodes[i].position)
            CAVESIM_CHECK(std::isfinite(c), "skeleton: node " + std::to_string(i) + " has a non-finite position");
    std::vector<std::uint64_t> keys;
    keys.reserve(skeleton.edges.size());
    for (std::size_t i = 0; i < skeleton.edges.size(); ++i) {
        const int a = skeleton.edges[i][0], b = skeleton.edges[i][1];
        CAVESIM_CHECK(a >= 0 && b >= 0 && a < n && b < n, "skeleton: edge " + std::to_string(i) + " (" +
                                                              std::to_string(a) + ", " + std::to_string(b) +
                                                              ") refers to a node outside 0.." + std::to_string(n - 1));
        CAVESIM_CHECK(a != b, "skeleton: edge " + std::to_string(i) + " is a self loop on node " + std::to_string(a));
        keys.push_back((std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b)));
    }
    std::sort(keys.begin(), keys.end());
    const auto dup = std::adjacent_find(keys.begin(), keys.end());
    CAVESIM_CHECK(dup == keys.end(), "skeleton: edge (" + std::to_string(*dup >> 32) + ", " +
                                         std::to_string(*dup & 0xffffffffu) + ") is listed twice");
}

std::vector<Branch> findBranches(const Skeleton& skeleton) {
    validateSkeleton(skeleton);
    const auto edges = orientedEdges(skeleton);
    const Adjacency adj = buildAdjacency(int(skeleton.nodes.size()), edges);
    return branchesOf(skeleton, edges, adj);
}

ReducedGraph reduceSkeleton(const Skeleton& skeleton) {
    validateSkeleton(skeleton);
    const int n = int(skeleton.nodes.size());
    const auto edges = orientedEdges(skeleton);
    const Adjacency adj = buildAdjacency(n, edges);
    return reduce(n, adj, branchesOf(skeleton, edges, adj));
}

GraphMetrics computeGraphMetrics(const Skeleton& skeleton) {
    validateSkeleton(skeleton);
    return metricsOf(skeleton);
}

std::optional<double> axisAlignedShare(const Skeleton& skeleton, double toleranceDeg) {
    validateSkeleton(skeleton);
    CAVESIM_CHECK(toleranceDeg >= 0.0 && toleranceDeg <= 45.0,
                  "axisAlignedShare: tolerance must lie in [0, 45] degrees, got " + std::to_string(toleranceDeg));
    return axisShareOf(skeleton, skeleton.edges, toleranceDeg);
}

nlohmann::json toJson(const GraphMetrics& m) {
    nlohmann::json j = nlohmann::json::object();
    auto put = [&j](const char* key, const std::optional<double>& v) {
        j[key] = v ? nlohmann::json(*v) : nlohmann::json(nullptr);
    };
    put("k_mean", m.k_mean);
    put("r_k", m.r_k);
    put("spl", m.spl);
    put("cpd", m.cpd);
    put("h_or", m.h_or);
    put("axis_aligned_share", m.axis_aligned_share);
    put("len_mean_m", m.len_mean_m);
    put("cv_len", m.cv_len);
    put("h_len", m.h_len);
    put("tortuosity", m.tortuosity);
    j["branches"] = m.branches;
    j["loop_branches"] = m.loop_branches;
    j["loops"] = m.loops;
    j["components"] = m.components;
    j["reduced_nodes"] = m.reduced_nodes;
    j["reduced_edges"] = m.reduced_edges;
    j["pair_sources"] = m.pair_sources;
    j["too_small"] = m.too_small;
    return j;
}

}  // namespace cavesim::morpho
