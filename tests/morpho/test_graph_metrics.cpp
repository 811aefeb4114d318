// Network metrics against values worked out by hand: a line, a star, a ring, a 3×3 lattice, a Y with
// unequal arms, a loop on a junction, parallel branches, several components; the entropies at their
// extremes; invariance under relabelling; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <string>

#include <tbb/task_arena.h>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/betweenness_centrality.hpp>

#include "core/error.h"
#include "morpho/graph_metrics.h"

namespace cavesim::morpho {
namespace {

constexpr double kTol = 1e-12;
const double kPi = std::acos(-1.0);

Skeleton makeSkeleton(const std::vector<std::array<double, 3>>& positions,
                      const std::vector<std::array<int, 2>>& edges) {
    Skeleton s;
    for (const auto& p : positions) s.nodes.push_back({p, 0.5, 0});
    s.edges = edges;
    return s;
}

/// Shannon entropy (base `base`) of the frequencies `weights / Σ weights`, written out for the tests.
double H(const std::vector<double>& weights, double base) {
    const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
    double h = 0.0;
    for (double w : weights)
        if (w > 0) h -= w / total * std::log(w / total);
    return h / std::log(base);
}

// 0 — 1 — 2 — 3 — 4 along x, 1 m apart.
Skeleton line() {
    return makeSkeleton({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}}, {{0, 1}, {1, 2}, {2, 3}, {3, 4}});
}

TEST(GraphMetrics, LineIsOneBranchAndOneReducedEdge) {
    const Skeleton s = line();
    const auto branches = findBranches(s);
    ASSERT_EQ(branches.size(), 1u);
    EXPECT_EQ(branches[0].nodes, (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_DOUBLE_EQ(branches[0].length_m, 4.0);
    EXPECT_FALSE(branches[0].loop());
    const ReducedGraph g = reduceSkeleton(s);
    EXPECT_EQ(g.nodes, (std::vector<int>{0, 4}));
    ASSERT_EQ(g.edges.size(), 1u);

    const GraphMetrics m = computeGraphMetrics(s);
    // Reduced graph: two ends joined by one edge. k = 2·1/2 = 1; both ends have degree 1 → r_k = 1;
    // one pair at 1 hop → spl = 1; n = 2 → nothing lies between two nodes → cpd = 0.
    EXPECT_DOUBLE_EQ(*m.k_mean, 1.0);
    EXPECT_DOUBLE_EQ(*m.r_k, 1.0);
    EXPECT_DOUBLE_EQ(*m.spl, 1.0);
    EXPECT_DOUBLE_EQ(*m.cpd, 0.0);
    // One branch of 4 m, straight: len = 4, tortuosity 4/4 = 1, h_len = 0 (one bin), cv_len needs
    // two branches (sample sd) → undefined. All edges east–west → one orientation bin → h_or = 0.
    EXPECT_DOUBLE_EQ(*m.len_mean_m, 4.0);
    EXPECT_FALSE(m.cv_len.has_value());
    EXPECT_DOUBLE_EQ(*m.h_len, 0.0);
    EXPECT_DOUBLE_EQ(*m.tortuosity, 1.0);
    EXPECT_DOUBLE_EQ(*m.h_or, 0.0);
    EXPECT_EQ(m.branches, 1);
    EXPECT_EQ(m.loop_branches, 0);
    EXPECT_EQ(m.loops, 0);
    EXPECT_EQ(m.components, 1);
    EXPECT_EQ(m.reduced_nodes, 2);
    EXPECT_EQ(m.reduced_edges, 1);
}

TEST(GraphMetrics, StarWithFourTwoEdgeArms) {
    // Centre 0; arms 0–1–2 (+x), 0–3–4 (−x), 0–5–6 (+y), 0–7–8 (−y), edges of 1 m.
    const Skeleton s = makeSkeleton(
        {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {-1, 0, 0}, {-2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, -1, 0}, {0, -2, 0}},
        {{0, 1}, {1, 2}, {0, 3}, {3, 4}, {0, 5}, {5, 6}, {0, 7}, {7, 8}});
    EXPECT_EQ(reduceSkeleton(s).nodes, (std::vector<int>{0, 2, 4, 6, 8}));
    const GraphMetrics m = computeGraphMetrics(s);
    // Reduced: centre of degree 4 + 4 leaves. k = 2·4/5 = 1.6.
    EXPECT_NEAR(*m.k_mean, 1.6, kTol);
    // Every edge joins degrees 4 and 1: ends (4,1) and (1,4) → perfectly disassortative, r_k = −1.
    EXPECT_NEAR(*m.r_k, -1.0, kTol);
    // 4 centre–leaf pairs at 1 hop, 6 leaf–leaf pairs at 2 hops: (4 + 12)/10 = 1.6.
    EXPECT_NEAR(*m.spl, 1.6, kTol);
    // Centre lies on all C(4,2) = 6 leaf–leaf paths: 6 · 2/((5−1)(5−2)) = 1; leaves 0.
    // cpd = 4·(1 − 0)/(5 − 1) = 1.
    EXPECT_NEAR(*m.cpd, 1.0, kTol);
    // Four straight branches of 2 m: mean 2, sd 0 → cv 0, one length bin → h_len 0, tortuosity 1.
    EXPECT_NEAR(*m.len_mean_m, 2.0, kTol);
    EXPECT_NEAR(*m.cv_len, 0.0, kTol);
    EXPECT_NEAR(*m.h_len, 0.0, kTol);
    EXPECT_NEAR(*m.tortuosity, 1.0, kTol);
    // Orientations: 4 m north–south (bin 0), 4 m east–west (bin 9) → log18(2).
    EXPECT_NEAR(*m.h_or, std::log(2.0) / std::log(18.0), kTol);
}

TEST(GraphMetrics, RingKeepsItsLoopAsATriangle) {
    // Regular hexagon of radius 1: sides of 1 m.
    std::vector<std::array<double, 3>> p;
    for (int k = 0; k < 6; ++k) p.push_back({std::cos(k * kPi / 3), std::sin(k * kPi / 3), 0.0});
    const Skeleton s = makeSkeleton(p, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {0, 5}});
    const auto branches = findBranches(s);
    ASSERT_EQ(branches.size(), 1u);
    EXPECT_EQ(branches[0].nodes, (std::vector<int>{0, 1, 2, 3, 4, 5, 0}));  // anchored at the lowest node
    EXPECT_TRUE(branches[0].loop());
    // The 6-edge loop is cut at chain positions k = ⌊7/3⌋ = 2 and 2k = 4: nodes 0, 2, 4 → a triangle.
    const ReducedGraph g = reduceSkeleton(s);
    EXPECT_EQ(g.nodes, (std::vector<int>{0, 2, 4}));
    EXPECT_EQ(g.edges, (std::vector<std::array<int, 2>>{{0, 1}, {0, 2}, {1, 2}}));

    const GraphMetrics m = computeGraphMetrics(s);
    // Triangle: k = 2, all degrees equal → r_k = 1, every pair adjacent → spl = 1, nobody between → cpd = 0.
    EXPECT_NEAR(*m.k_mean, 2.0, kTol);
    EXPECT_NEAR(*m.r_k, 1.0, kTol);
    EXPECT_NEAR(*m.spl, 1.0, kTol);
    EXPECT_NEAR(*m.cpd, 0.0, kTol);
    // One loop branch of 6 m; its ends coincide → no tortuosity.
    EXPECT_NEAR(*m.len_mean_m, 6.0, 1e-12);
    EXPECT_FALSE(m.cv_len.has_value());
    EXPECT_NEAR(*m.h_len, 0.0, kTol);
    EXPECT_FALSE(m.tortuosity.has_value());
    // Sides have azimuths 150°, 90°, 30°, 150°, 90°, 30° (folded): three bins of 2 m → log18(3).
    EXPECT_NEAR(*m.h_or, std::log(3.0) / std::log(18.0), kTol);
    EXPECT_EQ(m.loops, 1);
    EXPECT_EQ(m.loop_branches, 1);
    EXPECT_EQ(m.reduced_nodes, 3);
    EXPECT_EQ(m.reduced_edges, 3);
}

// 3×3 grid graph, node (i, j) = i + 3j at (i, j, 0) m.
Skeleton lattice3() {
    std::vector<std::array<double, 3>> p;
    std::vector<std::array<int, 2>> e;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            p.push_back({double(i), double(j), 0.0});
            if (i < 2) e.push_back({i + 3 * j, i + 1 + 3 * j});
            if (j < 2) e.push_back({i + 3 * j, i + 3 * (j + 1)});
        }
    return makeSkeleton(p, e);
}

void expectLattice3(const GraphMetrics& m) {
    // Corners have degree 2 and go: the reduced graph is the wheel W5 — hub 4 (degree 4) joined to the
    // side midpoints 1, 3, 5, 7 (degree 3), which form a 4-cycle through the removed corners.
    EXPECT_EQ(m.reduced_nodes, 5);
    EXPECT_EQ(m.reduced_edges, 8);
    // k = (4 + 4·3)/5 = 3.2.
    EXPECT_NEAR(*m.k_mean, 3.2, kTol);
    // 16 ordered ends: spokes (4,3)×4 and (3,4)×4, rim (3,3)×8. Mean 52/16 = 3.25, E[x²] = 172/16,
    // var = 10.75 − 10.5625 = 0.1875, E[xy] = (8·12 + 8·9)/16 = 10.5, cov = −0.0625 → r = −1/3.
    EXPECT_NEAR(*m.r_k, -1.0 / 3.0, kTol);
    // Hub: 4 pairs at 1. Each rim node: hub 1, two rim neighbours 1, opposite 2 → 5.
    // Ordered sum 4 + 4·5 = 24 over 5·4 = 20 pairs → 1.2.
    EXPECT_NEAR(*m.spl, 1.2, kTol);
    // Opposite rim pairs (A,C), (B,D) each have 3 shortest paths (via hub, via either rim node):
    // hub 2/3, each rim node 1/3. Normalised by 2/(4·3) = 1/6: hub 1/9, rim 1/18.
    // cpd = 4·(1/9 − 1/18)/4 = 1/18.
    EXPECT_NEAR(*m.cpd, 1.0 / 18.0, kTol);
    // Branches: 4 spokes of 1 m, 4 rim chains of 2 m (through a corner). Mean 1.5; sample sd
    // sqrt(8·0.25/7) → cv = sqrt(2/7)/1.5.
    EXPECT_EQ(m.branches, 8);
    EXPECT_NEAR(*m.len_mean_m, 1.5, kTol);
    EXPECT_NEAR(*m.cv_len, std::sqrt(2.0 / 7.0) / 1.5, kTol);
    // Normalised lengths 50 (×4, bin 5) and 100 (×4, bin 9) → log10(2).
    EXPECT_NEAR(*m.h_len, std::log10(2.0), kTol);
    // Spokes straight (1), rim chains 2/√2 = √2 → (4 + 4√2)/8.
    EXPECT_NEAR(*m.tortuosity, (1.0 + std::sqrt(2.0)) / 2.0, kTol);
    // 6 m east–west, 6 m north–south → log18(2).
    EXPECT_NEAR(*m.h_or, std::log(2.0) / std::log(18.0), kTol);
    EXPECT_EQ(m.loops, 12 - 9 + 1);
    EXPECT_EQ(m.components, 1);
}

TEST(GraphMetrics, Lattice3x3) {
    const Skeleton s = lattice3();
    EXPECT_EQ(reduceSkeleton(s).nodes, (std::vector<int>{1, 3, 4, 5, 7}));
    expectLattice3(computeGraphMetrics(s));
}

TEST(GraphMetrics, InvariantUnderRelabellingAndEdgeOrder) {
    const Skeleton s = lattice3();
    std::vector<int> perm(s.nodes.size());
    std::iota(perm.begin(), perm.end(), 0);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 5; ++trial) {
        std::shuffle(perm.begin(), perm.end(), rng);
        Skeleton t;
        t.nodes.resize(s.nodes.size());
        for (std::size_t v = 0; v < perm.size(); ++v) t.nodes[std::size_t(perm[v])] = s.nodes[v];
        for (const auto& e : s.edges)
            t.edges.push_back({perm[std::size_t(e[1])], perm[std::size_t(e[0])]});  // either orientation
        std::shuffle(t.edges.begin(), t.edges.end(), rng);
        expectLattice3(computeGraphMetrics(t));
    }
}

