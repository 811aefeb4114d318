// A run with [speleothems] on: the decorated mesh, the growth pictures and the report section.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/speleo_report.h"
#include "app_test_util.h"
#include "sim/scenario_io.h"

using namespace cavesim;
namespace fs = std::filesystem;

namespace {

const std::string kDecorated = std::string("name = \"small_decorated\"\n") + apptest::kSmallCave + R"([output]
image_width = 256
[speleothems]
enabled = true
years = 2000
voxel_size = 0.25
roughness = 0.3
roughness_scale = 1.5
frames = 2
)";

}  // namespace

TEST(AppSpeleothems, RunWritesTheDecoratedCaveItsPicturesAndItsReport) {
    const Scenario s = parseScenarioString(kDecorated, "decorated.toml");
    const fs::path out = apptest::scratch("speleo");
    const app::PipelineResult r = apptest::runInto(s, out);
    for (const char* f : {"cave_decorated.obj", "cave_decorated.ply", "cave_decorated.glb",
                          "images/speleo_perspective_00.png", "images/speleo_perspective_01.png"})
        EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    ASSERT_TRUE(r.report.contains("speleothems"));
    const auto& j = r.report["speleothems"];
    EXPECT_EQ(j["years"], 2000.0);
    EXPECT_TRUE(j["mesh"]["closed"].get<bool>());
    EXPECT_TRUE(j["mesh"]["manifold"].get<bool>());
    for (const char* f : {"cave_decorated.obj", "cave_decorated.ply", "cave_decorated.glb"}) {
        ASSERT_TRUE(r.report["files"].contains(f)) << f;  // fingerprinted beside the state files
        EXPECT_EQ(r.report["files"][f]["bytes"].get<std::uint64_t>(), fs::file_size(out / f)) << f;
    }
    std::ifstream md(out / "report.md");
    std::stringstream text;
    text << md.rdbuf();
    EXPECT_NE(text.str().find("## Speleothems"), std::string::npos);
    fs::remove_all(out);
}

TEST(AppSpeleothems, MeshOffWritesNoDecoratedMeshAndStillCaveReportsItsYears) {
    // [output] mesh = false: no cave_decorated.*, as no cave.obj. A cave that is not drained grows
    // nothing: the report gives the years decorated (the surface stays as it is) and says why.
    std::string text = kDecorated;
    text.replace(text.find("image_width = 256\n"), 18, "image_width = 256\nmesh = false\n");
    text += "drained = false\n";
    const Scenario s = parseScenarioString(text, "still.toml");
    const fs::path out = apptest::scratch("speleo_still");
    const app::PipelineResult r = apptest::runInto(s, out);
    for (const char* f : {"cave_decorated.obj", "cave_decorated.ply", "cave_decorated.glb", "cave.obj"}) {
        EXPECT_FALSE(fs::exists(out / f)) << f;
        EXPECT_FALSE(r.report["files"].contains(f)) << f;
    }
    const auto& j = r.report["speleothems"];
    EXPECT_EQ(j["years"], 2000.0);
    EXPECT_EQ(j["steps"], 0);
    EXPECT_EQ(j["stalactites"], 0);
    EXPECT_EQ(j["mesh_files"], nlohmann::json::array());
    ASSERT_TRUE(j.contains("note"));
    EXPECT_EQ(j["note"].get<std::string>().rfind("nothing grows: no ceiling drip point moves", 0), 0u) << j["note"];
    std::ifstream md(out / "report.md");
    std::stringstream mdText;
    mdText << md.rdbuf();
    EXPECT_NE(mdText.str().find("after 2000 years (0 steps"), std::string::npos) << mdText.str();
    EXPECT_NE(mdText.str().find("Mesh not written (mesh output is off)"), std::string::npos);
    fs::remove_all(out);
}

TEST(AppSpeleothems, OffByDefault) {
    Scenario s;
    EXPECT_FALSE(s.speleothems.enabled);
}

TEST(AppSpeleothems, ReportLengthIsTheGrownMaterialBelowTheOriginalCeiling) {
    // A cone 30 mm long, 12 mm in radius, hanging from a flat ceiling, on a 2 mm level set, grown
    // 400 years with the natural parameters: its tip moves down at Short's c = α·l_Q = 0.1 mm/yr,
    // so the grown length is c·400 yr; the cone itself (30 mm) is not counted.
    constexpr double kH = 0.002, kR = 0.012, kHeight = 0.03, kYears = 400;
    const double sinA = kR / std::hypot(kR, kHeight), cosA = kHeight / std::hypot(kR, kHeight);
    speleo::DecorationField f =
        speleo::fieldFromFunction({-0.04, -0.04, -0.08}, {0.04, 0.04, 0.01}, kH, [&](const Vec3d& x) {
            // Signed distance, > 0 in rock: the half space z ≥ 0 united with the cone (apex at
            // z = −H, opening up); the room's walls and floor 8 cm away.
            const double rho = std::hypot(x[0], x[1]), up = x[2] + kHeight;
            const double cone = up * sinA - rho * cosA < 0 && up * cosA + rho * sinA < 0
                                    ? -std::hypot(rho, up)     // below the apex: distance to it
                                    : up * sinA - rho * cosA;  // to the cone's side
            const double walls = std::max({std::abs(x[0]) - 0.035, std::abs(x[1]) - 0.035, -0.07 - x[2]});
            return std::max(std::max(x[2], cone), walls);
        });
    SpeleothemOptions o;
    o.enabled = true;
    o.voxelSize = kH;
    o.convexity = 20.0;
    o.minSize = 0.005;
    o.roughness = 0;
    o.dripVariability = 0;
    o.stalagmites = false;
    o.years = kYears;
    const speleo::DecorationField original = f;
    speleo::DecorationSummary sum;
    sum.voxelSize = kH;
    sum.years = kYears;
    sum.stalactites = speleo::grow(f, o).stalactites;
    speleo::measureGrowth(original, sum.stalactites);
    const nlohmann::json j = app::speleothemsJson(sum);
    const double c = o.alpha * o.lQ;  // m/yr, Short's tip speed
    ASSERT_EQ(j["stalactites"].get<long>(), 1);
    const double length = j["largest"][0]["length_m"].get<double>(), tipZ = j["largest"][0]["tip_m"][2].get<double>();
    std::printf("grown length %.2f mm, hand-computed c·T %.2f mm, tip z %.2f mm\n", length * 1e3, c * kYears * 1e3,
                tipZ * 1e3);
    EXPECT_NEAR(length, -kHeight - tipZ, 0.25 * kH);     // from the original apex down to the tip
    EXPECT_NEAR(length, c * kYears, 0.15 * c * kYears);  // 40 mm (a sharp apex lags ~10 %)
    EXPECT_EQ(j["longest_m"].get<double>(), length);
}
