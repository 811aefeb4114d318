// Network counts on hand-built skeletons: flow paths follow decreasing pressure, a phreatic loop is
// a descent followed by a rise of at least 2 voxels, a tributary joins an earlier-connected channel.
#include <gtest/gtest.h>

#include "morpho/network.h"

using namespace cavesim;
using namespace cavesim::morpho;

namespace {

/// A 2D section (ny = 1) in which channels are drawn voxel by voxel; the skeleton is the drawn
/// voxels themselves, joined where they are 26-adjacent, and the pressure falls along each
/// drawn channel toward its end.
struct Section {
    Dims dims{40, 1, 20};
    Grid3<std::uint8_t> cave{dims, 0};
    Grid3<float> pressure{dims, 100.f};
    Skeleton skeleton;
    NetworkInput input;

    int node(int i, int k) {
        const std::size_t v = dims.index(i, 0, k);
        for (std::size_t n = 0; n < skeleton.nodes.size(); ++n)
            if (skeleton.nodes[n].voxel == v) return int(n);
        skeleton.nodes.push_back({{i + 0.5, 0.5, k + 0.5}, 0.5, v});
        cave[v] = 1;
        return int(skeleton.nodes.size()) - 1;
    }
    void edge(int a, int b) {
        std::array<int, 2> e{std::min(a, b), std::max(a, b)};
        if (std::find(skeleton.edges.begin(), skeleton.edges.end(), e) == skeleton.edges.end())
            skeleton.edges.push_back(e);
    }
    /// Draws a channel through the points (i, k) (each step one voxel, any of 8 directions), with
    /// pressure `p0` at the first point falling by 1 per step.
    void channel(const std::vector<std::array<int, 2>>& pts, float p0) {
        int prev = -1;
        float p = p0;
        for (const auto& q : pts) {
            const int n = node(q[0], q[1]);
            pressure.at(q[0], 0, q[1]) = std::min(pressure.at(q[0], 0, q[1]), p);
            p -= 1.f;
            if (prev >= 0) edge(prev, n);
            prev = n;
        }
    }
    static std::vector<std::array<int, 2>> line(int i0, int k0, int i1, int k1) {
        std::vector<std::array<int, 2>> out;
        int i = i0, k = k0;
        out.push_back({i, k});
        while (i != i1 || k != k1) {
            i += (i1 > i) - (i1 < i);
            k += (k1 > k) - (k1 < k);
            out.push_back({i, k});
        }
        return out;
    }
    static std::vector<std::array<int, 2>> join(std::vector<std::array<int, 2>> a,
                                                const std::vector<std::array<int, 2>>& b) {
        a.insert(a.end(), b.begin() + 1, b.end());
        return a;
    }
    void source(int i, int k) { input.sources.push_back({dims.index(i, 0, k)}); }
    void sink(int i, int k) { input.sinks.push_back({dims.index(i, 0, k)}); }
    NetworkCounts run() {
        input.dims = dims;
        input.cave = &cave;
        input.pressure = &pressure;
        return analyseNetwork(skeleton, input);
    }
};

}  // namespace

TEST(Network, StraightDescendingChannelHasNoLoop) {
    Section s;
    s.source(2, 18);
    s.channel(Section::line(3, 17, 30, 2), 50);
    s.sink(31, 1);
    const NetworkCounts c = s.run();
    EXPECT_EQ(c.sourcesTotal, 1);
    EXPECT_EQ(c.sourcesConnected, 1);
    EXPECT_EQ(c.phreaticLoops, 0);
    EXPECT_EQ(c.confluences, 0);
    EXPECT_EQ(c.tributaryCaptures, 0);
    EXPECT_TRUE(c.paths[0].downhill);
    EXPECT_FALSE(c.paths[0].fallback);
    EXPECT_EQ(c.fallbackPaths, 0);
    EXPECT_EQ(c.paths[0].sink, 0);
    // The descent runs from the source's neighbour (3, 17) down the channel to (30, 2), next to the sink.
    ASSERT_EQ(c.paths[0].voxels.size(), 28u);
    EXPECT_EQ(c.paths[0].voxels.front(), s.dims.index(3, 0, 17));
    EXPECT_EQ(c.paths[0].voxels.back(), s.dims.index(30, 0, 2));
    EXPECT_EQ(c.paths[0].nodes.size(), 28u);
}