TEST(GraphMetrics, SameBitsWhateverTheThreadCount) {
    // A 9×9×3 grid graph (243 junctions: several blocks of sources) with irregular positions.
    Skeleton s;
    auto id = [](int i, int j, int k) { return i + 9 * (j + 9 * k); };
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 9; ++j)
            for (int i = 0; i < 9; ++i) {
                s.nodes.push_back({{i + 0.3 * std::sin(j * k + 1.0), j + 0.2 * std::cos(i), 2.0 * k}, 0.5, 0});
                if (i + 1 < 9) s.edges.push_back({id(i, j, k), id(i + 1, j, k)});
                if (j + 1 < 9 && (i + j) % 4) s.edges.push_back({id(i, j, k), id(i, j + 1, k)});
                if (k + 1 < 3 && (i * j) % 3 == 0) s.edges.push_back({id(i, j, k), id(i, j, k + 1)});
            }
    GraphMetrics one, two;
    tbb::task_arena(1).execute([&] { one = computeGraphMetrics(s); });
    tbb::task_arena(2).execute([&] { two = computeGraphMetrics(s); });
    EXPECT_EQ(toJson(one).dump(), toJson(two).dump());
    EXPECT_GT(one.reduced_nodes, 64);
}

TEST(GraphMetrics, YWithUnequalArms) {
    // Centre 0 at the origin. Arm A: 0–1–2–3 along +x (3 m, straight). Arm B: 0 → (0,3) → (4,3),
    // bent: 3 + 4 = 7 m, ends 5 m apart. Arm C: 0 → (−1,0): 1 m.
    const Skeleton s = makeSkeleton({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 3, 0}, {4, 3, 0}, {-1, 0, 0}},
                                    {{0, 1}, {1, 2}, {2, 3}, {0, 4}, {4, 5}, {0, 6}});
    const auto branches = findBranches(s);
    ASSERT_EQ(branches.size(), 3u);
    EXPECT_EQ(branches[0].nodes, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(branches[1].nodes, (std::vector<int>{0, 4, 5}));
    EXPECT_EQ(branches[2].nodes, (std::vector<int>{0, 6}));
    const GraphMetrics m = computeGraphMetrics(s);
    // Lengths 3, 7, 1: mean 11/3; deviations −2/3, 10/3, −8/3 → Σ² = 168/9, sample var 84/9,
    // cv = sqrt(84/9)/(11/3) = sqrt(84)/11.
    EXPECT_NEAR(*m.len_mean_m, 11.0 / 3.0, kTol);
    EXPECT_NEAR(*m.cv_len, std::sqrt(84.0) / 11.0, kTol);
    // Normalised 42.9 (bin 4), 100 (bin 9), 14.3 (bin 1): three bins of 1/3 → log10(3).
    EXPECT_NEAR(*m.h_len, std::log10(3.0), kTol);
    // Tortuosities 1, 7/5, 1 → 3.4/3.
    EXPECT_NEAR(*m.tortuosity, 3.4 / 3.0, kTol);
    // East–west 3 + 4 + 1 = 8 m, north–south 3 m.
    EXPECT_NEAR(*m.h_or, H({8, 3}, 18), kTol);
    // Reduced: a star with 3 leaves. k = 6/4; r = −1; spl = (2·(3·1 + 3·2))/12 = 1.5;
    // centre on 3 pairs → 3·2/(3·2) = 1, cpd = 3·1/3 = 1.
    EXPECT_NEAR(*m.k_mean, 1.5, kTol);
    EXPECT_NEAR(*m.r_k, -1.0, kTol);
    EXPECT_NEAR(*m.spl, 1.5, kTol);
    EXPECT_NEAR(*m.cpd, 1.0, kTol);
}

