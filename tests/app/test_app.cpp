// The application layer (src/app): the run pipeline, the state files written and read back in one
// schema, the report rebuilt from a run folder, the seed override, and limits reported against the
// scenario file.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "app/commands.h"
#include "app/state.h"
#include "app_test_util.h"
#include "core/error.h"
#include "sim/cave.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/simulate.h"
#include "sim/stage1.h"
#include "sim/stage2.h"

using namespace cavesim;
using namespace cavesim::apptest;
namespace fs = std::filesystem;

TEST(App, SeedTextIsDigitsOnly) {
    EXPECT_EQ(app::parseSeed("0"), 0u);
    EXPECT_EQ(app::parseSeed("0042"), 42u);
    EXPECT_EQ(app::parseSeed("9223372036854775807"), 9223372036854775807ull);
    for (const char* bad : {"", "-1", "+3", "1e3", "9223372036854775808", "99999999999999999999", "12a"})
        EXPECT_THROW(app::parseSeed(bad), InputError) << bad;
}

TEST(App, PipelineWritesEveryFileAndTheStateReadsBackExactly) {
    const Scenario s = parseScenarioString(kSmall, "small.toml");
    const fs::path out = scratch("run");
    const app::PipelineResult r = runInto(s, out);
    for (const char* f : {"scenario.toml", "state.vdb", "state.cavesim", "stage1.vdb", "cave.obj", "cave.ply",
                          "skeleton.json", "skeleton_nodes.dat", "skeleton_links.dat", "report.json", "report.md"})
        EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    EXPECT_EQ(r.report["scenario"], "small");
    EXPECT_EQ(r.report["stage2"]["iterations"], 40);

    // The state file holds the in-memory result, grid for grid (floats stored exactly).
    const Domain mem = simulate(s);
    const Domain back = app::loadState(out, s, r.report);
    EXPECT_EQ(back.porosity.data, mem.porosity.data);
    EXPECT_EQ(back.porosity0.data, mem.porosity0.data);
    EXPECT_EQ(back.flags.data, mem.flags.data);
    EXPECT_EQ(back.zone.data, mem.zone.data);
    EXPECT_EQ(back.pressure.data, mem.pressure.data);
    EXPECT_EQ(back.flow.data, mem.flow.data);
    EXPECT_EQ(back.water.data, mem.water.data);
    EXPECT_EQ(back.sourceVoxels, mem.sourceVoxels);
    EXPECT_EQ(back.sinkVoxels, mem.sinkVoxels);
}

TEST(App, StateAfterStage1ShowsProtochannelsOpenedWithoutChangingTheDomain) {
    Scenario s = parseScenarioString(kSmall, "small.toml");
    s.stage2.enabled = false;
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    runStage1(d, s.stage1, rng);
    const Grid3<float> shown = app::recordedPorosity(d, s, app::StateMoment::kFinal);
    long opened = 0;
    for (std::size_t v = 0; v < d.dims.count(); ++v) {
        EXPECT_EQ(d.porosity[v], d.porosity0[v]);
        if (d.flags[v] & kProtochannel) {
            EXPECT_EQ(shown[v], std::max(d.porosity0[v], float(s.stage1.protochannelPorosity)));
            ++opened;
        } else {
            EXPECT_EQ(shown[v], d.porosity[v]);
        }
    }
    EXPECT_GT(opened, 0);
    // With stage 2 the final state is the domain's own porosity.
    s.stage2.enabled = true;
    EXPECT_EQ(app::recordedPorosity(d, s, app::StateMoment::kFinal).data, d.porosity.data);
}