TEST(Network, DescentTakesTheSteepestDropPerUnitLengthThroughCaveVoxels) {
    // P = 10 i + 3 j + k on a 5×5×5 block of cave. From (4, 4, 4) the drops per unit length are
    // 10 along −i, 13/√2 = 9.2 along (−i, −j), 14/√3 = 8.1 along (−i, −j, −k): the descent runs
    // along −i to i = 0, then along −j (3 against 4/√2 = 2.8), then along −k: 13 voxels.
    const Dims d{5, 5, 5};
    Grid3<std::uint8_t> cave(d, 1);
    Grid3<float> pressure(d, 0.f);
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) pressure.at(i, j, k) = float(10 * i + 3 * j + k);
    std::vector<char> exit(d.count(), 0);
    exit[d.index(0, 0, 0)] = 1;
    Descent a = descendPressure(cave, pressure, d.index(4, 4, 4), exit);
    EXPECT_TRUE(a.reachedExit);
    std::vector<std::size_t> expected;
    for (int i = 4; i >= 0; --i) expected.push_back(d.index(i, 4, 4));
    for (int j = 3; j >= 0; --j) expected.push_back(d.index(0, j, 4));
    for (int k = 3; k >= 0; --k) expected.push_back(d.index(0, 0, k));
    EXPECT_EQ(a.voxels, expected);

    // Rock at (3, 4, 4): the next steepest step, (−i, −j), is taken instead.
    cave.at(3, 4, 4) = 0;
    a = descendPressure(cave, pressure, d.index(4, 4, 4), exit);
    ASSERT_GE(a.voxels.size(), 2u);
    EXPECT_EQ(a.voxels[1], d.index(3, 3, 4));
    EXPECT_TRUE(a.reachedExit);

    // No exit: the descent stops in the pit at the origin.
    const std::vector<char> none(d.count(), 0);
    a = descendPressure(cave, pressure, d.index(4, 4, 4), none);
    EXPECT_FALSE(a.reachedExit);
    EXPECT_EQ(a.voxels.back(), d.index(0, 0, 0));
}

TEST(Network, LoopOnTheSharedPartOfTwoPathsCountsOnce) {
    // Source 0 feeds a channel that falls from z 17 to 5, rises to 7 and runs to the sink (one
    // loop); source 1's channel joins it at (3, 11), above the trough. Both paths pass the trough.
    Section s;
    s.source(2, 18);
    s.channel(
        Section::join(Section::join(Section::line(3, 17, 3, 5), Section::line(3, 5, 5, 7)), Section::line(5, 7, 30, 7)),
        60);  // (3, 11) has 54
    s.sink(31, 7);
    s.source(10, 18);
    s.channel(Section::line(10, 17, 4, 11), 70);  // (4, 11) has 64
    s.edge(s.node(4, 11), s.node(3, 11));
    s.input.connectedIteration = {std::optional<int>(10), std::optional<int>(20)};
    const NetworkCounts c = s.run();
    EXPECT_EQ(c.sourcesConnected, 2);
    EXPECT_EQ(c.fallbackPaths, 0);
    ASSERT_EQ(c.paths[0].loopTroughs.size(), 1u);
    ASSERT_EQ(c.paths[1].loopTroughs.size(), 1u);
    EXPECT_EQ(c.paths[0].loopTroughs[0], c.paths[1].loopTroughs[0]);
    EXPECT_EQ(s.dims.coord(s.skeleton.nodes[std::size_t(c.paths[0].loopTroughs[0])].voxel).k, 5);
    EXPECT_EQ(c.phreaticLoops, 1);
    EXPECT_EQ(c.confluences, 1);
    EXPECT_EQ(c.tributaryCaptures, 1);
    ASSERT_TRUE(c.paths[1].joinNode.has_value());
    EXPECT_EQ(s.skeleton.nodes[std::size_t(*c.paths[1].joinNode)].voxel, s.dims.index(3, 0, 11));
}

TEST(Network, DescentThenRiseOfTwoIsOneLoopAndOfOneIsNone) {
    {
        Section s;  // down from z 17 to 5, up to 7, then along to the sink: one loop
        s.source(2, 18);
        s.channel(Section::join(Section::join(Section::line(3, 17, 3, 5), Section::line(3, 5, 5, 7)),
                                Section::line(5, 7, 30, 7)),
                  60);
        s.sink(31, 7);
        const NetworkCounts c = s.run();
        EXPECT_EQ(c.sourcesConnected, 1);
        EXPECT_EQ(c.phreaticLoops, 1);
        ASSERT_EQ(c.paths[0].loopTroughs.size(), 1u);
        EXPECT_EQ(s.dims.coord(s.skeleton.nodes[std::size_t(c.paths[0].loopTroughs[0])].voxel).k, 5);
    }
    {
        Section s;  // a rise of one voxel is staircase noise, not a loop
        s.source(2, 18);
        s.channel(Section::join(Section::join(Section::line(3, 17, 3, 5), Section::line(3, 5, 4, 6)),
                                Section::line(4, 6, 30, 6)),
                  60);
        s.sink(31, 6);
        EXPECT_EQ(s.run().phreaticLoops, 0);
    }
}