TEST(GraphMetrics, LoopOnAJunction) {
    // Stick 0–1 and a triangle 1–2–3 hanging on node 1 (degree 3).
    const Skeleton s = makeSkeleton({{-1, 0, 0}, {0, 0, 0}, {1, 1, 0}, {1, -1, 0}}, {{0, 1}, {1, 2}, {1, 3}, {2, 3}});
    const auto branches = findBranches(s);
    ASSERT_EQ(branches.size(), 2u);
    EXPECT_EQ(branches[0].nodes, (std::vector<int>{0, 1}));
    EXPECT_EQ(branches[1].nodes, (std::vector<int>{1, 2, 3, 1}));
    // The loop (3 edges) is cut at positions 1 and 2: the reduced graph is the skeleton itself.
    const ReducedGraph g = reduceSkeleton(s);
    EXPECT_EQ(g.nodes, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(g.edges.size(), 4u);
    const GraphMetrics m = computeGraphMetrics(s);
    // Degrees 1, 3, 2, 2: k = 8/4 = 2.
    EXPECT_NEAR(*m.k_mean, 2.0, kTol);
    // Ends (1,3) (3,2) (3,2) (2,2), both ways, M = 8: Σx = 18, Σx² = 44, Σxy = 2·(3+6+6+4) = 38.
    // r = (8·38 − 18²)/(8·44 − 18²) = −20/28.
    EXPECT_NEAR(*m.r_k, -20.0 / 28.0, kTol);
    // Pairs 0-1:1 0-2:2 0-3:2 1-2:1 1-3:1 2-3:1 → 8/6.
    EXPECT_NEAR(*m.spl, 8.0 / 6.0, kTol);
    // Node 1 lies on 0–2 and 0–3: 2 · 2/(3·2) = 2/3, others 0 → cpd = 3·(2/3)/3.
    EXPECT_NEAR(*m.cpd, 2.0 / 3.0, kTol);
    // Only the stick counts for tortuosity.
    EXPECT_NEAR(*m.tortuosity, 1.0, kTol);
    EXPECT_EQ(m.loop_branches, 1);
    EXPECT_EQ(m.loops, 1);
}

TEST(GraphMetrics, ParallelBranchesAreSplitSoTheReducedGraphStaysSimple) {
    // Junctions 0 (0,0) and 1 (4,0) joined three ways: directly, via 2 (2,1), via 3 (1,−1) and 4 (3,−1).
    const Skeleton s = makeSkeleton({{0, 0, 0}, {4, 0, 0}, {2, 1, 0}, {1, -1, 0}, {3, -1, 0}},
                                    {{0, 1}, {0, 2}, {1, 2}, {0, 3}, {3, 4}, {1, 4}});
    // The direct edge stays; 0–2–1 is cut at 2; 0–3–4–1 at its middle position ⌊4/2⌋ = 2 → node 4.
    const ReducedGraph g = reduceSkeleton(s);
    EXPECT_EQ(g.nodes, (std::vector<int>{0, 1, 2, 4}));
    EXPECT_EQ(g.edges, (std::vector<std::array<int, 2>>{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}}));
    const GraphMetrics m = computeGraphMetrics(s);
    // K4 minus one edge: degrees 3, 3, 2, 2 → k = 10/4.
    EXPECT_NEAR(*m.k_mean, 2.5, kTol);
    // Edges (3,3) + 4×(3,2): M = 10, Σx = 26, Σx² = 70, Σxy = 2·(9 + 24) = 66 → (660 − 676)/(700 − 676) = −2/3.
    EXPECT_NEAR(*m.r_k, -2.0 / 3.0, kTol);
    // Five pairs at 1, the two degree-2 nodes at 2 → 7/6.
    EXPECT_NEAR(*m.spl, 7.0 / 6.0, kTol);
    // The far pair has 2 shortest paths, via each junction: 1/2 each → normalised 1/2 · 2/(3·2) = 1/6.
    // cpd = (0 + 0 + 1/6 + 1/6)/3 = 1/9.
    EXPECT_NEAR(*m.cpd, 1.0 / 9.0, kTol);
    EXPECT_EQ(m.loops, 2);
    EXPECT_EQ(m.loop_branches, 0);
    // Lengths 4, 2√5, 2 + 2√2; chords all 4.
    const double l1 = 4, l2 = 2 * std::sqrt(5.0), l3 = 2 + 2 * std::sqrt(2.0);
    EXPECT_NEAR(*m.len_mean_m, (l1 + l2 + l3) / 3, kTol);
    EXPECT_NEAR(*m.tortuosity, (l1 + l2 + l3) / 12, kTol);
}

