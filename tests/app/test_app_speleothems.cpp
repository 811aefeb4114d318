// A run with [speleothems] on: the decorated mesh, the growth pictures and the report section.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/output_dir.h"
#include "app/pipeline.h"
#include "sim/scenario_io.h"

using namespace cavesim;
namespace fs = std::filesystem;

namespace {

const char* kDecorated = R"(name = "small_decorated"
seed = 5
[domain]
size = [20, 12, 8]
voxel_size = 2.0
[[source]]
at = [2, 3, 6]
[[source]]
at = [2, 9, 6]
pressure = 0.5
[[sink]]
box = [[19, 0, 0], [19, 11, 7]]
[stage2]
iterations = 40
[output]
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
    const fs::path out = fs::temp_directory_path() / ("cavesim_test_app_speleo_" + std::to_string(::getpid())) / "run";
    fs::remove_all(out);
    fs::create_directories(out.parent_path());
    app::OutputDir dir(out, true);
    dir.open();
    const app::PipelineResult r = app::runPipeline(s, dir, {});
    dir.commit();
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
    fs::remove_all(out.parent_path());
}

TEST(AppSpeleothems, OffByDefault) {
    Scenario s;
    EXPECT_FALSE(s.speleothems.enabled);
}