TEST(App, ChangedStateFileIsRefusedBeforeReading) {
    const Scenario s = parseScenarioString(kSmall, "small.toml");
    const fs::path out = scratch("changed");
    const app::PipelineResult r = runInto(s, out);
    {
        std::fstream f(out / "state.cavesim", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(100);
        f.put('\x7f');
    }
    EXPECT_THROW(app::loadState(out, s, r.report), InputError);
    EXPECT_THROW(app::rebuildReport(out.string()), InputError);
}

TEST(App, RebuiltReportMeasuresTheSameCave) {
    const Scenario s = parseScenarioString(kSmall, "small.toml");
    const fs::path out = scratch("rebuild");
    const app::PipelineResult r = runInto(s, out);
    const std::string msg = app::rebuildReport(out.string());
    EXPECT_NE(msg.find("rebuilt"), std::string::npos);
    std::ifstream in(out / "report.json");
    const nlohmann::json again = nlohmann::json::parse(in);
    for (const char* k : {"network", "morphometry", "graph_metrics", "skeleton", "cave_category", "pattern",
                          "cross_sections", "checksums"})
        EXPECT_EQ(again[k], r.report[k]) << k;
}

TEST(App, AlsoMeasureEqualsARunWithTheOtherCaveDefinition) {
    Scenario s = parseScenarioString(kSmall, "small.toml");
    s.output.mesh = false;
    app::PipelineOptions o;
    o.alsoMeasure = CaveExtent::kWithProtochannels;
    const app::PipelineResult both = runInto(s, scratch("both"), o);
    s.output.cave = CaveExtent::kWithProtochannels;
    const app::PipelineResult other = runInto(s, scratch("other"));
    for (const char* k :
         {"network", "morphometry", "graph_metrics", "skeleton", "cave_category", "pattern", "cross_sections"})
        EXPECT_EQ(both.alsoMeasured[k], other.report[k]) << k;
}

TEST(App, Stage1LimitNamesTheFileLineAndKey) {
    const std::string text = kSmall + "[stage1]\nmax_graph_voxels = 100\n";
    const Scenario s = parseScenarioString(text, "limits.toml");
    try {
        runInto(s, scratch("limit"));
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string m = e.what();
        // The key's own line (the last line of the file), and the [[source]] entry's.
        const auto keyLine = std::count(text.begin(), text.end(), '\n');
        EXPECT_EQ(m.rfind("limits.toml:" + std::to_string(keyLine) + ": key 'stage1.max_graph_voxels' = 100: ", 0), 0u)
            << m;
        EXPECT_NE(m.find("(the [[source]] entry at line 6)"), std::string::npos) << m;
        EXPECT_NE(m.find("source 1"), std::string::npos) << m;
    }
}

TEST(App, RequestedScenarioAppliesOverridesAndValidates) {
    app::RunRequest q;
    q.seed = "77";
    q.meshStyle = MeshStyle::kVoxel;
    const Scenario s = app::requestedScenario(q);  // the built-in default
    EXPECT_EQ(s.seed, 77u);
    EXPECT_EQ(s.output.meshStyle, MeshStyle::kVoxel);
    EXPECT_EQ(s.name, "fig10");
    q.seed = "x";
    EXPECT_THROW(app::requestedScenario(q), InputError);
}

TEST(App, ValidateSummaryNamesTheGrid) {
    const fs::path p = scratch("v.toml");
    std::ofstream(p) << kSmall;
    const std::string line = app::validateSummary(p.string());
    EXPECT_NE(line.find("ok: scenario 'small', grid 20 x 12 x 8"), std::string::npos) << line;
    EXPECT_NE(line.find("2 source(s), 1 sink(s)"), std::string::npos) << line;
}

TEST(App, ValidateSummaryCountsPhasesAndSiteTerminals) {
    // The phases' iterations replace [stage2] iterations; a [site]'s sinkholes and springs are
    // sources and sinks too (the summary once said "0 source(s), 0 sink(s)" for them).
    const fs::path dir = scratch("site_summary");
    fs::create_directories(dir);
    std::ofstream(dir / "sinkholes.csv") << "x,y,name\n2.5,3.5,A\n7.5,3.5,B\n";
    std::ofstream(dir / "springs.csv") << "x,y,z,name\n19.5,5.5,2.5,S\n";
    std::ofstream(dir / "v.toml") << "name = \"s\"\n[domain]\nsize = [20, 12, 8]\n[stage2]\niterations = 40\n"
                                     "[[phase]]\niterations = 3\n[[phase]]\niterations = 4\n"
                                     "[site]\nsinkholes = \"sinkholes.csv\"\nsprings = \"springs.csv\"\n";
    const std::string line = app::validateSummary((dir / "v.toml").string());
    EXPECT_NE(line.find("2 source(s), 1 sink(s), stage 1 on, stage 2 7 iterations"), std::string::npos) << line;
}
