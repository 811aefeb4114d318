// Max flow against hand-computed minimum cuts, flow conservation and capacity bounds, agreement of
// Boykov–Kolmogorov, Edmonds–Karp and the least-resistance solver, least-resistance routing, and
// flow-cycle cancellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "test_util.h"

namespace cavesim::flownet {
namespace {

Grid3<float> randomPorosity(const Dims& d, unsigned seed, float lo = 0.02f, float hi = 0.3f) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    Grid3<float> g(d);
    for (auto& r : g.data) r = u(gen);
    return g;
}

/// Every voxel on the grid's outer faces except the sources.
std::vector<std::size_t> outerFaces(const Dims& d, const std::vector<std::size_t>& sources) {
    std::vector<std::size_t> out;
    for (std::size_t v = 0; v < d.count(); ++v) {
        const Index3 p = d.coord(v);
        const bool face =
            p.i == 0 || p.i == d.nx - 1 || (d.ny > 1 && (p.j == 0 || p.j == d.ny - 1)) || p.k == 0 || p.k == d.nz - 1;
        if (face && std::find(sources.begin(), sources.end(), v) == sources.end()) out.push_back(v);
    }
    return out;
}

/// Conservation at every voxel node, antisymmetry, capacity bounds, value = what leaves the source.
void expectValidFlow(const FlowNetwork& net, const MaxFlowResult& r, double tol = 1e-12) {
    ASSERT_EQ(r.flow.size(), net.arcCount());
    double scale = 1;
    for (ArcId a = 0; a < net.arcCount(); ++a) {
        EXPECT_EQ(r.flow[a], -r.flow[net.arcReverse[a]]) << "arc " << a;
        EXPECT_LE(r.flow[a], net.capacity[a] + tol) << "arc " << a;
        if (net.arcTarget[a] < net.voxelNodes) scale = std::max(scale, net.capacity[a]);
    }
    const std::vector<double> in = netInflow(net, r);
    for (std::size_t v = 0; v < net.voxelNodes; ++v) EXPECT_NEAR(in[v], 0.0, tol * scale * 10) << "node " << v;
    EXPECT_NEAR(in[net.source], -r.value, tol * 10);
    EXPECT_NEAR(in[net.sink], r.value, tol * 10);
}

/// True when the arcs with positive flow form no directed cycle (Kahn's algorithm).
bool positiveFlowIsAcyclic(const FlowNetwork& net, const MaxFlowResult& r) {
    std::vector<int> indeg(net.nodeCount(), 0);
    for (std::size_t v = 0; v < net.nodeCount(); ++v)
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a)
            if (r.flow[a] > 0) ++indeg[net.arcTarget[a]];
    std::vector<NodeId> queue;
    for (std::size_t v = 0; v < net.nodeCount(); ++v)
        if (indeg[v] == 0) queue.push_back(NodeId(v));
    std::size_t seen = 0;
    while (!queue.empty()) {
        const NodeId v = queue.back();
        queue.pop_back();
        ++seen;
        for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a)
            if (r.flow[a] > 0 && --indeg[net.arcTarget[a]] == 0) queue.push_back(net.arcTarget[a]);
    }
    return seen == net.nodeCount();
}

TEST(MaxFlow, TextbookNetworkHasCutOf23) {
    // Cormen et al. Figure 26.1: s=0, v1..v4 = 1..4, t=5; maximum flow 23. s feeds, t drains.
    const std::vector<ArcSpec> arcs{{0, 1, 16}, {0, 2, 13}, {1, 3, 12}, {2, 1, 4}, {2, 4, 14},
                                    {3, 2, 9},  {3, 5, 20}, {4, 3, 7},  {4, 5, 4}};
    const FlowNetwork net = flowNetworkFromArcs(6, arcs, {0}, {5});
    for (const auto alg : {MaxFlowAlgorithm::BoykovKolmogorov, MaxFlowAlgorithm::EdmondsKarp}) {
        const MaxFlowResult r = maxFlow(net, alg);
        EXPECT_DOUBLE_EQ(r.value, 23.0);
        expectValidFlow(net, r);
    }
    const MaxFlowResult lr = leastResistanceMaxFlow(net);
    EXPECT_DOUBLE_EQ(lr.value, 23.0);
    expectValidFlow(net, lr);
}

