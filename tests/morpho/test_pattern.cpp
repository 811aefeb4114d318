// Cave pattern classification on hand-built centrelines: a grid maze (network maze), the same grid
// with fracture families along its diagonals (no longer aligned: anastomotic), a triangular lattice
// on one bed (anastomotic maze) and spread over levels (spongework), a binary tree (branchwork)
// and the same tree in 3D with rooms (ramiform), a single tube and a small Y; criteria against
// hand-computed numbers; a voxel cylinder through the skeleton.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "morpho/pattern.h"
#include "morpho/skeleton.h"

namespace cavesim::morpho {
namespace {

const double kPi = std::acos(-1.0);

Skeleton makeSkeleton(const std::vector<Vec3d>& positions, std::vector<std::array<int, 2>> edges, double radius = 0.5) {
    Skeleton s;
    for (const auto& p : positions) s.nodes.push_back({p, radius, 0});
    for (auto& e : edges)
        if (e[0] > e[1]) std::swap(e[0], e[1]);
    std::sort(edges.begin(), edges.end());
    s.edges = edges;
    return s;
}

PatternResult classify(const Skeleton& s, double coverage = 0.3, const std::vector<double>& families = {}) {
    return classifyPattern(s, computeGraphMetrics(s), coverage, {}, families);
}

/// n × n cells of `spacing` metres, rotated by `degrees` anticlockwise seen from above.
Skeleton gridMaze(int n, double spacing, double degrees = 0) {
    const double c = std::cos(degrees * kPi / 180), s = std::sin(degrees * kPi / 180);
    std::vector<Vec3d> pos;
    std::vector<std::array<int, 2>> edges;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = i * spacing, y = j * spacing;
            pos.push_back({100 + c * x - s * y, 100 + s * x + c * y, 5.0});
            const int v = j * (n + 1) + i;
            if (i < n) edges.push_back({v, v + 1});
            if (j < n) edges.push_back({v, v + n + 1});
        }
    return makeSkeleton(pos, edges);
}

/// A rhombus of the triangular lattice, n × n points, `spacing` metres; z from `zOf(i, j)`.
template <typename F>
Skeleton triangularLattice(int n, double spacing, F zOf) {
    std::vector<Vec3d> pos;
    std::vector<std::array<int, 2>> edges;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            pos.push_back({(i + 0.5 * j) * spacing, j * std::sqrt(3.0) / 2 * spacing, zOf(i, j)});
            const int v = j * n + i;
            if (i + 1 < n) edges.push_back({v, v + 1});
            if (j + 1 < n) edges.push_back({v, v + n});
            if (j + 1 < n && i > 0) edges.push_back({v, v + n - 1});
        }
    return makeSkeleton(pos, edges);
}

/// A trunk and a binary tree of `depth` levels below it, spread in plan, level d at z = d · zStep;
/// with `rooms`, the leaves are rooms of radius 5 m (the rest 0.5 m).
Skeleton binaryTree(int depth, double zStep, bool rooms) {
    std::vector<Vec3d> pos{{0, 0, 0}, {0, 10, 0}};  // trunk end, root
    std::vector<std::array<int, 2>> edges{{0, 1}};
    std::vector<double> radius{0.5, 0.5};
    std::vector<int> level{1};
    std::vector<int> frontier{1};
    for (int d = 1; d <= depth; ++d) {
        std::vector<int> next;
        const double spread = 40.0 / (1 << d);
        for (int v : frontier)
            for (int side : {-1, 1}) {
                const Vec3d& p = pos[std::size_t(v)];
                pos.push_back({p[0] + side * spread, p[1] + 10, d * zStep});
                radius.push_back(rooms && d == depth ? 5.0 : 0.5);
                edges.push_back({v, int(pos.size()) - 1});
                next.push_back(int(pos.size()) - 1);
            }
        frontier = next;
    }
    Skeleton s = makeSkeleton(pos, edges);
    for (std::size_t v = 0; v < s.nodes.size(); ++v) s.nodes[v].radius = radius[v];
    return s;
}