TEST(Network, TwoLoopsInSequenceCountTwice) {
    Section s;
    s.source(1, 18);
    auto pts = Section::line(2, 17, 2, 10);
    pts = Section::join(pts, Section::line(2, 10, 5, 13));  // rise 3
    pts = Section::join(pts, Section::line(5, 13, 9, 9));   // descent
    pts = Section::join(pts, Section::line(9, 9, 12, 12));  // rise 3
    pts = Section::join(pts, Section::line(12, 12, 30, 12));
    s.channel(pts, 80);
    s.sink(31, 12);
    EXPECT_EQ(s.run().phreaticLoops, 2);
}

TEST(Network, LaterChannelJoiningAnEarlierOneIsACapture) {
    Section s;
    s.source(5, 18);                             // source 0: main channel straight to the sink
    s.source(25, 18);                            // source 1: joins the main channel from above
    s.channel(Section::line(5, 17, 5, 3), 100);  // pressure 100 .. 86
    s.channel(Section::line(6, 3, 35, 3), 85);   // 85 .. 56; (25, 3) has 66
    s.edge(s.node(5, 3), s.node(6, 3));
    s.channel(Section::line(25, 17, 25, 4), 100);  // 100 .. 87, then down into the main channel
    s.edge(s.node(25, 4), s.node(25, 3));
    s.sink(36, 3);
    s.input.connectedIteration = {std::optional<int>(10), std::optional<int>(30)};
    NetworkCounts c = s.run();
    EXPECT_EQ(c.sourcesConnected, 2);
    EXPECT_EQ(c.confluences, 1);
    EXPECT_EQ(c.tributaryCaptures, 1);
    EXPECT_FALSE(c.paths[0].capturedBy.has_value());
    ASSERT_TRUE(c.paths[1].capturedBy.has_value());
    EXPECT_EQ(*c.paths[1].capturedBy, 0);

    // Both connected in the same iteration: a confluence, but neither captured the other.
    s.input.connectedIteration = {std::optional<int>(10), std::optional<int>(10)};
    c = s.run();
    EXPECT_EQ(c.confluences, 1);
    EXPECT_EQ(c.tributaryCaptures, 0);
}

TEST(Network, UnconnectedSourceAndNoSkeleton) {
    Section s;
    s.source(2, 18);
    s.source(38, 18);  // far from any channel
    s.channel(Section::line(3, 17, 30, 2), 50);
    s.sink(31, 1);
    const NetworkCounts c = s.run();
    EXPECT_EQ(c.sourcesTotal, 2);
    EXPECT_EQ(c.sourcesConnected, 1);
    EXPECT_FALSE(c.paths[1].sink.has_value());

    Section empty;
    empty.source(2, 18);
    empty.sink(31, 1);
    const NetworkCounts e = empty.run();
    EXPECT_EQ(e.sourcesTotal, 1);
    EXPECT_EQ(e.sourcesConnected, 0);
    EXPECT_EQ(e.phreaticLoops, 0);
}

TEST(Network, UphillOnlyPathIsStillConnectedButMarked) {
    Section s;
    s.source(2, 18);
    s.channel(Section::line(3, 17, 30, 2), 10);  // pressure rises toward the sink end
    for (std::size_t n = 0; n < s.skeleton.nodes.size(); ++n) s.pressure[s.skeleton.nodes[n].voxel] = float(n);
    s.sink(31, 1);
    const NetworkCounts c = s.run();
    EXPECT_EQ(c.sourcesConnected, 1);
    EXPECT_FALSE(c.paths[0].downhill);
    // The descent is stuck at the source end: the path is the fallback.
    EXPECT_TRUE(c.paths[0].fallback);
    EXPECT_EQ(c.fallbackPaths, 1);
    EXPECT_TRUE(c.paths[0].voxels.empty());
    EXPECT_EQ(toJson(c, s.skeleton)["fallback_fraction"], 1.0);
}

TEST(Network, ElevationsComeFromSmoothedPositionsWhenTheVoxelSizeIsGiven) {
    // Down from z 17 to 5, up to 7, along to the sink: by voxel rows a rise of 2 (a loop). Smoothing
    // has pulled the nodes of the step toward the line (the step is 1.5 high): no loop.
    Section s;
    s.source(2, 18);
    s.channel(
        Section::join(Section::join(Section::line(3, 17, 3, 5), Section::line(3, 5, 5, 7)), Section::line(5, 7, 30, 7)),
        60);
    s.sink(31, 7);
    EXPECT_EQ(s.run().phreaticLoops, 1);
    for (auto& n : s.skeleton.nodes) {
        const Index3 p = s.dims.coord(n.voxel);
        if (p.i >= 5) n.position[2] = 6.5 + 0.5;  // z of the far passage, in metres (voxel size 1)
    }
    s.input.voxelSize = 1.0;
    EXPECT_EQ(s.run().phreaticLoops, 0);
    s.input.voxelSize = 0.0;  // voxel rows again
    EXPECT_EQ(s.run().phreaticLoops, 1);
}