TEST(MaxFlow, ChainIsLimitedByItsTightestLink) {
    const Dims d{6, 1, 1};
    Grid3<float> R(d);
    R.data = {0.3f, 0.2f, 0.25f, 0.05f, 0.4f, 0.1f};
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {0}, {5});
    EXPECT_EQ(net.voxelEdgeCount(), 5u);
    // Links: min(.3,.2)=.2, .2, .05, .05, .1 → the cut is 0.05.
    for (const auto alg : {MaxFlowAlgorithm::BoykovKolmogorov, MaxFlowAlgorithm::EdmondsKarp}) {
        const MaxFlowResult r = maxFlow(net, alg);
        EXPECT_NEAR(r.value, 0.05, 1e-7);
        expectValidFlow(net, r);
    }
    EXPECT_NEAR(leastResistanceMaxFlow(net).value, 0.05, 1e-7);
}

TEST(MaxFlow, PointSourceInAPlaneIsCutAtItsFourLinks) {
    // 5 × 1 × 5 section, porosity 0.1, source in the middle, protosinks on the rim: the smallest
    // cut is the source's 4 links (0.4); the ring around it has 12 links (1.2).
    const Dims d{5, 1, 5};
    const Grid3<float> R(d, 0.1f);
    const std::size_t src = d.index(2, 0, 2);
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, outerFaces(d, {src}), face6());
    for (const auto alg : {MaxFlowAlgorithm::BoykovKolmogorov, MaxFlowAlgorithm::EdmondsKarp}) {
        const MaxFlowResult r = maxFlow(net, alg);
        EXPECT_NEAR(r.value, 0.4, 1e-7);
        expectValidFlow(net, r);
    }
}

TEST(MaxFlow, LowPorositySlabIsTheMinimumCut) {
    // Source face x = 0, protosink face x = 3, a slab x = 2 of porosity 0.05 with one voxel at
    // 0.1; elsewhere 0.2. The 9 links into the slab are the cut: 8·0.05 + 0.1 = 0.5; with
    // capacity exponent 2 it is 8·0.0025 + 0.01 = 0.03.
    const Dims d{4, 3, 3};
    Grid3<float> R(d, 0.2f);
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) R.at(2, j, k) = 0.05f;
    R.at(2, 1, 1) = 0.1f;
    std::vector<std::size_t> src, snk;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) {
            src.push_back(d.index(0, j, k));
            snk.push_back(d.index(3, j, k));
        }
    FlowNetworkOptions o = face6();
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), src, snk, o);
    EXPECT_EQ(net.voxelEdgeCount(), 3u * 9u + 4u * 3u * 3u);  // 27 along x, 12 per slice in y–z
    EXPECT_NEAR(maxFlow(net).value, 0.5, 1e-6);
    EXPECT_NEAR(maxFlow(net, MaxFlowAlgorithm::EdmondsKarp).value, 0.5, 1e-6);
    EXPECT_NEAR(leastResistanceMaxFlow(net).value, 0.5, 1e-6);
    o.capacityExponent = 2;
    const FlowNetwork net2 = buildFlowNetwork(R, allVoxels(d), src, snk, o);
    EXPECT_NEAR(maxFlow(net2).value, 0.03, 1e-7);
}

