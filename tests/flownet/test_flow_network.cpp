// Flow-network construction (arcs, reverses, capacity rule, terminals, limits) and protosink
// selection (zone boundaries, cluster centres, clusters).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/error.h"
#include "flownet/flow_network.h"
#include "flownet/protosinks.h"
#include "test_util.h"

namespace cavesim::flownet {
namespace {

TEST(FlowNetwork, CubeHasEveryNeighbourPairOnceWithConsistentReverses) {
    const Dims d{3, 3, 3};
    std::mt19937 gen(5);
    std::uniform_real_distribution<float> u(0.01f, 0.5f);
    Grid3<float> R(d);
    for (auto& r : R.data) r = u(gen);
    for (const LinkStencil links : {LinkStencil::kFace6, LinkStencil::kAll26}) {
        FlowNetworkOptions o;
        o.capacityExponent = 1.5;
        o.links = links;
        const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {13}, {0, 26}, o);
        EXPECT_EQ(net.voxelNodes, 27u);
        // Face pairs 3 · 3² · 2 = 54; with 26 links also 6 edge directions × 2·2·3 and 4 corner
        // directions × 2·2·2 (0 and 26 are opposite corners, too far apart to be linked).
        const std::size_t edges = links == LinkStencil::kFace6 ? 54u : 54u + 72u + 32u;
        EXPECT_EQ(net.voxelEdgeCount(), edges);
        EXPECT_EQ(net.arcCount(), 2u * edges + 2u * 1u + 2u * 2u);
        for (ArcId a = 0; a < net.arcCount(); ++a) {
            const ArcId b = net.arcReverse[a];
            ASSERT_LT(b, net.arcCount());
            EXPECT_EQ(net.arcReverse[b], a);
            EXPECT_EQ(net.resistance[a], net.resistance[b]);
            // b leaves the head of a and points back to a's tail.
            EXPECT_GE(b, net.arcBegin[net.arcTarget[a]]);
            EXPECT_LT(b, net.arcBegin[net.arcTarget[a] + 1]);
        }
        for (std::size_t v = 0; v < 27; ++v) {
            const Index3 p = d.coord(v);
            for (ArcId a = net.arcBegin[v]; a < net.arcBegin[v + 1]; ++a) {
                const NodeId w = net.arcTarget[a];
                if (w >= net.voxelNodes) continue;
                const Index3 q = d.coord(w);
                const int di = std::abs(p.i - q.i), dj = std::abs(p.j - q.j), dk = std::abs(p.k - q.k);
                EXPECT_EQ(std::max({di, dj, dk}), 1);  // neighbours
                if (links == LinkStencil::kFace6) EXPECT_EQ(di + dj + dk, 1);
                const double length = std::sqrt(double(di + dj + dk));
                const double link = std::pow(double(std::min(R[v], R[w])), 1.5);
                const bool fromProtosink = v == 0 || v == 26;
                EXPECT_DOUBLE_EQ(net.capacity[a], fromProtosink ? 0.0 : link / length);  // conductance
                EXPECT_DOUBLE_EQ(net.resistance[a], length / link);                      // its inverse
            }
        }
    }
    FlowNetworkOptions o;
    o.capacityExponent = 1.5;
    const FlowNetwork net = buildFlowNetwork(R, allVoxels(d), {13}, {0, 26}, o);
    // Terminals: the super-source feeds voxel 13, voxels 0 and 26 drain, both without binding.
    ASSERT_EQ(net.arcBegin[net.source + 1] - net.arcBegin[net.source], 1u);
    EXPECT_EQ(net.arcTarget[net.arcBegin[net.source]], 13u);
    double total = 0;
    for (ArcId a = net.arcBegin[0]; a < net.arcBegin[27]; ++a)
        if (net.arcTarget[a] < 27) total += net.capacity[a];
    EXPECT_GT(net.terminalCapacity, total);
    EXPECT_EQ(net.capacity[net.arcBegin[1] - 1], net.terminalCapacity);  // voxel 0 → sink
    EXPECT_GT(net.bytes(), 0u);
}

TEST(FlowNetwork, SubsetOfVoxelsLinksOnlyMembersAndSkipsZeroPorosity) {
    const Dims d{4, 1, 3};
    Grid3<float> R(d, 0.1f);
    R.at(1, 0, 1) = 0.0f;  // impermeable: its links carry nothing and are left out
    std::vector<std::size_t> voxels;
    for (std::size_t v = 0; v < d.count(); ++v)
        if (d.coord(v).i < 3) voxels.push_back(v);  // leave column x = 3 out
    const FlowNetwork net = buildFlowNetwork(R, voxels, {d.index(0, 0, 0)}, {d.index(2, 0, 2)}, face6());
    // 3 × 3 block: 12 face pairs, minus the 4 pairs of the impermeable centre.
    EXPECT_EQ(net.voxelEdgeCount(), 8u);
    EXPECT_EQ(nodeOfVoxel(net, d.index(3, 0, 0)), -1);
    EXPECT_EQ(nodeOfVoxel(net, d.index(2, 0, 1)), 5);
}

TEST(FlowNetwork, ResistanceJitterIsBoundedSymmetricAndSeeded) {
    const Dims d{6, 5, 4};
    const Grid3<float> R(d, 0.1f);
    FlowNetworkOptions o = face6();
    o.resistanceJitter = 0.5;
    o.jitterSeed = 42;
    const FlowNetwork a = buildFlowNetwork(R, allVoxels(d), {0}, {d.count() - 1}, o);
    const FlowNetwork b = buildFlowNetwork(R, allVoxels(d), {0}, {d.count() - 1}, o);
    o.jitterSeed = 43;
    const FlowNetwork c = buildFlowNetwork(R, allVoxels(d), {0}, {d.count() - 1}, o);
    EXPECT_EQ(a.resistance, b.resistance);
    EXPECT_NE(a.resistance, c.resistance);
    std::set<double> distinct;
    const double base = 1.0 / double(0.1f);
    for (std::size_t v = 0; v + 1 < a.voxelNodes; ++v)  // every voxel but the protosink (the last)
        for (ArcId e = a.arcBegin[v]; e < a.arcBegin[v + 1]; ++e) {
            if (a.arcTarget[e] >= a.voxelNodes) continue;
            EXPECT_GE(a.resistance[e], base / std::exp(1.0));  // factor e^(2 · 0.5 · (2u − 1)) in [1/e, e)
            EXPECT_LT(a.resistance[e], base * std::exp(1.0));
            EXPECT_EQ(a.resistance[e], a.resistance[a.arcReverse[e]]);
            EXPECT_EQ(a.capacity[e], double(0.1f));  // capacity untouched
            distinct.insert(a.resistance[e]);
        }
    EXPECT_GT(distinct.size(), a.voxelEdgeCount() * 9 / 10);
}

TEST(FlowNetwork, BadInputThrows) {
    const Dims d{3, 1, 1};
    const Grid3<float> R(d, 0.1f);
    EXPECT_THROW(buildFlowNetwork(R, {0, 1, 2}, {5}, {0}), InternalError);  // source not a node
    EXPECT_THROW(buildFlowNetwork(R, {0, 1, 2}, {1}, {1}), InternalError);  // source = protosink
    EXPECT_THROW(buildFlowNetwork(R, {0, 2, 1}, {0}, {2}), InternalError);  // not increasing
    EXPECT_THROW(buildFlowNetwork(R, {0, 1, 7}, {0}, {1}), InternalError);  // outside the grid
    FlowNetworkOptions o;
    o.capacityExponent = 0;
    EXPECT_THROW(buildFlowNetwork(R, {0, 1, 2}, {0}, {2}, o), InternalError);
    o = {};
    o.maxNodes = 2;
    EXPECT_THROW(buildFlowNetwork(R, {0, 1, 2}, {0}, {2}, o), std::length_error);
    EXPECT_THROW(flowNetworkFromArcs(2, {{0, 2, 1}}, {0}, {1}), InternalError);
    EXPECT_THROW(flowNetworkFromArcs(2, {{0, 1, -1}}, {0}, {1}), InternalError);
    EXPECT_THROW(flowNetworkFromArcs(2, {{0, 1, 1}, {0, 1, 2}}, {0}, {1}), InternalError);
    EXPECT_THROW(flowNetworkFromArcs(2, {{0, 1, 1, 1}, {1, 0, 1, 2}}, {0}, {1}), InternalError);
}

TEST(FlowNetwork, EmptyAndSingleVoxelNetworks) {
    const Dims d{1, 1, 1};
    const Grid3<float> R(d, 0.1f);
    const FlowNetwork one = buildFlowNetwork(R, {0}, {0}, {});
    EXPECT_EQ(one.voxelEdgeCount(), 0u);
    EXPECT_EQ(one.arcCount(), 2u);
    const FlowNetwork none = buildFlowNetwork(R, {}, {}, {});
    EXPECT_EQ(none.nodeCount(), 2u);
    EXPECT_EQ(none.arcCount(), 0u);
}

TEST(Protosinks, BoundaryBetweenZonesAndOnChosenFaces) {
    // 6 × 4 × 3: zone 0 for x < 3, zone 1 for x ≥ 3, and one unlabelled voxel inside zone 0.
    const Dims d{6, 4, 3};
    Grid3<std::int32_t> labels(d, 0);
    for (std::size_t v = 0; v < d.count(); ++v)
        if (d.coord(v).i >= 3) labels[v] = 1;
    labels.at(1, 2, 1) = -1;
    std::vector<std::size_t> zone0;
    for (std::size_t v = 0; v < d.count(); ++v)
        if (labels[v] == 0) zone0.push_back(v);
    const GridFaces none{};
    const auto b = zoneBoundary(labels, zone0, 0, none);
    EXPECT_EQ(b.size(), 12u);  // the x = 2 slice, 4 × 3; the unlabelled voxel's neighbours are not boundary
    for (std::size_t v : b) EXPECT_EQ(d.coord(v).i, 2);
    GridFaces minusX{};
    minusX[0] = true;
    EXPECT_EQ(zoneBoundary(labels, zone0, 0, minusX).size(), 24u);  // plus the x = 0 slice
    const GridFaces all{true, true, true, true, true, true};
    // All faces: every voxel of zone 0 but the interior ones (x = 1, y = 1..2, z = 1) … minus the hole.
    EXPECT_EQ(zoneBoundary(labels, zone0, 0, all).size(), zone0.size() - 1u);
    std::vector<std::size_t> wrong{d.index(4, 0, 0)};
    EXPECT_THROW(zoneBoundary(labels, wrong, 0, all), InternalError);
}

TEST(Protosinks, FacesOfExtentOneAreNotBoundary) {
    // A 2D section (ny = 1): the ±y faces are the section's plane, never a boundary.
    const Dims d{5, 1, 4};
    const Grid3<std::int32_t> labels(d, 0);
    GridFaces y{};
    y[2] = y[3] = true;
    EXPECT_TRUE(zoneBoundary(labels, allVoxels(d), 0, y).empty());
    GridFaces z{};
    z[4] = true;
    EXPECT_EQ(zoneBoundary(labels, allVoxels(d), 0, z).size(), 5u);
}

TEST(Protosinks, ClusterCentresAreReproducibleAndSpread) {
    const Dims d{30, 30, 1};
    std::vector<std::size_t> candidates = allVoxels(d);
    std::mt19937_64 a(7), b(7), c(8);
    const auto ca = chooseClusterCentres(d, candidates, 5, {}, a);
    const auto cb = chooseClusterCentres(d, candidates, 5, {}, b);
    const auto cc = chooseClusterCentres(d, candidates, 5, {}, c);
    EXPECT_EQ(ca, cb);
    EXPECT_NE(ca, cc);
    ASSERT_EQ(ca.size(), 5u);
    EXPECT_EQ(std::set<std::size_t>(ca.begin(), ca.end()).size(), 5u);
    for (std::size_t v : ca) EXPECT_TRUE(std::binary_search(candidates.begin(), candidates.end(), v));
    // Fewer candidates than clusters: all of them.
    std::mt19937_64 e(1);
    EXPECT_EQ(chooseClusterCentres(d, {3, 9}, 4, {}, e), (std::vector<std::size_t>{3, 9}));
    EXPECT_THROW(chooseClusterCentres(d, candidates, 0, {}, e), InternalError);
    EXPECT_TRUE(chooseClusterCentres(d, {}, 3, {}, e).empty());
}

TEST(Protosinks, AimPicksTheNearestCandidates) {
    const Dims d{10, 10, 1};
    std::vector<std::size_t> rim;
    for (std::size_t v = 0; v < d.count(); ++v) {
        const Index3 p = d.coord(v);
        if (p.i == 0 || p.j == 0 || p.i == 9 || p.j == 9) rim.push_back(v);
    }
    std::mt19937_64 rng(1);
    const std::mt19937_64 before = rng;
    const auto c = chooseClusterCentres(d, rim, 3, {{20, 4.2, 0}, {4.6, -3, 0}, {19, 4, 0}}, rng);
    EXPECT_EQ(c, (std::vector<std::size_t>{d.index(9, 4, 0), d.index(5, 0, 0)}));  // third duplicates the first
    EXPECT_EQ(rng, before);                                                        // aiming draws nothing
}

TEST(Protosinks, ClusterIsTheBallOfGivenRadius) {
    const Dims d{9, 9, 9};
    const auto all = allVoxels(d);
    const auto ball = clusterProtosinks(d, all, {d.index(4, 4, 4)}, 2.0);
    std::size_t expected = 0;
    for (int k = -2; k <= 2; ++k)
        for (int j = -2; j <= 2; ++j)
            for (int i = -2; i <= 2; ++i) expected += i * i + j * j + k * k <= 4;
    EXPECT_EQ(ball.size(), expected);  // 33
    EXPECT_EQ(clusterProtosinks(d, all, {5, 7}, 0.0), (std::vector<std::size_t>{5, 7}));
    EXPECT_THROW(clusterProtosinks(d, all, {5}, -1.0), InternalError);
}

}  // namespace
}  // namespace cavesim::flownet