TEST(GraphMetrics, ComponentsAreWeightedByTheirNodeCounts) {
    // A: 0–1 (a lone passage). B: star 2 with leaves 3, 4, 5. C: isolated node 6.
    const Skeleton s = makeSkeleton({{0, 0, 0}, {1, 0, 0}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}, {9, 0, 0}, {20, 0, 0}},
                                    {{0, 1}, {2, 3}, {2, 4}, {2, 5}});
    const GraphMetrics m = computeGraphMetrics(s);
    EXPECT_EQ(m.components, 3);
    EXPECT_EQ(m.reduced_nodes, 7);
    // k = 2·4/7 (the isolated node counts, degree 0).
    EXPECT_NEAR(*m.k_mean, 8.0 / 7.0, kTol);
    // spl_A = 1 (2 nodes), spl_B = 1.5 (4 nodes), C has no pair: (2·1 + 4·1.5)/6 = 4/3.
    EXPECT_NEAR(*m.spl, 4.0 / 3.0, kTol);
    // Over all 7 nodes: centre of B on 3 pairs → 3 · 2/(6·5) = 1/5 → cpd = 6·(1/5)/6 = 1/5.
    EXPECT_NEAR(*m.cpd, 0.2, kTol);
    // Ends (1,1), 3×(3,1): M = 8, Σx = 14, Σx² = 32, Σxy = 2·(1 + 9) = 20 → (160 − 196)/(256 − 196) = −0.6.
    EXPECT_NEAR(*m.r_k, -0.6, kTol);
}

