// The least-resistance maximum flow gives, bit for bit, the flows of the previous solver (every
// phase over the whole network, kept in reference_least_resistance.h): on random voxel grids
// with either stencil, jitter and protosink shares, under several options, on random sparse
// networks, and on a network with parallel arcs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <set>
#include <string>

#include "flownet/flow_network.h"
#include "flownet/max_flow.h"
#include "reference_least_resistance.h"
#include "test_util.h"

namespace cavesim::flownet {
namespace {

/// Same bits in value, cost, phase count and every arc's flow.
void expectSameBits(const MaxFlowResult& want, const MaxFlowResult& got, const std::string& what) {
    ASSERT_EQ(want.flow.size(), got.flow.size()) << what;
    EXPECT_EQ(want.phases, got.phases) << what;
    EXPECT_EQ(std::memcmp(&want.value, &got.value, sizeof(double)), 0) << what << ": value";
    EXPECT_EQ(std::memcmp(&want.cost, &got.cost, sizeof(double)), 0) << what << ": cost";
    std::size_t differing = 0;
    for (std::size_t a = 0; a < want.flow.size(); ++a)
        differing += std::memcmp(&want.flow[a], &got.flow[a], sizeof(double)) != 0;
    EXPECT_EQ(differing, 0u) << what << ": arcs whose flow differs in some bit";
}

/// A zone-like block: noisy porosity (with a porous slab standing in for a bedding plane), one
/// or two sources inside, protosinks on the lower faces.
FlowNetwork zoneNetwork(const Dims& d, unsigned seed, const FlowNetworkOptions& o, bool twoSources) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<float> u(0.02f, 0.08f);
    Grid3<float> R(d);
    for (auto& r : R.data) r = u(gen);
    for (int i = 0; i < d.nx; ++i)
        for (int j = 0; j < d.ny; ++j) R.at(i, j, d.nz / 3) = 0.3f;
    std::vector<std::size_t> sources{d.index(d.nx / 2, d.ny / 2, d.nz - 2)};
    if (twoSources) sources.push_back(d.index(1, d.ny - 2, d.nz / 2));
    std::vector<std::size_t> rim;
    for (std::size_t v = 0; v < d.count(); ++v) {
        const Index3 p = d.coord(v);
        const bool face = p.i == 0 || p.j == 0 || p.k == 0 || p.i == d.nx - 1 || p.j == d.ny - 1;
        if (face && std::find(sources.begin(), sources.end(), v) == sources.end()) rim.push_back(v);
    }
    return buildFlowNetwork(R, allVoxels(d), sources, rim, o);
}

std::vector<LeastResistanceOptions> optionSets() {
    std::vector<LeastResistanceOptions> out(6);
    out[1].tolerance = 0;
    out[2].tolerance = 0.05;
    out[3].equalizeProtosinks = false;
    out[4].maxPhases = 1;
    out[5].maxPhases = 3;
    return out;
}

void expectSameAsReference(const FlowNetwork& net, const std::string& what) {
    int o = 0;
    for (const LeastResistanceOptions& options : optionSets())
        expectSameBits(reference::leastResistanceMaxFlow(net, options), leastResistanceMaxFlow(net, options),
                       what + ", option set " + std::to_string(o++));
}

TEST(MaxFlowIdentity, RandomGridsGiveTheReferenceFlowsBitForBit) {
    const std::vector<Dims> sizes{{9, 8, 7}, {14, 11, 9}};
    unsigned seed = 1;
    for (const Dims& d : sizes)
        for (const LinkStencil links : {LinkStencil::kAll26, LinkStencil::kFace6})
            for (const double share : {0.0, 0.4})
                for (const double jitter : {0.0, 0.5}) {
                    FlowNetworkOptions o;
                    o.links = links;
                    o.protosinkShare = share;
                    o.resistanceJitter = jitter;
                    o.jitterSeed = seed;
                    const FlowNetwork net = zoneNetwork(d, seed, o, seed % 2 == 0);
                    ++seed;
                    expectSameAsReference(net, "grid " + std::to_string(d.nx) + "x" + std::to_string(d.ny) + "x" +
                                                   std::to_string(d.nz) + " seed " + std::to_string(seed - 1));
                }
}

TEST(MaxFlowIdentity, ZoneSizedNetworkGivesTheReferenceFlowsBitForBit) {
    // Large enough for many phases with most arcs idle in each, as in stage 1's zones.
    FlowNetworkOptions o;
    o.protosinkShare = 0.5;
    o.resistanceJitter = 0.5;
    o.jitterSeed = 3;
    const FlowNetwork net = zoneNetwork({28, 28, 14}, 17, o, true);
    const MaxFlowResult want = reference::leastResistanceMaxFlow(net);
    EXPECT_GT(want.phases, 5);
    expectSameBits(want, leastResistanceMaxFlow(net), "28x28x14 zone");
}

/// Random sparse networks: every node linked to a few random others, some links zero one way.
TEST(MaxFlowIdentity, RandomSparseNetworksGiveTheReferenceFlowsBitForBit) {
    for (unsigned seed = 0; seed < 12; ++seed) {
        std::mt19937 gen(seed);
        const NodeId n = 40 + seed * 7;
        std::uniform_int_distribution<NodeId> node(0, n - 1);
        std::uniform_real_distribution<double> cap(0.0, 1.0), res(0.1, 3.0);
        std::vector<ArcSpec> arcs;
        std::set<std::pair<NodeId, NodeId>> linked;
        for (NodeId u = 0; u < n; ++u)
            for (int k = 0; k < 4; ++k) {
                const NodeId v = node(gen);
                if (v == u || !linked.insert({std::min(u, v), std::max(u, v)}).second) continue;
                const double r = res(gen);
                const double c = cap(gen);
                arcs.push_back({u, v, c < 0.2 ? 0.0 : c, r});
                arcs.push_back({v, u, c > 0.8 ? 0.0 : c, r});
            }
        const FlowNetwork net = flowNetworkFromArcs(n, arcs, {0, 1, 2}, {n - 3, n - 2, n - 1});
        expectSameAsReference(net, "sparse seed " + std::to_string(seed));
    }
}

/// Every arc doubled (same head, capacity and resistance; twins reverse twins): a network with
/// parallel arcs, which the solver runs without dropping anything.
FlowNetwork doubled(const FlowNetwork& net) {
    FlowNetwork out = net;
    out.arcBegin.assign(1, 0);
    out.arcTarget.clear();
    out.capacity.clear();
    out.resistance.clear();
    out.arcReverse.clear();
    for (NodeId u = 0; u < net.nodeCount(); ++u) {
        for (ArcId a = net.arcBegin[u]; a < net.arcBegin[u + 1]; ++a)
            for (int twin = 0; twin < 2; ++twin) {
                out.arcTarget.push_back(net.arcTarget[a]);
                out.capacity.push_back(net.capacity[a]);
                out.resistance.push_back(net.resistance[a]);
                out.arcReverse.push_back(2 * net.arcReverse[a] + twin);
            }
        out.arcBegin.push_back(ArcId(out.arcTarget.size()));
    }
    return out;
}

TEST(MaxFlowIdentity, NetworkWithParallelArcsGivesTheReferenceFlowsBitForBit) {
    FlowNetworkOptions o;
    o.resistanceJitter = 0.3;
    const FlowNetwork net = doubled(zoneNetwork({8, 7, 6}, 5, o, false));
    expectSameAsReference(net, "doubled 8x7x6");
}

}  // namespace
}  // namespace cavesim::flownet
