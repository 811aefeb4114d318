// `cavesim reproduce geology`: the settings and their pictures, the levels of phreatic passages,
// the generated page from hand-made reports.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/geology_settings.h"

namespace cavesim::app {
namespace {

nlohmann::json passage(const char* cls, double zMin, double zMax, nlohmann::json height) {
    return {{"class", cls}, {"z_min_m", zMin}, {"z_max_m", zMax}, {"z_m", (zMin + zMax) / 2}, {"height_m", height}};
}

TEST(GeologySettings, TheFourSettingsAndTheirPictures) {
    const std::vector<GeologySetting>& s = geologySettings();
    ASSERT_EQ(s.size(), 4u);
    EXPECT_STREQ(s[0].scenario, "branchwork");
    EXPECT_STREQ(s[1].scenario, "network_maze");
    EXPECT_STREQ(s[2].scenario, "anastomotic");
    EXPECT_STREQ(s[3].scenario, "multilevel");
    for (int i = 0; i < 3; ++i) EXPECT_STREQ(s[i].picture, "plan.png");
    EXPECT_STREQ(s[3].picture, "side_xz.png");
    EXPECT_EQ(geologyPictureName("multilevel"), "geology_multilevel.png");
    EXPECT_EQ(reproduceDefaultDoc(ReproduceSet::kGeology), "docs/geology_settings.md");
    EXPECT_EQ(reproduceDefaultDoc(ReproduceSet::kPaper), "docs/reproduction.md");
    EXPECT_EQ(reproduceDefaultOut(ReproduceSet::kGeology), "out/geology");
    EXPECT_EQ(reproduceDefaultOut(ReproduceSet::kPaper), "out/reproduce");
}

TEST(GeologySettings, LevelsGroupTubesAndKeyholesWhoseExtentsOverlap) {
    EXPECT_EQ(passageLevels(nlohmann::json()), 0);
    EXPECT_EQ(passageLevels(nlohmann::json{{"passages", nlohmann::json::array()}}), 0);
    // Extents [z_min − h/2, z_max + h/2] of tubes, [z_min, z_max] of keyholes: [25, 35], [32, 36] overlap; [66, 76]
    // alone; [106, 118] and [115, 121] overlap. Canyons, "other" and "short" passages do not count, even between
    // levels.
    nlohmann::json cs = {
        {"passages",
         {passage("tube", 30, 30, 10.0), passage("keyhole", 32, 36, 8.0), passage("canyon", 30, 110, 90.0),
          passage("tube", 71, 71, 10.0), passage("other", 50, 50, 40.0), passage("short", 90, 90, nullptr),
          passage("tube", 110, 114, 8.0), passage("tube", 118, 118, 6.0)}}};
    EXPECT_EQ(passageLevels(cs), 3);
    // Touching extents are one level ([25, 35] and [35, 45]); a gap of 1 m makes two.
    EXPECT_EQ(passageLevels({{"passages", {passage("tube", 30, 30, 10.0), passage("tube", 40, 40, 10.0)}}}), 1);
    EXPECT_EQ(passageLevels({{"passages", {passage("tube", 30, 30, 10.0), passage("tube", 41, 41, 10.0)}}}), 2);
    // A chain: each overlaps the next, the first and the last do not — one level.
    EXPECT_EQ(passageLevels(
                  {{"passages",
                    {passage("tube", 48, 48, 10.0), passage("tube", 30, 30, 10.0), passage("tube", 39, 39, 10.0)}}}),
              1);
    // A tube climbing more than its height (a ramp or a round shaft from 34 to 70 m, 16 m high) joins
    // the levels at 34 and 72 m but does not make them one; climbing exactly its height it counts.
    EXPECT_EQ(passageLevels(
                  {{"passages",
                    {passage("tube", 34, 34, 16.0), passage("tube", 34, 70, 16.0), passage("tube", 72, 74, 16.0)}}}),
              2);
    EXPECT_EQ(passageLevels(
                  {{"passages",
                    {passage("tube", 34, 34, 16.0), passage("tube", 34, 50, 16.0), passage("tube", 62, 62, 16.0)}}}),
              1);
    // A keyhole 88 m high (mostly canyon) at 114–144 m does not reach down to the tubes at 70–74 m.
    EXPECT_EQ(passageLevels({{"passages", {passage("tube", 70, 74, 16.0), passage("keyhole", 114, 144, 88.0)}}}), 2);
    // A passage without a height counts by its centreline range alone.
    EXPECT_EQ(passageLevels({{"passages", {passage("tube", 30, 30, nullptr), passage("tube", 31, 31, nullptr)}}}), 2);
}

TEST(GeologySettings, PageShowsClassMetricsLevelsPhasesAndPictures) {
    nlohmann::json r;
    r["grid"] = {64, 48, 16};
    r["voxel_size_m"] = 4.0;
    r["pattern"] = {
        {"class", "branchwork"},
        {"rule", "loops per branch 0 < 0.2"},
        {"criteria",
         {{"branches", 11}, {"loops", 0}, {"loops_per_branch", 0.0}, {"bed_share", 1.0}, {"family_share", nullptr}}}};
    r["morphometry"] = {{"length_m", 779.4}, {"vertical_range_m", 64.0}};
    // In range of the 34 real caves: h_or, len_mean_m, h_len, k_mean, spl, cpd (6); out: cv_len, r_k,
    // tortuosity.
    r["graph_metrics"] = {{"too_small", false}, {"h_or", 0.9},       {"len_mean_m", 50.0}, {"cv_len", 0.6},
                          {"h_len", 0.5},       {"k_mean", 2.0},     {"r_k", -0.6},        {"spl", 3.0},
                          {"cpd", 0.3},         {"tortuosity", 1.03}};
    r["cross_sections"] = {
        {"passages", {passage("tube", 40, 50, 10.0)}},
        {"summary",
         {{{"class", "tube"}, {"passages", 1}, {"z_min_m", 40.0}, {"z_max_m", 50.0}, {"z_mean_m", 45.0}},
          {{"class", "canyon"}, {"passages", 0}}}}};
    r["stage2"] = {{"iterations", 200}, {"breakthrough_iteration", 85}};
    r["timing_s"] = {{"total", 4.53}};
    nlohmann::json m = r;
    m["stage2"] = {
        {"iterations", 600},
        {"breakthrough_iteration", 150},
        {"phases",
         {{{"first_iteration", 1}, {"iterations", 300}, {"water_table", 28.0}, {"breakthrough_iteration", 150}},
          {{"first_iteration", 301}, {"iterations", 300}, {"water_table", 8.0}, {"breakthrough_iteration", nullptr}}}}};
    const std::string md = geologySettingsMarkdown({{"branchwork", "plan", r}, {"multilevel", "side view x–z", m}}, 2);
    const auto has = [&md](const std::string& text) {
        EXPECT_NE(md.find(text), std::string::npos) << "missing: " << text << "\n" << md;
    };
    has("Generated by `cavesim reproduce geology` (2 thread(s))");
    has("| [branchwork](#branchwork) | branchwork | 779 | 11 | 0 | 6/9 | 1 | 85 | 4.5 |");
    has("| [multilevel](#multilevel) | branchwork | 779 | 11 | 0 | 6/9 | 1 | 150 / – | 4.5 |");
    has("`cv_len` 0.6 (0.9 – 2.56), `r_k` -0.6 (-0.56 – -0.15), `tortuosity` 1.03 (1.12 – 1.54)");
    has("64 × 48 × 16 voxels of 4 m (256 × 192 × 64 m), 200 stage-2 iterations");
    has("tube 1, z 40–50 m (mean 45); 1 level(s)");
    has("1) iterations 1–300, water table at z = 28 voxels, breakthrough 150; 2) iterations 301–600, water table at "
        "z = 8 voxels, breakthrough –.");
    has("![branchwork, seed 1, plan](images/geology_branchwork.png)");
    has("![multilevel, seed 1, side view x–z](images/geology_multilevel.png)");
    EXPECT_EQ(md.find("canyon 0"), std::string::npos);             // classes without passages left out
    EXPECT_EQ(md.find("fracture families –"), std::string::npos);  // no families: not mentioned
    // Too few branches for network statistics: not compared.
    r["graph_metrics"]["too_small"] = true;
    const std::string small = geologySettingsMarkdown({{"branchwork", "plan", r}}, 1);
    EXPECT_NE(small.find("| too small |"), std::string::npos) << small;
}

}  // namespace
}  // namespace cavesim::app