TEST(GraphMetrics, LengthEntropyBinsAreClosedBelowAndRobustToRoundOff) {
    // A star whose arms are 1, 1, 2, 5, 10 m; the first is a vertical zigzag of ten 0.1 m edges, whose
    // lengths sum to 0.9999999999999999 (10·l/l_max = 0.9999999999999998 without the edge tolerance).
    // Normalised 10, 10, 20, 50, 100 → bins 1, 1, 2, 5, 9 (100 in the last bin).
    std::vector<std::array<double, 3>> p{{0, 0, 0}};
    std::vector<std::array<int, 2>> e;
    for (int k = 1; k <= 10; ++k) {
        p.push_back({0, 0, 0.1 * (k % 2)});
        e.push_back({k - 1, k});
    }
    auto arm = [&](std::array<double, 3> tip) {
        p.push_back(tip);
        e.push_back({0, int(p.size()) - 1});
    };
    arm({0, 1, 0});
    arm({-2, 0, 0});
    arm({0, -5, 0});
    arm({0, 0, 10});
    const GraphMetrics m = computeGraphMetrics(makeSkeleton(p, e));
    EXPECT_NEAR(*m.h_len, H({2, 1, 1, 1}, 10), kTol);
    EXPECT_NEAR(*m.len_mean_m, 19.0 / 5.0, kTol);
    // The zigzag ends where it starts (chord 0): left out of the tortuosity; the other four are straight.
    EXPECT_NEAR(*m.tortuosity, 1.0, kTol);
}

TEST(GraphMetrics, OrientationEntropyZeroForOneAzimuthVerticalEdgesIgnored) {
    // A zigzag in plan along azimuth 45° (dx = dy) at varying slopes, plus two vertical edges.
    const Skeleton s = makeSkeleton({{0, 0, 0}, {1, 1, 0.3}, {3, 3, 0.3}, {4, 4, -2}, {4, 4, 5}, {4, 4, 9}},
                                    {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}});
    EXPECT_NEAR(*computeGraphMetrics(s).h_or, 0.0, kTol);
    // Only vertical edges: no azimuth at all → undefined.
    const Skeleton shaft = makeSkeleton({{0, 0, 0}, {0, 0, 1}, {0, 0, 3}}, {{0, 1}, {1, 2}});
    EXPECT_FALSE(computeGraphMetrics(shaft).h_or.has_value());
}

