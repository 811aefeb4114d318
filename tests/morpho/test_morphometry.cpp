// Morphometric indices against values worked out by hand: a straight 1-voxel tube, an L-shaped tube
// (rectangle vs convex hull), a vertical shaft in a 2D section, a ring and two separate cells in plan,
// an empty mask; the cave category of the paper's Table 4 caves; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.h"
#include "morpho/morphometry.h"

namespace cavesim::morpho {
namespace {

constexpr double kTol = 1e-12;

Skeleton polyline(const std::vector<std::array<double, 3>>& points) {
    Skeleton s;
    for (const auto& p : points) s.nodes.push_back({p, 0.0, 0});
    for (int i = 0; i + 1 < int(points.size()); ++i) s.edges.push_back({i, i + 1});
    return s;
}

TEST(Morphometry, StraightTubeOfOneVoxel) {
    // L = 10 voxels along x at j = 3, k = 1 in a 12×7×3 grid, h = 0.5 m: voxels i = 1..10 span
    // x ∈ [0.5, 5.5] m. The centreline runs from end face to end face through the voxel centres.
    const double h = 0.5;
    Grid3<std::uint8_t> mask(Dims{12, 7, 3}, 0);
    std::vector<std::array<double, 3>> pts{{1 * h, 3.5 * h, 1.5 * h}};
    for (int i = 1; i <= 10; ++i) {
        mask.at(i, 3, 1) = 1;
        pts.push_back({(i + 0.5) * h, 3.5 * h, 1.5 * h});
    }
    pts.push_back({11 * h, 3.5 * h, 1.5 * h});
    const Morphometry m = computeMorphometry(mask, polyline(pts), h);
    EXPECT_NEAR(m.length_m, 10 * h, kTol);             // L·h = 5 m
    EXPECT_NEAR(m.area_m2, 10 * h * h, kTol);          // 10 cells of 0.25 m²
    EXPECT_NEAR(m.volume_m3, 10 * h * h * h, kTol);    // 1.25 m³
    EXPECT_NEAR(m.vertical_range_m, h, kTol);          // one layer
    EXPECT_NEAR(m.a_field_rect_m2, 10 * h * h, kTol);  // 10 × 1 cells
    EXPECT_NEAR(m.a_field_opt_m2, 10 * h * h, kTol);   // the hull of a rectangle is the rectangle
    EXPECT_NEAR(m.v_block_rect_m3, 10 * h * h * h, kTol);
    EXPECT_NEAR(m.v_block_opt_m3, 10 * h * h * h, kTol);
    EXPECT_NEAR(m.network_density_rect, 1 / h, kTol);  // 5 m / 2.5 m² = 2 m/m²
    EXPECT_NEAR(m.network_density_opt, 1 / h, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_rect, 100.0, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_opt, 100.0, kTol);
    EXPECT_NEAR(m.porosity_pct_rect, 100.0, kTol);
    EXPECT_NEAR(m.porosity_pct_opt, 100.0, kTol);
    EXPECT_DOUBLE_EQ(m.mean_width_m, h);  // W = 2.5 m² / 5 m = h exactly
    EXPECT_EQ(m.cave_voxels, 10);
    EXPECT_EQ(m.plan_cells, 10);

    // The same tube with a centreline that stops at the end-voxel centres: 9 h long, W = 10h²/9h.
    pts.erase(pts.begin());
    pts.pop_back();
    const Morphometry c = computeMorphometry(mask, polyline(pts), h);
    EXPECT_NEAR(c.length_m, 9 * h, kTol);
    EXPECT_NEAR(c.mean_width_m, 10.0 / 9.0 * h, kTol);
}

TEST(Morphometry, LShapedTubeRectangleVersusConvexHull) {
    // h = 2 m. Plan: arm A cells (1..5, 2), arm B cells (1, 3..6), both two voxels tall (k = 1, 2).
    // In cell units relative to (1, 2): A = [0,5]×[0,1], B = [0,1]×[1,5].
    const double h = 2.0;
    Grid3<std::uint8_t> mask(Dims{8, 8, 4}, 0);
    for (int k = 1; k <= 2; ++k) {
        for (int i = 1; i <= 5; ++i) mask.at(i, 2, k) = 1;
        for (int j = 3; j <= 6; ++j) mask.at(1, j, k) = 1;
    }
    // Centreline from the end face of A through the corner cell's centre to the end face of B:
    // (6h, 2.5h) → (1.5h, 2.5h) → (1.5h, 7h): 4.5h + 4.5h = 9h = 18 m.
    const Skeleton s = polyline({{6 * h, 2.5 * h, 2 * h}, {1.5 * h, 2.5 * h, 2 * h}, {1.5 * h, 7 * h, 2 * h}});
    const Morphometry m = computeMorphometry(mask, s, h);
    EXPECT_EQ(m.plan_cells, 9);
    EXPECT_EQ(m.cave_voxels, 18);
    EXPECT_NEAR(m.length_m, 18.0, kTol);
    EXPECT_NEAR(m.area_m2, 9 * 4.0, kTol);       // 36 m²
    EXPECT_NEAR(m.volume_m3, 18 * 8.0, kTol);    // 144 m³
    EXPECT_NEAR(m.vertical_range_m, 4.0, kTol);  // 2 layers
    // Rectangle: 5 × 5 cells = 25 cells = 100 m².
    EXPECT_NEAR(m.a_field_rect_m2, 100.0, kTol);
    // Hull of the corners: (0,0) (5,0) (5,1) (1,5) (0,5). Shoelace: 0 + 5 + (25 − 1) + 5 + 0 = 34 →
    // 17 cells (= 25 minus the triangle (5,1) (5,5) (1,5) of area 8) = 68 m².
    EXPECT_NEAR(m.a_field_hull_m2, 68.0, kTol);
    EXPECT_NEAR(m.v_block_rect_m3, 400.0, kTol);
    EXPECT_NEAR(m.v_block_hull_m3, 272.0, kTol);
    EXPECT_NEAR(m.network_density_rect, 18.0 / 100.0, kTol);
    EXPECT_NEAR(m.network_density_hull, 18.0 / 68.0, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_rect, 36.0, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_hull, 100.0 * 36.0 / 68.0, kTol);
    EXPECT_NEAR(m.porosity_pct_rect, 36.0, kTol);  // 144 / 400
    EXPECT_NEAR(m.porosity_pct_hull, 100.0 * 144.0 / 272.0, kTol);
    // Optimised field: spacing 68 / 18 m, margin 68 / 36 = 1.89 m = 0.94 cells: no cell centre
    // beyond the plan is that close, so the field is the plan itself (9 cells).
    EXPECT_NEAR(m.passage_spacing_m, 68.0 / 18.0, kTol);
    EXPECT_NEAR(m.field_margin_m, 68.0 / 36.0, kTol);
    EXPECT_NEAR(m.a_field_opt_m2, 36.0, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_opt, 100.0, kTol);
    EXPECT_NEAR(m.porosity_pct_opt, 100.0, kTol);
    EXPECT_NEAR(m.mean_width_m, 2.0, kTol);  // 36 / 18 = h
}

TEST(Morphometry, OptimisedFieldOfALShapedPlanWithAMarginOfOneDiagonal) {
    // h = 1 m, one layer. Plan: column i = 1, j = 1..10 and row j = 1, i = 1..10 (19 cells); the
    // centreline (1.5, 10.5) → (1.5, 1.5) → (10.5, 1.5) is 18 m long.
    Grid3<std::uint8_t> mask(Dims{12, 12, 1}, 0);
    for (int t = 1; t <= 10; ++t) mask.at(1, t, 0) = mask.at(t, 1, 0) = 1;
    const Skeleton s = polyline({{1.5, 10.5, 0.5}, {1.5, 1.5, 0.5}, {10.5, 1.5, 0.5}});
    const Morphometry m = computeMorphometry(mask, s, 1.0);
    EXPECT_EQ(m.plan_cells, 19);
    EXPECT_NEAR(m.a_field_rect_m2, 100.0, kTol);
    // Hull (1,1) (11,1) (11,2) (2,11) (1,11): shoelace 2·area = 10 + 99 + 10 = 119 (rectangle
    // minus the triangle (11,2) (11,11) (2,11) of 40.5) → 59.5 m².
    EXPECT_NEAR(m.a_field_hull_m2, 59.5, kTol);
    // Margin 59.5 / 36 = 1.65 cells: centres at distance 1 and √2 from the plan join it, 2 does not.
    // Dilated plan: columns i = 0..2 along the arm j, rows j = 0..2 along the arm i. Inside the
    // hull (x ≥ 1, y ≥ 1, x ≤ 11, y ≤ 11, x + y ≤ 13): i = 1, 2 for j = 1..10 (20 cells) and
    // j = 1, 2 for i = 3..10 (16 cells; (10, 2) has its centre on the hull's edge x + y = 13).
    EXPECT_NEAR(m.field_margin_m, 59.5 / 36.0, kTol);
    EXPECT_NEAR(m.a_field_opt_m2, 36.0, kTol);
    EXPECT_NEAR(m.areal_coverage_pct_opt, 100.0 * 19.0 / 36.0, kTol);
    EXPECT_NEAR(m.network_density_opt, 18.0 / 36.0, kTol);
    EXPECT_NEAR(m.a_field_rect_m2 / m.a_field_opt_m2, 100.0 / 36.0, kTol);
}

TEST(Morphometry, CentrelineAndBlockNearMarkedVoxels) {
    // 10×1×1 row of voxels, voxel 0 marked: within 2 voxels lie voxels 0, 1, 2 (3 of 10). A
    // centreline along the row, nodes on voxels 0..9 one metre apart: edges 0–1 and 1–2 near at
    // both ends (2 m), edge 2–3 at one end (0.5 m); 2.5 of 9 m.
    Grid3<std::uint8_t> marked(Dims{10, 1, 1}, 0);
    marked[0] = 1;
    Skeleton s;
    for (int i = 0; i < 10; ++i) {
        s.nodes.push_back({{i + 0.5, 0.5, 0.5}, 0.5, std::size_t(i)});
        if (i > 0) s.edges.push_back({i - 1, i});
    }
    const NearMarked n = nearMarked(s, marked, 2.0);
    EXPECT_EQ(n.block_voxels, 10);
    EXPECT_EQ(n.block_voxels_near, 3);
    ASSERT_TRUE(n.block_share.has_value());
    EXPECT_NEAR(*n.block_share, 0.3, kTol);
    EXPECT_NEAR(n.length_m, 9.0, kTol);
    EXPECT_NEAR(n.length_near_m, 2.5, kTol);
    ASSERT_TRUE(n.centreline_share.has_value());
    EXPECT_NEAR(*n.centreline_share, 2.5 / 9.0, kTol);
    // In 3D the ball of radius 2 holds 33 voxels (1 + 6 + 12 + 8 + 6).
    Grid3<std::uint8_t> cube(Dims{7, 7, 7}, 0);
    cube.at(3, 3, 3) = 1;
    EXPECT_EQ(nearMarked(Skeleton{}, cube, 2.0).block_voxels_near, 33);
    EXPECT_FALSE(nearMarked(Skeleton{}, cube, 2.0).centreline_share.has_value());
}

TEST(Morphometry, VerticalShaftInATwoDimensionalSection) {
    // ny = 1 section, h = 0.25 m: a shaft at i = 2, k = 0..3, centreline floor to roof (4h).
    const double h = 0.25;
    Grid3<std::uint8_t> mask(Dims{5, 1, 4}, 0);
    for (int k = 0; k < 4; ++k) mask.at(2, 0, k) = 1;
    const Morphometry m = computeMorphometry(mask, polyline({{2.5 * h, 0.5 * h, 0}, {2.5 * h, 0.5 * h, 4 * h}}), h);
    EXPECT_EQ(m.plan_cells, 1);
    EXPECT_NEAR(m.area_m2, h * h, kTol);
    EXPECT_NEAR(m.a_field_rect_m2, h * h, kTol);
    EXPECT_NEAR(m.a_field_opt_m2, h * h, kTol);
    EXPECT_NEAR(m.vertical_range_m, 4 * h, kTol);
    EXPECT_NEAR(m.volume_m3, 4 * h * h * h, kTol);
    EXPECT_NEAR(m.porosity_pct_rect, 100.0, kTol);
    EXPECT_NEAR(m.network_density_opt, 4 * h / (h * h), kTol);  // 16 m/m²
    EXPECT_NEAR(m.mean_width_m, h / 4, kTol);                   // plan area / length
}

TEST(Morphometry, RingAndScatteredPlans) {
    const double h = 1.0;
    // A 5×5 square ring (the 3×3 centre is rock), one layer: 16 cells; rectangle = hull = 25 → 64 %.
    Grid3<std::uint8_t> ring(Dims{7, 7, 2}, 0);
    for (int j = 1; j <= 5; ++j)
        for (int i = 1; i <= 5; ++i)
            if (i == 1 || i == 5 || j == 1 || j == 5) ring.at(i, j, 1) = 1;
    const Morphometry r = computeMorphometry(ring, Skeleton{}, h);
    EXPECT_EQ(r.plan_cells, 16);
    EXPECT_NEAR(r.a_field_rect_m2, 25.0, kTol);
    EXPECT_NEAR(r.a_field_opt_m2, 25.0, kTol);
    EXPECT_NEAR(r.areal_coverage_pct_opt, 64.0, kTol);
    EXPECT_DOUBLE_EQ(r.mean_width_m, 0.0);  // no skeleton: length 0, W reported as 0
    EXPECT_DOUBLE_EQ(r.network_density_opt, 0.0);

    // Two cells on a diagonal, (0,0) and (3,3), at different heights k = 0 and k = 2 (range 3 cells).
    // Hull (0,0) (1,0) (4,3) (4,4) (3,4) (0,1): shoelace 0 + 3 + 4 + 4 + 3 + 0 = 14 → 7 cells; rectangle 16.
    Grid3<std::uint8_t> two(Dims{4, 4, 3}, 0);
    two.at(0, 0, 0) = 1;
    two.at(3, 3, 2) = 1;
    const Morphometry t = computeMorphometry(two, Skeleton{}, 3.0);
    EXPECT_NEAR(t.a_field_rect_m2, 16 * 9.0, kTol);
    EXPECT_NEAR(t.a_field_opt_m2, 7 * 9.0, kTol);
    EXPECT_NEAR(t.vertical_range_m, 9.0, kTol);
    EXPECT_NEAR(t.porosity_pct_opt, 100.0 * 2 * 27.0 / (7 * 9.0 * 9.0), kTol);
    EXPECT_NEAR(t.areal_coverage_pct_rect, 100.0 * 2 / 16, kTol);

    // Two voxels stacked in one column: plan 1 cell, volume 2.
    Grid3<std::uint8_t> stack(Dims{1, 1, 2}, 1);
    const Morphometry st = computeMorphometry(stack, Skeleton{}, 1.0);
    EXPECT_EQ(st.plan_cells, 1);
    EXPECT_EQ(st.cave_voxels, 2);
    EXPECT_NEAR(st.porosity_pct_rect, 100.0, kTol);
}

TEST(Morphometry, EmptyMaskGivesZeros) {
    for (const Dims& d : {Dims{0, 0, 0}, Dims{6, 5, 4}, Dims{3, 1, 1}}) {
        const Morphometry m = computeMorphometry(Grid3<std::uint8_t>(d, 0), Skeleton{}, 0.7);
        const nlohmann::json j = toJson(m);
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (it->is_string()) continue;
            EXPECT_TRUE(it->is_number()) << it.key();
            EXPECT_EQ(it->get<double>(), 0.0) << it.key();
        }
        EXPECT_EQ(caveCategory(m), "none");
    }
}

TEST(Morphometry, JsonHasTheDesignKeys) {
    Grid3<std::uint8_t> mask(Dims{2, 2, 2}, 1);
    const nlohmann::json j = toJson(computeMorphometry(mask, polyline({{0, 0, 1}, {2, 2, 1}}), 1.0));
    for (const char* key : {"length_m", "area_m2", "volume_m3", "a_field_rect_m2", "a_field_opt_m2", "v_block_rect_m3",
                            "v_block_opt_m3", "network_density_opt", "network_density_rect", "areal_coverage_pct_opt",
                            "areal_coverage_pct_rect", "porosity_pct_opt", "porosity_pct_rect", "mean_width_m"})
        EXPECT_TRUE(j.contains(key) && j[key].is_number()) << key;
    EXPECT_EQ(j["field_opt_method"].get<std::string>(), std::string("plan_margin_in_hull"));
    EXPECT_NEAR(j["length_m"].get<double>(), 2 * std::sqrt(2.0), kTol);
}

TEST(Morphometry, BadInputThrows) {
    Grid3<std::uint8_t> mask(Dims{2, 2, 2}, 1);
    EXPECT_THROW(computeMorphometry(mask, Skeleton{}, 0.0), InternalError);
    EXPECT_THROW(computeMorphometry(mask, Skeleton{}, -1.0), InternalError);
    EXPECT_THROW(computeMorphometry(mask, Skeleton{}, std::nan("")), InternalError);
    EXPECT_THROW(computeMorphometry(mask, Skeleton{}, INFINITY), InternalError);
    Grid3<std::uint8_t> broken = mask;
    broken.data.pop_back();
    EXPECT_THROW(computeMorphometry(broken, Skeleton{}, 1.0), InternalError);
    Skeleton bad;
    bad.nodes.resize(1);
    bad.edges.push_back({0, 3});
    EXPECT_THROW(computeMorphometry(mask, bad, 1.0), InternalError);
}

Morphometry indices(double densityOpt, double densityRect, double coverageOpt, double coverageRect, double porosityOpt,
                    double width) {
    Morphometry m;
    m.network_density_opt = densityOpt;
    m.network_density_rect = densityRect;
    m.areal_coverage_pct_opt = coverageOpt;
    m.areal_coverage_pct_rect = coverageRect;
    m.porosity_pct_opt = porosityOpt;
    m.mean_width_m = width;
    return m;
}

TEST(CaveCategory, PaperTable4CavesAreConfined) {
    // Figure 10: Table 2 confined ranges hold all 4 opt values (0.317, 46.51, 5.59, 2.28), Table 3
    // confined all 3 rect values (0.122, 17.94, 2.28); chamber holds 0.122 and 2.28; unconfined none.
    const Morphometry f10 = indices(0.317, 0.122, 46.51, 17.94, 5.59, 2.28);
    const CategoryVotes v = categoryVotes(f10);
    EXPECT_EQ(v.unconfined, 0);
    EXPECT_EQ(v.confined, 7);
    EXPECT_EQ(v.chamber, 2);
    EXPECT_EQ(caveCategory(f10), "confined");
    // Figure 11: confined 2 (porosity 8.74, W 1.95) + 3 = 5, chamber 2 (0.179, 30.05), unconfined 0.
    const Morphometry f11 = indices(0.462, 0.179, 77.54, 30.05, 8.74, 1.95);
    EXPECT_EQ(categoryVotes(f11).confined, 5);
    EXPECT_EQ(categoryVotes(f11).chamber, 2);
    EXPECT_EQ(caveCategory(f11), "confined");
    // Figure 12: confined 2 (0.277, W 3.33) + 3 = 5, chamber 3, unconfined 1 (W 3.33).
    const Morphometry f12 = indices(0.277, 0.105, 63.66, 24.05, 14.06, 3.33);
    EXPECT_EQ(categoryVotes(f12).confined, 5);
    EXPECT_EQ(categoryVotes(f12).chamber, 3);
    EXPECT_EQ(categoryVotes(f12).unconfined, 1);
    EXPECT_EQ(caveCategory(f12), "confined");
}

TEST(CaveCategory, UnconfinedChamberMixed) {
    // Table 2 unconfined averages (0.017, 6.17 %, 0.40 %, 3.77 m) with a sparse rectangle field:
    // unconfined 4, confined 1 (W in Table 2) + 1 (W in Table 3), chamber 1 (W).
    EXPECT_EQ(caveCategory(indices(0.017, 0.008, 6.17, 3.0, 0.40, 3.77)), "unconfined");
    // A chamber: wide (20 m), dense coverage: chamber 3; confined only density_opt 0.08 → 1.
    EXPECT_EQ(caveCategory(indices(0.08, 0.05, 60.0, 50.0, 15.0, 20.0)), "chamber");
    // A tie: only the rect density 0.08 falls in a range, of both chamber and confined → 1 : 1 → mixed.
    EXPECT_EQ(caveCategory(indices(1.0, 0.08, 99.0, 99.0, 50.0, 200.0)), "mixed");
    // Bounds are inclusive.
    EXPECT_EQ(categoryVotes(indices(0.012, 0.0, 0.0, 0.0, 0.0, 0.0)).unconfined, 1);
    EXPECT_EQ(categoryRanges().size(), 14u);
}

}  // namespace
}  // namespace cavesim::morpho
