// Protochannel tracing: exact trees on hand-made flows, the joining rule on parallel flow, the
// gathering threshold, and the tree invariants (rooted at a source, face-connected, acyclic,
// only voxels that carry flow, never a protosink) on random zones.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "core/error.h"
#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "flownet/protochannels.h"
#include "test_util.h"

namespace cavesim::flownet {
namespace {

ProtochannelTree solveAndTrace(const FlowNetwork& net, const TraceOptions& o = {}) {
    MaxFlowResult r = leastResistanceMaxFlow(net);
    cancelFlowCycles(net, r);
    return traceProtochannels(net, r, o);
}

bool linked(const FlowNetwork& net, NodeId a, NodeId b) {
    for (ArcId e = net.arcBegin[a]; e < net.arcBegin[a + 1]; ++e)
        if (net.arcTarget[e] == b) return true;
    return false;
}

/// Every marked node drains along parent links, between linked nodes, to a source node.
void expectTreeRootedAtSources(const FlowNetwork& net, const ProtochannelTree& t) {
    ASSERT_EQ(t.nodes.size(), t.parent.size());
    std::vector<std::int64_t> parentOf(net.voxelNodes, -1);
    std::set<NodeId> sources(net.sources.begin(), net.sources.end());
    std::set<NodeId> protosinks(net.protosinks.begin(), net.protosinks.end());
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
        ASSERT_EQ(parentOf[t.nodes[i]], -1) << "node marked twice";
        EXPECT_FALSE(sources.count(t.nodes[i]));
        EXPECT_FALSE(protosinks.count(t.nodes[i])) << "a protosink was marked";
        EXPECT_TRUE(linked(net, t.nodes[i], t.parent[i]));
        parentOf[t.nodes[i]] = t.parent[i];
    }
    for (NodeId v : t.nodes) {
        NodeId u = v;
        std::size_t steps = 0;
        while (!sources.count(u)) {
            ASSERT_GE(parentOf[u], 0) << "parent " << u << " is neither marked nor a source";
            u = NodeId(parentOf[u]);
            ASSERT_LE(++steps, t.nodes.size()) << "cycle";
        }
    }
}

TEST(Protochannels, ChainIsOneBranchFromSinkToSource) {
    const Dims d{7, 1, 1};
    const Grid3<float> R(d, 0.2f);
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {0}, {6});
    const ProtochannelTree t = solveAndTrace(net);
    EXPECT_EQ(t.nodes, (std::vector<NodeId>{5, 4, 3, 2, 1}));
    EXPECT_EQ(t.parent, (std::vector<NodeId>{4, 3, 2, 1, 0}));
    EXPECT_EQ(t.branches, 1u);
    EXPECT_EQ(t.protosinksWithFlow, 1u);
}

TEST(Protochannels, ParallelFlowJoinsIntoOneChannel) {
    // A corridor two voxels wide: two sources at one end, two protosinks at the other; each lane
    // carries the same flow. Without joining both lanes become channels (a 2-voxel slab); with
    // it the second lane's branch attaches to the first at once (1 voxel), and with
    // minBranchVoxels = 2 that stub is dropped.
    const Dims d{12, 1, 2};
    const Grid3<float> R(d, 0.1f);
    const std::vector<std::size_t> src{d.index(0, 0, 0), d.index(0, 0, 1)};
    const std::vector<std::size_t> snk{d.index(11, 0, 0), d.index(11, 0, 1)};
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), src, snk, face6());
    MaxFlowResult r = leastResistanceMaxFlow(net);
    cancelFlowCycles(net, r);
    EXPECT_NEAR(r.value, 0.2, 1e-6);

    TraceOptions plain;
    plain.joinOnContact = false;
    const ProtochannelTree slab = traceProtochannels(net, r, plain);
    EXPECT_EQ(slab.nodes.size(), 20u);
    expectTreeRootedAtSources(net, slab);

    const ProtochannelTree joined = traceProtochannels(net, r);
    EXPECT_EQ(joined.nodes.size(), 11u);
    EXPECT_EQ(joined.branches, 2u);
    expectTreeRootedAtSources(net, joined);
    for (int i = 1; i <= 10; ++i)  // the first lane (lower protosink id) is the trunk
        EXPECT_TRUE(std::count(joined.nodes.begin(), joined.nodes.end(), NodeId(nodeOfVoxel(net, d.index(i, 0, 0)))));

    TraceOptions noStubs;
    noStubs.minBranchVoxels = 2;
    const ProtochannelTree trimmed = traceProtochannels(net, r, noStubs);
    EXPECT_EQ(trimmed.nodes.size(), 10u);
    EXPECT_EQ(trimmed.branches, 1u);
}