TEST(GraphMetrics, OrientationEntropyOneWhenSpreadEvenlyOverTheBins) {
    // 36 arms from the origin at azimuths 5°, 15°, …, 355° (folded: every 10° bin twice), each of
    // horizontal length 2 m but with different dips, plus a vertical arm that must not count.
    std::vector<std::array<double, 3>> p{{0, 0, 0}};
    std::vector<std::array<int, 2>> e;
    for (int k = 0; k < 36; ++k) {
        const double az = (5.0 + 10.0 * k) * kPi / 180.0;
        p.push_back({2 * std::sin(az), 2 * std::cos(az), 0.1 * k});
        e.push_back({0, k + 1});
    }
    p.push_back({0, 0, -7});
    e.push_back({0, 37});
    EXPECT_NEAR(*computeGraphMetrics(makeSkeleton(p, e)).h_or, 1.0, kTol);
}

TEST(GraphMetrics, AxisAlignedShareWeighsHorizontalLengthNearTheAxes) {
    // From the origin: 2 m along +x, 1 m at 4° off −y (aligned), 3 m at 30° (not), 4 m at 6° off +y
    // (not), 1 m at exactly 5° (aligned: the bound is inclusive) and 5 m straight down (no weight).
    const auto arm = [](double deg, double len, double dz) {
        const double a = deg * kPi / 180.0;
        return std::array<double, 3>{len * std::cos(a), len * std::sin(a), dz};
    };
    const Skeleton s = makeSkeleton(
        {{0, 0, 0}, arm(0, 2, 0), arm(-86, 1, 0.5), arm(30, 3, -1), arm(84, 4, 2), arm(185, 1, 0), {0, 0, -5}},
        {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}, {0, 6}});
    EXPECT_NEAR(*axisAlignedShare(s), (2.0 + 1.0 + 1.0) / 11.0, kTol);
    EXPECT_NEAR(*computeGraphMetrics(s).axis_aligned_share, 4.0 / 11.0, kTol);
    EXPECT_NEAR(*axisAlignedShare(s, 45.0), 1.0, kTol);
    EXPECT_NEAR(*axisAlignedShare(s, 0.0), 2.0 / 11.0, kTol);

    // Edges spread evenly over all azimuths (1° apart, half a degree off the axes): 40 of 360 aligned.
    std::vector<std::array<double, 3>> p{{0, 0, 0}};
    std::vector<std::array<int, 2>> e;
    for (int k = 0; k < 360; ++k) {
        p.push_back(arm(0.5 + k, 1.0, 0));
        e.push_back({0, k + 1});
    }
    EXPECT_NEAR(*axisAlignedShare(makeSkeleton(p, e)), 40.0 / 360.0, kTol);

    EXPECT_FALSE(axisAlignedShare(makeSkeleton({{0, 0, 0}, {0, 0, 3}}, {{0, 1}})).has_value());
    EXPECT_THROW(axisAlignedShare(s, 46.0), InternalError);
}

TEST(GraphMetrics, OrientationEntropyWeightsByHorizontalLength) {
    // 1 m along azimuth 0°, 3 m along 90° (one edge dips, its horizontal part counts), 2 m straight up.
    const Skeleton s = makeSkeleton({{0, 0, 0}, {0, 1, 0}, {3, 1, 4}, {3, 1, 6}}, {{0, 1}, {1, 2}, {2, 3}});
    EXPECT_NEAR(*computeGraphMetrics(s).h_or, H({1, 3}, 18), kTol);
}

TEST(GraphMetrics, EmptyAndSingleNode) {
    const GraphMetrics empty = computeGraphMetrics(Skeleton{});
    for (const auto* v : {&empty.k_mean, &empty.r_k, &empty.spl, &empty.cpd, &empty.h_or, &empty.len_mean_m,
                          &empty.cv_len, &empty.h_len, &empty.tortuosity})
        EXPECT_FALSE(v->has_value());
    EXPECT_EQ(empty.branches, 0);
    EXPECT_EQ(empty.components, 0);
    EXPECT_EQ(empty.reduced_nodes, 0);

    const GraphMetrics one = computeGraphMetrics(makeSkeleton({{1, 2, 3}}, {}));
    EXPECT_DOUBLE_EQ(*one.k_mean, 0.0);
    EXPECT_FALSE(one.r_k.has_value());
    EXPECT_FALSE(one.spl.has_value());
    EXPECT_FALSE(one.cpd.has_value());
    EXPECT_FALSE(one.len_mean_m.has_value());
    EXPECT_EQ(one.components, 1);
    EXPECT_EQ(one.reduced_nodes, 1);
    EXPECT_EQ(one.loops, 0);

    // Two nodes at the same place: a branch of length 0 has no normalised length, cv or tortuosity.
    const GraphMetrics dot = computeGraphMetrics(makeSkeleton({{1, 1, 1}, {1, 1, 1}}, {{0, 1}}));
    EXPECT_DOUBLE_EQ(*dot.len_mean_m, 0.0);
    EXPECT_FALSE(dot.h_len.has_value());
    EXPECT_FALSE(dot.tortuosity.has_value());
    EXPECT_FALSE(dot.h_or.has_value());
    EXPECT_DOUBLE_EQ(*dot.cpd, 0.0);
}

