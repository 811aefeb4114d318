// Grid layout (x fastest), index/coord round trip and the neighbour tables.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "core/grid.h"

namespace cavesim {
namespace {

TEST(Grid, IndexIsXFastest) {
    const Dims d{3, 4, 5};
    EXPECT_EQ(d.count(), 60u);
    EXPECT_EQ(d.index(0, 0, 0), 0u);
    EXPECT_EQ(d.index(1, 0, 0), 1u);
    EXPECT_EQ(d.index(0, 1, 0), 3u);
    EXPECT_EQ(d.index(0, 0, 1), 12u);
    EXPECT_EQ(d.index(2, 3, 4), 59u);
}

TEST(Grid, IndexAndCoordRoundTrip) {
    const Dims d{3, 4, 5};
    std::size_t expected = 0;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i, ++expected) {
                const Index3 p{i, j, k};
                ASSERT_EQ(d.index(p), expected);
                ASSERT_EQ(d.coord(expected), p);
            }
    for (std::size_t n = 0; n < d.count(); ++n) ASSERT_EQ(d.index(d.coord(n)), n);
}

TEST(Grid, FlatSectionsWork) {
    const Dims d{7, 1, 3};  // a 2D vertical section
    EXPECT_EQ(d.count(), 21u);
    for (std::size_t n = 0; n < d.count(); ++n) {
        EXPECT_EQ(d.coord(n).j, 0);
        EXPECT_EQ(d.index(d.coord(n)), n);
    }
}

TEST(Grid, Contains) {
    const Dims d{2, 3, 4};
    EXPECT_TRUE(d.contains(0, 0, 0));
    EXPECT_TRUE(d.contains(1, 2, 3));
    EXPECT_FALSE(d.contains(-1, 0, 0));
    EXPECT_FALSE(d.contains(2, 0, 0));
    EXPECT_FALSE(d.contains(0, 3, 0));
    EXPECT_FALSE(d.contains(Index3{0, 0, 4}));
    EXPECT_EQ(Dims{}.count(), 0u);
}

TEST(Grid, Grid3AccessorsAgree) {
    Grid3<int> g(Dims{3, 2, 2}, 7);
    EXPECT_EQ(g.size(), 12u);
    for (int v : g.data) EXPECT_EQ(v, 7);
    g.at(2, 1, 1) = 42;
    EXPECT_EQ(g[11], 42);
    EXPECT_EQ(g.at(Index3{2, 1, 1}), 42);
    g[g.dims.index(1, 0, 1)] = 5;
    EXPECT_EQ(g.at(1, 0, 1), 5);
}

TEST(Grid, FaceNeighbours) {
    const auto& f = faceNeighbours();
    ASSERT_EQ(f.size(), 6u);
    std::set<std::tuple<int, int, int>> seen;
    for (const auto& n : f) {
        EXPECT_EQ(std::abs(n.di) + std::abs(n.dj) + std::abs(n.dk), 1);
        EXPECT_EQ(n.length, 1.0);
        seen.insert({n.di, n.dj, n.dk});
    }
    EXPECT_EQ(seen.size(), 6u);
}

TEST(Grid, AllNeighboursHaveExactLengthsAndOrder) {
    const auto& a = allNeighbours();
    ASSERT_EQ(a.size(), 26u);
    std::set<std::tuple<int, int, int>> seen;
    int faces = 0, edges = 0, corners = 0;
    for (std::size_t c = 0; c < a.size(); ++c) {
        const auto& n = a[c];
        const int s = n.di * n.di + n.dj * n.dj + n.dk * n.dk;
        ASSERT_GE(s, 1);
        ASSERT_LE(s, 3);
        EXPECT_EQ(n.length, std::sqrt(double(s)));  // correctly rounded: equal to the table's constant
        faces += s == 1, edges += s == 2, corners += s == 3;
        seen.insert({n.di, n.dj, n.dk});
        if (c > 0) {  // (dk, dj, di) strictly increasing
            const auto& p = a[c - 1];
            EXPECT_LT(std::make_tuple(p.dk, p.dj, p.di), std::make_tuple(n.dk, n.dj, n.di));
        }
    }
    EXPECT_EQ(seen.size(), 26u);
    EXPECT_EQ(faces, 6);
    EXPECT_EQ(edges, 12);
    EXPECT_EQ(corners, 8);
    for (const auto& f : faceNeighbours()) EXPECT_EQ(seen.count({f.di, f.dj, f.dk}), 1u);
}

}  // namespace
}  // namespace cavesim