TEST(Pattern, GridMazeIsANetworkMazeWithHandComputedCriteria) {
    const PatternResult p = classify(gridMaze(4, 10.0), 0.25);
    EXPECT_EQ(p.pattern, "network maze");
    // 25 nodes, 40 edges of 10 m: loops 40 − 25 + 1 = 16; the 4 corners have degree 2, so
    // branches 40 − 4 = 36; junctions 21: 9 of degree 4, 12 of degree 3 → (36 + 36) / 21.
    EXPECT_EQ(p.branches, 36);
    EXPECT_EQ(p.loops, 16);
    EXPECT_DOUBLE_EQ(p.length_m, 400.0);
    EXPECT_DOUBLE_EQ(p.loops_per_km, 40.0);
    EXPECT_DOUBLE_EQ(p.loops_per_branch, 16.0 / 36.0);
    EXPECT_EQ(p.junctions, 21);
    EXPECT_DOUBLE_EQ(*p.junction_degree_mean, 72.0 / 21.0);
    EXPECT_EQ(p.dead_ends, 0);
    EXPECT_DOUBLE_EQ(*p.dead_end_share, 0.0);
    EXPECT_DOUBLE_EQ(*p.orthogonal_share, 1.0);
    EXPECT_DOUBLE_EQ(*p.orthogonal_azimuth_deg, 0.0);
    EXPECT_DOUBLE_EQ(p.slab_thickness_m, 2.0);  // 2 diameters of 2 × 0.5 m
    EXPECT_DOUBLE_EQ(*p.bed_share, 1.0);
    EXPECT_DOUBLE_EQ(p.vertical_spread_m, 0.0);
    EXPECT_DOUBLE_EQ(p.plan_coverage, 0.25);
    EXPECT_DOUBLE_EQ(*p.width_cv, 0.0);
    EXPECT_FALSE(p.family_share.has_value());
}

TEST(Pattern, RotatedGridFindsItsDirections) {
    const PatternResult p = classify(gridMaze(4, 10.0, 30.0));
    EXPECT_EQ(p.pattern, "network maze");
    EXPECT_NEAR(*p.orthogonal_share, 1.0, 1e-12);
    // Rotated 30° anticlockwise: the x passages point to azimuth 60°, the y passages to 150° (−30°).
    EXPECT_DOUBLE_EQ(*p.orthogonal_azimuth_deg, 60.0);
}

TEST(Pattern, FractureFamiliesDecideTheOrientationWhenGiven) {
    const Skeleton grid = gridMaze(4, 10.0);
    const PatternResult along = classify(grid, 0.3, {0.0, 90.0});
    EXPECT_DOUBLE_EQ(*along.family_share, 1.0);
    EXPECT_EQ(along.pattern, "network maze");
    // Families along the diagonals: no passage follows them; the maze is planar → anastomotic.
    const PatternResult across = classify(grid, 0.3, {45.0, 135.0});
    EXPECT_DOUBLE_EQ(*across.family_share, 0.0);
    EXPECT_EQ(across.pattern, "anastomotic maze");
    EXPECT_DOUBLE_EQ(*alignedShare(grid, {0.0}, 15.0), 0.5);  // the north–south half
}

TEST(Pattern, PlanarTriangularLatticeIsAnastomotic) {
    const PatternResult p = classify(triangularLattice(5, 10.0, [](int, int) { return 3.0; }));
    EXPECT_EQ(p.pattern, "anastomotic maze");
    // Edges of 10 m in three directions 60° apart: 20 at azimuth 90°, 20 at 30°, 16 at 150°
    // (56 edges, loops 56 − 25 + 1 = 32); a perpendicular pair takes one direction: 20 / 56.
    EXPECT_NEAR(*p.orthogonal_share, 20.0 / 56.0, 1e-12);
    EXPECT_DOUBLE_EQ(*p.bed_share, 1.0);
    EXPECT_EQ(p.loops, 32);
    EXPECT_EQ(p.branches, 54);  // two acute corners of degree 2
}

TEST(Pattern, LatticeOverManyLevelsIsSpongework) {
    const PatternResult p = classify(triangularLattice(5, 10.0, [](int i, int j) { return 10.0 * ((i + 2 * j) % 4); }));
    EXPECT_EQ(p.pattern, "spongework");
    EXPECT_LT(*p.bed_share, 0.6);
    EXPECT_GT(p.vertical_spread_m, 5.0);
}

TEST(Pattern, TreeIsBranchwork) {
    const PatternResult p = classify(binaryTree(4, 0.0, false));
    EXPECT_EQ(p.pattern, "branchwork");
    // 32 nodes, 31 edges, no node of degree 2: 31 branches; 16 leaves + the trunk end are dead
    // ends, each on its own branch; 15 junctions of degree 3.
    EXPECT_EQ(p.branches, 31);
    EXPECT_EQ(p.loops, 0);
    EXPECT_DOUBLE_EQ(p.loops_per_km, 0.0);
    EXPECT_EQ(p.junctions, 15);
    EXPECT_DOUBLE_EQ(*p.junction_degree_mean, 3.0);
    EXPECT_EQ(p.dead_ends, 17);
    EXPECT_DOUBLE_EQ(*p.dead_end_share, 17.0 / 31.0);
    EXPECT_DOUBLE_EQ(*p.bed_share, 1.0);
}