TEST(Protochannels, GatheringThresholdKeepsOnlyArmsWithEnoughFlow) {
    // Star: source 0, four arms 0 → a → protosink, each carrying a quarter of the flow.
    const std::vector<ArcSpec> arcs{{0, 1, 1, 1}, {1, 2, 1, 1}, {0, 3, 1, 1}, {3, 4, 1, 1},
                                    {0, 5, 1, 1}, {5, 6, 1, 1}, {0, 7, 1, 1}, {7, 8, 1, 1}};
    const FlowNetwork net = flowNetworkFromArcs(9, arcs, {0}, {2, 4, 6, 8});
    TraceOptions o;
    o.minThroughFraction = 0.3;
    EXPECT_TRUE(solveAndTrace(net, o).nodes.empty());
    o.minThroughFraction = 0.2;
    const ProtochannelTree t = solveAndTrace(net, o);
    EXPECT_EQ(std::set<NodeId>(t.nodes.begin(), t.nodes.end()), (std::set<NodeId>{1, 3, 5, 7}));

    // A fork: everything passes node 1, then splits to protosinks 2 and 3 — at 60 % only the
    // trunk voxel is a channel.
    const FlowNetwork fork = flowNetworkFromArcs(4, {{0, 1, 2, 1}, {1, 2, 1, 1}, {1, 3, 1, 1}}, {0}, {2, 3});
    o.minThroughFraction = 0.6;
    const ProtochannelTree f = solveAndTrace(fork, o);
    EXPECT_EQ(f.nodes, (std::vector<NodeId>{1}));
    EXPECT_EQ(f.parent, (std::vector<NodeId>{0}));
}

TEST(Protochannels, RandomZonesGiveTreesRootedAtTheSource) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const Dims d{14, seed % 2 ? 1 : 12, 11};
        std::mt19937 gen(seed);
        std::uniform_real_distribution<float> u(0.03f, 0.08f);
        Grid3<float> R(d);
        for (auto& r : R.data) r = u(gen);
        const std::vector<std::size_t> src{d.index(7, d.ny / 2, 5)};
        std::vector<std::size_t> rim;
        for (std::size_t v = 0; v < d.count(); ++v) {
            const Index3 p = d.coord(v);
            if (p.i == 0 || p.i == d.nx - 1 || p.k == 0 || p.k == d.nz - 1 ||
                (d.ny > 1 && (p.j == 0 || p.j == d.ny - 1)))
                rim.push_back(v);
        }
        FlowNetworkOptions no;
        no.protosinkShare = 0.5;
        no.resistanceJitter = 0.5;
        no.jitterSeed = seed;
        const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), src, rim, no);
        MaxFlowResult r = leastResistanceMaxFlow(net);
        cancelFlowCycles(net, r);
        const std::vector<double> through = throughFlow(net, r);
        for (double frac : {0.0, 0.02, 0.1}) {
            TraceOptions o;
            o.minThroughFraction = frac;
            const ProtochannelTree t = traceProtochannels(net, r, o);
            EXPECT_FALSE(t.nodes.empty());
            expectTreeRootedAtSources(net, t);
            for (NodeId v : t.nodes) EXPECT_GT(through[v], 0.0);  // only voxels that carry flow
        }
        // The join rule never adds voxels.
        TraceOptions plain;
        plain.joinOnContact = false;
        EXPECT_LE(traceProtochannels(net, r).nodes.size(), traceProtochannels(net, r, plain).nodes.size());
    }
}

TEST(Protochannels, BadInputThrows) {
    const FlowNetwork net = flowNetworkFromArcs(2, {{0, 1, 1, 1}}, {0}, {1});
    MaxFlowResult r = maxFlow(net);
    TraceOptions o;
    o.minBranchVoxels = 0;
    EXPECT_THROW(traceProtochannels(net, r, o), InternalError);
    o = {};
    o.minThroughFraction = 2;
    EXPECT_THROW(traceProtochannels(net, r, o), InternalError);
    r.flow.pop_back();
    EXPECT_THROW(traceProtochannels(net, r), InternalError);
}

}  // namespace
}  // namespace cavesim::flownet