TEST(MaxFlow, AlgorithmsAgreeAndFlowsAreValidOnRandomGrids) {
    for (unsigned seed = 1; seed <= 6; ++seed) {
        const Dims d{9, seed % 2 ? 1 : 7, 8};
        const Grid3<float> R = randomPorosity(d, seed);
        const std::size_t src = d.index(4, d.ny / 2, 4);
        const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, outerFaces(d, {src}));
        const MaxFlowResult bk = maxFlow(net, MaxFlowAlgorithm::BoykovKolmogorov);
        const MaxFlowResult ek = maxFlow(net, MaxFlowAlgorithm::EdmondsKarp);
        const MaxFlowResult lr = leastResistanceMaxFlow(net);
        EXPECT_GT(bk.value, 0);
        EXPECT_NEAR(bk.value, ek.value, 1e-9) << "seed " << seed;
        EXPECT_NEAR(bk.value, lr.value, 1e-9) << "seed " << seed;
        expectValidFlow(net, bk);
        expectValidFlow(net, ek);
        expectValidFlow(net, lr);
        // Least resistance: never more resistance than the routings of the plain solvers (with
        // the protosinks not equalised, so that the objective is the resistance itself).
        LeastResistanceOptions exact;
        exact.tolerance = 0;
        exact.equalizeProtosinks = false;
        const MaxFlowResult lr0 = leastResistanceMaxFlow(net, exact);
        EXPECT_NEAR(lr0.value, bk.value, 1e-9);
        expectValidFlow(net, lr0);
        EXPECT_LE(lr0.cost, bk.cost * (1 + 1e-9));
        EXPECT_LE(lr0.cost, ek.cost * (1 + 1e-9));
    }
}

TEST(MaxFlow, LeastResistanceTakesTheCheaperOfTwoRoutes) {
    // Source 0 → {1 (resistance 1), 2 (resistance 5)} → 3 → protosink 4; node 3 → 4 carries at
    // most 1, so only one unit flows and it must take the cheap route: cost 1 + 1 = 2.
    const std::vector<ArcSpec> arcs{{0, 1, 1, 1}, {1, 3, 1, 1}, {0, 2, 1, 5}, {2, 3, 1, 5}, {3, 4, 1, 0}};
    const FlowNetwork net = flowNetworkFromArcs(5, arcs, {0}, {4});
    const MaxFlowResult r = leastResistanceMaxFlow(net);
    EXPECT_DOUBLE_EQ(r.value, 1.0);
    EXPECT_DOUBLE_EQ(r.cost, 2.0);
    expectValidFlow(net, r);
}

TEST(MaxFlow, LeastResistanceFollowsAPorousFracture) {
    // 2D section: source at the left, protosink column at the right edge; a row of porosity 0.3
    // (a fracture) one voxel below the source. Least-resistance flow drops into the fracture near
    // the source, runs along it and leaves it only next to the protosinks.
    const Dims d{12, 1, 5};
    Grid3<float> R(d, 0.05f);
    for (int i = 0; i < d.nx; ++i) R.at(i, 0, 1) = 0.3f;
    const std::size_t src = d.index(0, 0, 2);
    std::vector<std::size_t> snk;
    for (int k = 0; k < d.nz; ++k) snk.push_back(d.index(d.nx - 1, 0, k));
    FlowNetworkOptions o = face6();
    o.protosinkShare = 0.5;
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, snk, o);
    const MaxFlowResult r = leastResistanceMaxFlow(net);
    expectValidFlow(net, r);
    // Total protosink capacity = 0.5 × source cut (links to (1,2), (0,1), (0,3): 0.05 each).
    EXPECT_NEAR(r.value, 0.5 * 3 * double(0.05f), 1e-15);
    // All flow reaching the right edge arrives through the fracture row.
    const std::vector<double> through = throughFlow(net, r);
    const auto node = [&](int i, int k) { return std::size_t(nodeOfVoxel(net, d.index(i, 0, k))); };
    for (int i = 2; i < d.nx - 2; ++i) {
        EXPECT_NEAR(through[node(i, 1)], r.value, 1e-12) << "x = " << i;
        for (int k : {0, 2, 3, 4}) EXPECT_LE(through[node(i, k)], 1e-12) << "x = " << i << " z = " << k;
    }
}