/// A star of `leaves` one-metre arms: `leaves` branches.
Skeleton star(int leaves) {
    std::vector<std::array<double, 3>> pos{{0, 0, 0}};
    std::vector<std::array<int, 2>> edges;
    for (int l = 0; l < leaves; ++l) {
        const double a = 2 * kPi * l / leaves;
        pos.push_back({std::cos(a), std::sin(a), 0});
        edges.push_back({0, l + 1});
    }
    return makeSkeleton(pos, edges);
}

TEST(GraphMetrics, FewerThanTenBranchesIsTooSmallForNetworkStatistics) {
    const GraphMetrics nine = computeGraphMetrics(star(9));
    EXPECT_EQ(nine.branches, 9);
    EXPECT_TRUE(nine.too_small);
    EXPECT_TRUE(toJson(nine)["too_small"].get<bool>());
    const GraphMetrics ten = computeGraphMetrics(star(10));
    EXPECT_EQ(ten.branches, 10);
    EXPECT_FALSE(ten.too_small);
    EXPECT_FALSE(toJson(ten)["too_small"].get<bool>());
    EXPECT_TRUE(computeGraphMetrics(Skeleton{}).too_small);
}

TEST(GraphMetrics, JsonHasTheDesignKeysAndNullForUndefined) {
    const nlohmann::json j = toJson(computeGraphMetrics(line()));
    for (const char* key : {"k_mean", "r_k", "spl", "cpd", "h_or", "len_mean_m", "cv_len", "h_len", "tortuosity"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_TRUE(j["cv_len"].is_null());
    EXPECT_DOUBLE_EQ(j["len_mean_m"].get<double>(), 4.0);
    EXPECT_EQ(j["branches"].get<long>(), 1);
    EXPECT_EQ(j["reduced_edges"].get<long>(), 1);
    // No NaN can reach the JSON (nlohmann would write null silently, so check the struct's values).
    const GraphMetrics e = computeGraphMetrics(Skeleton{});
    const nlohmann::json je = toJson(e);
    EXPECT_TRUE(je["k_mean"].is_null());
    EXPECT_TRUE(je["tortuosity"].is_null());

    // The real-cave ranges are listed under the same keys, in the same order.
    std::vector<std::string> keys;
    for (const auto& r : realCaveRanges()) {
        keys.push_back(r.key);
        EXPECT_LT(r.low, r.high);
        EXPECT_TRUE(j.contains(r.key));
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"k_mean", "r_k", "spl", "cpd", "h_or", "len_mean_m", "cv_len", "h_len",
                                              "tortuosity"}));
    EXPECT_TRUE(j.contains("axis_aligned_share"));
}

TEST(GraphMetrics, BadSkeletonThrows) {
    EXPECT_THROW(computeGraphMetrics(makeSkeleton({{0, 0, 0}, {1, 0, 0}}, {{0, 2}})), InternalError);
    EXPECT_THROW(computeGraphMetrics(makeSkeleton({{0, 0, 0}, {1, 0, 0}}, {{-1, 1}})), InternalError);
    EXPECT_THROW(computeGraphMetrics(makeSkeleton({{0, 0, 0}, {1, 0, 0}}, {{1, 1}})), InternalError);
    EXPECT_THROW(computeGraphMetrics(makeSkeleton({{0, 0, 0}, {1, 0, 0}}, {{0, 1}, {1, 0}})), InternalError);
    EXPECT_THROW(computeGraphMetrics(makeSkeleton({{0, 0, 0}, {std::nan(""), 0, 0}}, {{0, 1}})), InternalError);
    EXPECT_THROW(findBranches(makeSkeleton({{0, 0, 0}}, {{0, 1}})), InternalError);
    EXPECT_THROW(reduceSkeleton(makeSkeleton({{0, 0, 0}}, {{0, 0}})), InternalError);
}

