// The public C++ API (include/cavesim/cavesim.h), used as an outside program uses it: only the
// public header and libcavesim.so. The command's own files and messages are the reference: the
// `cavesim` binary (CAVESIM_BINARY) is run on the same scenario and compared with.
#include <sys/wait.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include <cavesim/cavesim.h>

namespace api = cavesim::api;
namespace fs = std::filesystem;

namespace {

const std::string kSmall = std::string(CAVESIM_SOURCE_DIR) + "/examples/small.toml";

fs::path scratch(const std::string& name) {
    const fs::path p = fs::path(CAVESIM_SCRATCH_DIR) / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs the command; returns its exit code, stderr in `err`.
int command(const std::string& args, const fs::path& dir, std::string* err = nullptr) {
    const fs::path errFile = dir / "stderr.txt";
    const std::string line =
        std::string("'") + CAVESIM_BINARY + "' " + args + " > /dev/null 2> '" + errFile.string() + "'";
    const int status = std::system(line.c_str());
    if (err) *err = readFile(errFile);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string inputErrorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const cavesim::InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

}  // namespace

TEST(Lib, ScenarioFromFileReadsTheFile) {
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    EXPECT_EQ(s.name(), "small3d");
    EXPECT_EQ(s.seed(), 7u);
    EXPECT_EQ(s.size(), (std::array<int, 3>{24, 24, 8}));
    EXPECT_EQ(s.get("stage2.iterations").asInt(), 150);
    EXPECT_EQ(s.get("source").items().size(), 2u);
    EXPECT_DOUBLE_EQ(s.get("stage2.p_rate").asReal(), 0.5);  // a default
}

TEST(Lib, BadFileGivesTheCommandsMessage) {
    const fs::path dir = scratch("bad_file");
    const fs::path bad = dir / "bad.toml";
    std::ofstream(bad) << "name = \"x\"\n[stage2]\np_rate = -1\n";
    std::string err;
    ASSERT_EQ(command("validate '" + bad.string() + "'", dir, &err), 2);
    const std::string m = inputErrorOf([&] { api::Scenario::fromTomlFile(bad.string()); });
    EXPECT_EQ("cavesim: error: " + m + "\n", err);
    EXPECT_EQ(m, bad.string() + ":3: key 'stage2.p_rate' = -1: must be a number in (0, 1e+06]");
}

TEST(Lib, SetKeyIsCheckedLikeTheFileAndFailureLeavesTheScenario) {
    api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    s.set("stage2.p_rate", 0.25);
    EXPECT_DOUBLE_EQ(s.get("stage2.p_rate").asReal(), 0.25);
    // The file parser's message, without a line (the value was set in code).
    EXPECT_EQ(inputErrorOf([&] { s.set("stage2.p_rate", -1); }),
              kSmall + ": key 'stage2.p_rate' = -1: must be a number in (0, 1e+06]");
    EXPECT_DOUBLE_EQ(s.get("stage2.p_rate").asReal(), 0.25);
    const std::string unknown = inputErrorOf([&] { s.set("stage2.p_rat", 1); });
    EXPECT_EQ(unknown.rfind(kSmall + ": unknown key 'stage2.p_rat' = 1: allowed keys here are enabled, ", 0), 0u)
        << unknown;
    EXPECT_EQ(inputErrorOf([&] { s.set("seed.x", 1); }), kSmall + ": key 'seed.x': 'seed' is not a table");
    EXPECT_EQ(inputErrorOf([&] { s.set("stage2.mesh_style", "smooth"); }).find("unknown key"), kSmall.size() + 2);
}

TEST(Lib, EveryRegistryKeyIsSettableByItsName) {
    api::Scenario s;  // the built-in default
    const std::vector<std::string> keys = api::Scenario::keys();
    EXPECT_NE(std::find(keys.begin(), keys.end(), "stage2.p_rate"), keys.end());
    EXPECT_NE(std::find(keys.begin(), keys.end(), "rock.noise.scale"), keys.end());
    EXPECT_NE(std::find(keys.begin(), keys.end(), "source"), keys.end());
    const std::string before = s.toToml();
    for (const std::string& key : keys) {
        api::Value v;
        try {
            v = s.get(key);
        } catch (const cavesim::InputError&) {
            // only a table of arrays the default leaves empty has no value
            EXPECT_TRUE(key == "rock.plane" || key == "rock.channel" || key == "rock.sphere" || key == "site.horizon" ||
                        key == "rock.inception_horizon" || key == "rock.fracture_family" || key == "recharge" ||
                        key == "phase")
                << key;
            continue;
        }
        EXPECT_NO_THROW(s.set(key, v)) << key;
    }
    EXPECT_EQ(s.toToml(), before);
}

TEST(Lib, FromTableAndUpdateChangeRelatedKeysTogether) {
    const api::Value t = api::Value::table({
        {"name", "built"},
        {"seed", 3},
        {"domain", api::Value::table({{"size", {16, 16, 6}}})},
        {"source", api::Value::list({api::Value::table({{"at", {1, 8, 4}}})})},
        {"sink", api::Value::list({api::Value::table({{"box", {{15, 6, 0}, {15, 10, 2}}}})})},
        {"stage2.iterations", 20},
    });
    api::Scenario s = api::Scenario::fromTable(t, "<built>");
    EXPECT_EQ(s.name(), "built");
    EXPECT_EQ(s.get("stage2.iterations").asInt(), 20);
    // Shrinking the block alone would leave the sink outside it; together with the sink it is fine.
    const std::string outside = inputErrorOf([&] { s.set("domain.size", {10, 16, 6}); });
    EXPECT_EQ(outside,
              "<built>: key 'sink.box' = [[15, 6, 0], [15, 10, 2]]: the sink must lie inside the domain: "
              "indices 0..9, 0..15, 0..5");
    EXPECT_EQ(s.size()[0], 16);
    s.update(api::Value::table({{"domain.size", {10, 16, 6}},
                                {"sink", api::Value::list({api::Value::table({{"box", {{9, 6, 0}, {9, 10, 2}}}})})}}));
    EXPECT_EQ(s.size()[0], 10);
    s.add("rock.sphere", api::Value::table({{"center", {5.0, 8.0, 3.0}}, {"radius", 1.5}}));
    EXPECT_EQ(s.get("rock.sphere").items().size(), 1u);
    s.clear("rock.sphere");
    EXPECT_THROW(s.get("rock.sphere"), cavesim::InputError);
}

TEST(Lib, RunMatchesTheCommandByteForByte) {
    const fs::path dir = scratch("byte_identical");
    ASSERT_EQ(command("run '" + kSmall + "' --out '" + (dir / "cli").string() + "' --quiet --threads 2", dir), 0);
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    api::RunOptions o;
    o.threads = 1;  // another thread count than the command's: the same results
    o.stage1StatePath = (dir / "stage1.vdb").string();
    const api::Result r = api::run(s, o);
    r.writeState((dir / "state.vdb").string());
    EXPECT_EQ(readFile(dir / "state.vdb"), readFile(dir / "cli" / "state.vdb"));
    EXPECT_EQ(readFile(dir / "stage1.vdb"), readFile(dir / "cli" / "stage1.vdb"));
    EXPECT_FALSE(readFile(dir / "state.vdb").empty());

    const api::Report& rep = r.report();
    // The breakthrough the command reported (report.json: "breakthrough_iteration": N,).
    const std::string cliJson = readFile(dir / "cli" / "report.json");
    const std::size_t bt = cliJson.find("\"breakthrough_iteration\": ");
    ASSERT_NE(bt, std::string::npos);
    ASSERT_TRUE(rep.breakthroughIteration.has_value());
    EXPECT_EQ(std::to_string(*rep.breakthroughIteration), cliJson.substr(bt + 26, cliJson.find(',', bt) - bt - 26));
    EXPECT_EQ(rep.sourcesConnected, 2);
    EXPECT_EQ(rep.iterations, 150);
    EXPECT_EQ(r.skeleton().nodes.size(), std::size_t(rep.skeletonNodes));
    EXPECT_EQ(r.mesh().triangles.size(), std::size_t(rep.meshFaces));
    EXPECT_TRUE(rep.meshClosed);
    // The report's measurements are the command's report.json measurements.
    const std::string cliReport = readFile(dir / "cli" / "report.json");
    for (const char* key : {"\"morphometry\"", "\"network\"", "\"graph_metrics\""}) {
        const auto section = [&](const std::string& doc) {
            const std::size_t at = doc.find(key);
            return at == std::string::npos ? std::string() : doc.substr(at, doc.find("\n  }", at) - at);
        };
        EXPECT_EQ(section(rep.json), section(cliReport)) << key;
        EXPECT_FALSE(section(rep.json).empty()) << key;
    }
}

TEST(Lib, GridsAndTransform) {
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    api::RunOptions o;
    o.mesh = false;
    o.analysis = false;
    const api::Result r = api::run(s, o);
    EXPECT_EQ(r.dims(), (std::array<int, 3>{24, 24, 8}));
    EXPECT_EQ(r.porosity().size(), 24u * 24u * 8u);
    // Source 1 at (2, 4, 6), sink box [[22, 9, 0], [23, 14, 2]].
    EXPECT_TRUE(r.flags().at(2, 4, 6) & api::kFlagSource);
    EXPECT_TRUE(r.flags().at(23, 14, 2) & api::kFlagSink);
    EXPECT_FALSE(r.flags().at(23, 15, 2) & api::kFlagSink);
    EXPECT_EQ(r.pressure().at(22, 9, 0), 0.0f);
    EXPECT_EQ(r.zone().at(2, 4, 6), 0);
    EXPECT_TRUE(r.mesh().vertices.empty());
    EXPECT_TRUE(r.skeleton().nodes.empty());
    const auto w = r.worldFromIndex(2, 4, 6);
    EXPECT_EQ(w, (std::array<double, 3>{2.5, 4.5, 6.5}));
    EXPECT_EQ(r.indexFromWorld(w[0], w[1], w[2]), (std::array<double, 3>{2, 4, 6}));
}

TEST(Lib, CancelStopsTheRun) {
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    api::RunOptions o;
    int last = 0;
    o.progress = [&](const std::string& phase, long done, long) {
        if (phase == "stage 2") {
            last = int(done);
            if (done == 5) o.cancel.cancel();
        }
    };
    EXPECT_THROW(api::run(s, o), cavesim::Cancelled);
    EXPECT_EQ(last, 5);  // cancelled at the next progress step
    api::RunOptions thrown;
    thrown.progress = [](const std::string& phase, long, long) {
        if (phase == "stage 2") throw std::runtime_error("stop here");
    };
    EXPECT_THROW(api::run(s, thrown), std::runtime_error);
}

TEST(Lib, StageOneLimitGivesTheCommandsMessage) {
    const fs::path dir = scratch("limit");
    const fs::path file = dir / "limit.toml";
    std::ofstream(file) << readFile(kSmall) << "\n[stage1]\nmax_graph_voxels = 100\n";
    std::string err;
    ASSERT_EQ(command("run '" + file.string() + "' --out '" + (dir / "out").string() + "' --quiet", dir, &err), 2);
    const std::string m = inputErrorOf([&] { api::run(api::Scenario::fromTomlFile(file.string())); });
    EXPECT_EQ("cavesim: error: " + m + "\n", err);
    EXPECT_NE(m.find("'stage1.max_graph_voxels' = 100"), std::string::npos) << m;
}