TEST(MaxFlow, ProtosinkShareCapsTheFlowAndFeedsEveryProtosink) {
    const Dims d{11, 1, 11};
    const Grid3<float> R = randomPorosity(d, 9, 0.04f, 0.08f);
    const std::size_t src = d.index(5, 0, 5);
    std::vector<std::size_t> snk;  // the rim without its corners, which have no link inward
    for (std::size_t v : outerFaces(d, {src})) {
        const Index3 p = d.coord(v);
        if (!((p.i == 0 || p.i == 10) && (p.k == 0 || p.k == 10))) snk.push_back(v);
    }
    FlowNetworkOptions o = face6();
    o.protosinkShare = 0.5;
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, snk, o);
    double cut = 0, sinkCap = 0;
    const NodeId s = NodeId(nodeOfVoxel(net, src));
    for (ArcId a = net.arcBegin[s]; a < net.arcBegin[s + 1]; ++a)
        if (net.arcTarget[a] < net.voxelNodes) cut += net.capacity[a];
    for (NodeId p : net.protosinks) sinkCap += net.capacity[net.arcBegin[p + 1] - 1];
    EXPECT_NEAR(sinkCap, 0.5 * cut, 1e-12);
    const MaxFlowResult r = leastResistanceMaxFlow(net);
    EXPECT_EQ(r.phases, 1);                // equalised protosinks: one phase routes everything
    EXPECT_NEAR(r.value, sinkCap, 1e-12);  // nothing inside binds: every protosink is saturated
    for (NodeId p : net.protosinks) {
        const ArcId a = net.arcBegin[p + 1] - 1;
        EXPECT_NEAR(r.flow[a], net.capacity[a], 1e-12);
    }
    // When every protosink is fed, equalising changes nothing but the number of phases.
    LeastResistanceOptions plain;
    plain.equalizeProtosinks = false;
    const MaxFlowResult q = leastResistanceMaxFlow(net, plain);
    EXPECT_GT(q.phases, 1);
    EXPECT_NEAR(q.value, r.value, 1e-12);
    EXPECT_NEAR(q.cost, r.cost, 1e-3 * r.cost);
}

TEST(MaxFlow, CycleCancellationKeepsValueAndLeavesADag) {
    // A hand-made circulation 1 → 2 → 3 → 1 on top of a path 0 → 1 → 4.
    const std::vector<ArcSpec> arcs{{0, 1, 2}, {1, 2, 1}, {2, 3, 1}, {3, 1, 1}, {1, 4, 2}};
    const FlowNetwork net = flowNetworkFromArcs(5, arcs, {0}, {4});
    MaxFlowResult r = maxFlow(net);
    ASSERT_DOUBLE_EQ(r.value, 2.0);
    const auto setFlow = [&](NodeId u, NodeId v, double f) {
        for (ArcId a = net.arcBegin[u]; a < net.arcBegin[u + 1]; ++a)
            if (net.arcTarget[a] == v) {
                r.flow[a] = f;
                r.flow[net.arcReverse[a]] = -f;
            }
    };
    setFlow(1, 2, 0.75);
    setFlow(2, 3, 0.75);
    setFlow(3, 1, 0.75);
    expectValidFlow(net, r);
    EXPECT_FALSE(positiveFlowIsAcyclic(net, r));
    EXPECT_EQ(cancelFlowCycles(net, r), 1u);
    EXPECT_TRUE(positiveFlowIsAcyclic(net, r));
    EXPECT_DOUBLE_EQ(r.value, 2.0);
    expectValidFlow(net, r);

    for (unsigned seed = 1; seed <= 4; ++seed) {  // and on solver output
        const Dims d{10, 6, 7};
        const Grid3<float> R2 = randomPorosity(d, 100 + seed);
        const std::size_t src = d.index(5, 3, 3);
        const FlowNetwork g = buildFlowNetwork(R2, allVoxels(d), {src}, outerFaces(d, {src}));
        MaxFlowResult f = maxFlow(g);
        const double value = f.value;
        cancelFlowCycles(g, f);
        EXPECT_TRUE(positiveFlowIsAcyclic(g, f));
        EXPECT_EQ(f.value, value);
        expectValidFlow(g, f);
    }
}

