// A run with [speleothems] on: the decorated mesh, the growth pictures and the report section.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

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
    std::ifstream md(out / "report.md");
    std::stringstream text;
    text << md.rdbuf();
    EXPECT_NE(text.str().find("## Speleothems"), std::string::npos);
    fs::remove_all(out);
}

TEST(AppSpeleothems, OffByDefault) {
    Scenario s;
    EXPECT_FALSE(s.speleothems.enabled);
}