TEST(GraphMetrics, RandomGraphsGiveMetricsInTheirRanges) {
    // Random sparse graphs (trees plus a few chords, several components): every defined value is
    // finite and inside its mathematical range; the reduced graph is simple.
    std::mt19937 rng(11);
    for (int trial = 0; trial < 40; ++trial) {
        const int n = 2 + int(rng() % 60);
        std::vector<std::array<double, 3>> p;
        std::uniform_real_distribution<double> u(-10, 10);
        for (int v = 0; v < n; ++v) p.push_back({u(rng), u(rng), u(rng)});
        std::set<std::pair<int, int>> edges;
        for (int v = 1; v < n; ++v)
            if (rng() % 8) edges.insert({int(rng() % unsigned(v)), v});
        for (int c = 0; c < n / 6; ++c) {
            const int a = int(rng() % unsigned(n)), b = int(rng() % unsigned(n));
            if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
        }
        std::vector<std::array<int, 2>> e;
        for (const auto& [a, b] : edges) e.push_back({a, b});
        const Skeleton s = makeSkeleton(p, e);
        const ReducedGraph g = reduceSkeleton(s);
        std::set<std::array<int, 2>> unique(g.edges.begin(), g.edges.end());
        EXPECT_EQ(unique.size(), g.edges.size());
        for (const auto& re : g.edges) EXPECT_LT(re[0], re[1]);
        const GraphMetrics m = computeGraphMetrics(s);
        EXPECT_EQ(m.loops, long(e.size()) - n + m.components);
        if (m.r_k) {
            EXPECT_TRUE(*m.r_k >= -1 - 1e-12 && *m.r_k <= 1 + 1e-12);
        }
        if (m.cpd) {
            EXPECT_TRUE(*m.cpd >= -1e-12 && *m.cpd <= 1 + 1e-12);
        }
        // Oracle: Boost's Brandes + relative_betweenness_centrality + central_point_dominance.
        if (g.nodes.size() >= 3) {
            using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS>;
            Graph bg(g.nodes.size());
            for (const auto& re : g.edges) boost::add_edge(std::size_t(re[0]), std::size_t(re[1]), bg);
            std::vector<double> c(g.nodes.size());
            auto map = boost::make_iterator_property_map(c.begin(), boost::get(boost::vertex_index, bg));
            boost::brandes_betweenness_centrality(bg, map);
            boost::relative_betweenness_centrality(bg, map);
            EXPECT_NEAR(*m.cpd, boost::central_point_dominance(bg, map), 1e-12);
        }
        if (m.h_or) {
            EXPECT_TRUE(*m.h_or >= 0 && *m.h_or <= 1 + 1e-12);
        }
        if (m.h_len) {
            EXPECT_TRUE(*m.h_len >= 0 && *m.h_len <= 1 + 1e-12);
        }
        if (m.tortuosity) {
            EXPECT_GE(*m.tortuosity, 1 - 1e-12);
        }
        if (m.spl) {
            EXPECT_GE(*m.spl, 1 - 1e-12);
        }
        // Branches partition the edges.
        std::size_t covered = 0;
        for (const auto& b : findBranches(s)) covered += b.nodes.size() - 1;
        EXPECT_EQ(covered, e.size());
    }
}

// Above kExactPairsNodes reduced nodes, spl and cpd come from a fixed sample of BFS sources: on a
// 17×17×17 grid graph (4,913 junctions) the estimate of spl lies within 1 % of the exact value,
// m⁵(m² − 1) / (N(N − 1)) for N = m³ nodes (the mean Manhattan distance between distinct nodes),
// cpd stays in [0, 1], and the bits do not depend on the thread count.
TEST(GraphMetrics, LargeGraphsAreEstimatedFromASampleOfSources) {
    const int m = 17;
    Skeleton s;
    auto id = [](int i, int j, int k) { return i + m * (j + m * k); };
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                s.nodes.push_back({{double(i), double(j), double(k)}, 0.5, 0});
                if (i + 1 < m) s.edges.push_back({id(i, j, k), id(i + 1, j, k)});
                if (j + 1 < m) s.edges.push_back({id(i, j, k), id(i, j + 1, k)});
                if (k + 1 < m) s.edges.push_back({id(i, j, k), id(i, j, k + 1)});
            }
    GraphMetrics one, two;
    tbb::task_arena(1).execute([&] { one = computeGraphMetrics(s); });
    tbb::task_arena(2).execute([&] { two = computeGraphMetrics(s); });
    EXPECT_EQ(toJson(one).dump(), toJson(two).dump());
    const double nodes = double(m) * m * m;
    ASSERT_GT(nodes, kExactPairsNodes);
    EXPECT_EQ(one.reduced_nodes, long(nodes));
    EXPECT_EQ(one.pair_sources, kPairSources);
    const double exact = std::pow(m, 5) * (m * m - 1) / (nodes * (nodes - 1));
    ASSERT_TRUE(one.spl && one.cpd);
    EXPECT_NEAR(*one.spl, exact, 0.01 * exact);
    EXPECT_GE(*one.cpd, 0.0);
    EXPECT_LE(*one.cpd, 1.0);
    // Below the limit every node is a source.
    EXPECT_EQ(computeGraphMetrics(lattice3()).pair_sources, computeGraphMetrics(lattice3()).reduced_nodes);
}

}  // namespace
}  // namespace cavesim::morpho