TEST(MaxFlow, NoSourcesOrNoProtosinksGiveZeroFlow) {
    const Dims d{3, 3, 3};
    const Grid3<float> R(d, 0.1f);
    EXPECT_EQ(maxFlow(buildFlowNetwork(R, allVoxels(d), {}, {0}, face6())).value, 0.0);
    EXPECT_EQ(leastResistanceMaxFlow(buildFlowNetwork(R, allVoxels(d), {13}, {}, face6())).value, 0.0);
    // Source walled in by porosity 0: no link, no flow.
    Grid3<float> walled(d, 0.0f);
    walled[13] = 0.5f;
    walled[0] = 0.5f;
    const FlowNetwork net = buildFlowNetwork(walled, allVoxels(d), {13}, {0}, face6());
    EXPECT_EQ(net.voxelEdgeCount(), 0u);
    EXPECT_EQ(leastResistanceMaxFlow(net).value, 0.0);
    EXPECT_EQ(maxFlow(net).value, 0.0);
}

TEST(MaxFlow, BadOptionsThrow) {
    const FlowNetwork net = flowNetworkFromArcs(2, {{0, 1, 1, 1}}, {0}, {1});
    LeastResistanceOptions o;
    o.tolerance = -1;
    EXPECT_THROW(leastResistanceMaxFlow(net, o), InternalError);
    o = {};
    o.maxPhases = 0;
    EXPECT_THROW(leastResistanceMaxFlow(net, o), InternalError);
    FlowNetwork broken = net;
    broken.capacity.pop_back();
    EXPECT_THROW(maxFlow(broken), InternalError);
}

TEST(MaxFlow, PhaseLimitStillGivesTheMaximumFlow) {
    const Dims d{9, 7, 8};
    const Grid3<float> R = randomPorosity(d, 77);
    const std::size_t src = d.index(4, 3, 4);
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, outerFaces(d, {src}));
    LeastResistanceOptions o;
    o.maxPhases = 1;
    const MaxFlowResult one = leastResistanceMaxFlow(net, o);
    EXPECT_NEAR(one.value, maxFlow(net).value, 1e-9);
    expectValidFlow(net, one);
}

TEST(MaxFlow, LeastResistanceCallsBeforeEveryPhaseAndStopsWhenItThrows) {
    const Dims d{9, 7, 8};
    const Grid3<float> R = randomPorosity(d, 3);
    const std::size_t src = d.index(4, 3, 4);
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {src}, outerFaces(d, {src}));
    int calls = 0;
    LeastResistanceOptions counted;
    counted.beforePhase = [&] { ++calls; };
    const MaxFlowResult r = leastResistanceMaxFlow(net, counted);
    const MaxFlowResult plain = leastResistanceMaxFlow(net);
    ASSERT_GT(r.phases, 1);
    // Once before each phase, and once more before the search that finds no augmenting path.
    EXPECT_GE(calls, r.phases);
    EXPECT_LE(calls, r.phases + 1);
    EXPECT_EQ(r.flow, plain.flow);  // the callback changes nothing
    int seen = 0;
    LeastResistanceOptions stop;
    stop.beforePhase = [&] {
        if (++seen == 2) throw Cancelled("test");
    };
    EXPECT_THROW(leastResistanceMaxFlow(net, stop), Cancelled);
    EXPECT_EQ(seen, 2);
}

}  // namespace
}  // namespace cavesim::flownet