TEST(Pattern, TreeOverLevelsWithRoomsIsRamiform) {
    const PatternResult p = classify(binaryTree(4, 12.0, true));
    EXPECT_EQ(p.pattern, "ramiform");
    // Branch radii: 16 of (0.5 + 5) / 2 = 2.75 m, 15 of 0.5 m: CV = sd / mean ≈ 0.69.
    const double mean = (16 * 2.75 + 15 * 0.5) / 31;
    const double sd = std::sqrt((16 * (2.75 - mean) * (2.75 - mean) + 15 * (0.5 - mean) * (0.5 - mean)) / 30);
    EXPECT_NEAR(*p.width_cv, sd / mean, 1e-12);
    EXPECT_LT(*p.bed_share, 0.6);
    // The same tree over levels without rooms stays branchwork.
    EXPECT_EQ(classify(binaryTree(4, 12.0, false)).pattern, "branchwork");
}

TEST(Pattern, SingleTubeAndSmallY) {
    std::vector<Vec3d> pos;
    std::vector<std::array<int, 2>> edges;
    for (int i = 0; i < 20; ++i) {
        pos.push_back({double(i), 0, 0});
        if (i) edges.push_back({i - 1, i});
    }
    const PatternResult tube = classify(makeSkeleton(pos, edges));
    EXPECT_EQ(tube.pattern, "single passage");
    EXPECT_EQ(tube.branches, 1);
    EXPECT_EQ(tube.junctions, 0);
    EXPECT_DOUBLE_EQ(*tube.dead_end_share, 1.0);
    EXPECT_DOUBLE_EQ(tube.length_m, 19.0);

    const PatternResult y =
        classify(makeSkeleton({{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {-10, -10, 0}}, {{0, 1}, {0, 2}, {0, 3}}));
    EXPECT_EQ(y.pattern, "branchwork");
    EXPECT_EQ(y.branches, 3);

    EXPECT_EQ(classify(Skeleton{}).pattern, "none");
}

TEST(Pattern, ChamberStubsMergeTheirJunctions) {
    // An H: two junctions 1 m apart (radius 1 m each: the stub lies in their chamber), two arms of
    // 10 m at each: one junction of degree 4 with four blind branches.
    Skeleton s = makeSkeleton({{0, 0, 0}, {1, 0, 0}, {-5, 8, 0}, {-5, -8, 0}, {6, 8, 0}, {6, -8, 0}},
                              {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}}, 1.0);
    const PatternResult p = classify(s);
    EXPECT_EQ(p.chamber_branches, 1);
    EXPECT_EQ(p.branches, 4);
    EXPECT_EQ(p.junctions, 1);
    EXPECT_DOUBLE_EQ(*p.junction_degree_mean, 4.0);
    EXPECT_DOUBLE_EQ(*p.dead_end_share, 1.0);
    // Two parallel stubs between the junctions: a pillar in the chamber, its loop dropped.
    s.nodes.push_back({{0.5, 0.5, 0}, 1.0, 0});
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 6}, {1, 4}, {1, 5}, {1, 6}};
    const PatternResult pillar = classify(s);
    EXPECT_EQ(pillar.chamber_branches, 2);
    EXPECT_EQ(pillar.loops, 0);
    EXPECT_EQ(pillar.junctions, 1);
    EXPECT_DOUBLE_EQ(*pillar.junction_degree_mean, 4.0);
}

TEST(Pattern, VoxelCylinderIsASinglePassage) {
    Grid3<std::uint8_t> mask(Dims{40, 11, 11}, 0);
    for (int k = 0; k < 11; ++k)
        for (int j = 0; j < 11; ++j)
            for (int i = 2; i < 38; ++i)
                if ((j - 5) * (j - 5) + (k - 5) * (k - 5) <= 9) mask.at(i, j, k) = 1;
    const Skeleton s = skeletonize(mask, 1.0);
    EXPECT_EQ(classify(s).pattern, "single passage");
}

}  // namespace
}  // namespace cavesim::morpho
