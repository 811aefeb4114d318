// The public C++ API (include/cavesim/cavesim.h), used as an outside program uses it: only the
// public header and libcavesim.so. The command's own files and messages are the reference: the
// `cavesim` binary (CAVESIM_BINARY) is run on the same scenario and compared with.
#include <sys/wait.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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

/// Runs the command (with `env`, "NAME=value ", before it); returns its exit code, stderr in `err`.
int command(const std::string& args, const fs::path& dir, std::string* err = nullptr, const std::string& env = "") {
    const fs::path errFile = dir / "stderr.txt";
    const std::string line = env + "'" + CAVESIM_BINARY + "' " + args + " > /dev/null 2> '" + errFile.string() + "'";
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

namespace {

/// The same bits: every grid, the mesh, the skeleton and the report's numbers (not its timings).
void expectSameResult(const api::Result& a, const api::Result& b, const std::string& what) {
    SCOPED_TRACE(what);
    const auto same = [](const auto& x, const auto& y) {
        return x.dims == y.dims && std::memcmp(x.data, y.data, x.size() * sizeof(*x.data)) == 0;
    };
    EXPECT_TRUE(same(a.porosity(), b.porosity()));
    EXPECT_TRUE(same(a.porosity0(), b.porosity0()));
    EXPECT_TRUE(same(a.pressure(), b.pressure()));
    EXPECT_TRUE(same(a.flow(), b.flow()));
    EXPECT_TRUE(same(a.water(), b.water()));
    EXPECT_TRUE(same(a.flags(), b.flags()));
    EXPECT_TRUE(same(a.zone(), b.zone()));
    EXPECT_TRUE(same(a.caveMask(), b.caveMask()));
    EXPECT_EQ(a.mesh().vertices, b.mesh().vertices);
    EXPECT_EQ(a.mesh().triangles, b.mesh().triangles);
    ASSERT_EQ(a.skeleton().nodes.size(), b.skeleton().nodes.size());
    for (std::size_t n = 0; n < a.skeleton().nodes.size(); ++n) {
        EXPECT_EQ(a.skeleton().nodes[n].position, b.skeleton().nodes[n].position);
        EXPECT_EQ(a.skeleton().nodes[n].radius, b.skeleton().nodes[n].radius);
    }
    EXPECT_EQ(a.skeleton().edges, b.skeleton().edges);
    const api::Report &p = a.report(), &q = b.report();
    EXPECT_EQ(p.iterations, q.iterations);
    EXPECT_EQ(p.breakthroughIteration, q.breakthroughIteration);
    EXPECT_EQ(p.sourceConnectedIteration, q.sourceConnectedIteration);
    EXPECT_EQ(p.channelVoxels, q.channelVoxels);
    EXPECT_EQ(p.zones, q.zones);
    EXPECT_EQ(p.protochannelVoxels, q.protochannelVoxels);
    EXPECT_EQ(p.sourcesConnected, q.sourcesConnected);
    EXPECT_EQ(p.confluences, q.confluences);
    EXPECT_EQ(p.phreaticLoops, q.phreaticLoops);
    EXPECT_EQ(p.skeletonNodes, q.skeletonNodes);
    EXPECT_EQ(p.lengthM, q.lengthM);  // exact: the same bits
    EXPECT_EQ(p.volumeM3, q.volumeM3);
    EXPECT_EQ(p.networkDensityOpt, q.networkDensityOpt);
    EXPECT_EQ(p.porosityPctRect, q.porosityPctRect);
    EXPECT_EQ(p.meanWidthM, q.meanWidthM);
    EXPECT_EQ(p.meshFaces, q.meshFaces);
    EXPECT_EQ(p.meshVolumeM3, q.meshVolumeM3);
    // The report document, its timings and thread count aside.
    const auto numbers = [](const std::string& json) {
        std::istringstream in(json);
        std::string line, out;
        int skip = 0;  // inside "timing_s": { … }
        while (std::getline(in, line)) {
            if (line.find("\"timing") != std::string::npos && line.find('{') != std::string::npos) skip = 1;
            if (skip) {
                if (line.find('}') != std::string::npos) skip = 0;
                continue;
            }
            if (line.find("\"threads\"") != std::string::npos || line.find("seconds") != std::string::npos) continue;
            out += line + "\n";
        }
        return out;
    };
    EXPECT_EQ(numbers(p.json), numbers(q.json));
}

/// Runs `s` with checkpoints every `every` iterations into `file`, stopped (by `stop`) when stage 2
/// reports iteration `at` done; expects Cancelled.
void runStopped(const api::Scenario& s, const fs::path& file, int every, long at, bool throwFromProgress) {
    api::RunOptions o;
    o.threads = 2;
    o.checkpointPath = file.string();
    o.checkpointEvery = every;
    o.progress = [&](const std::string& phase, long done, long) {
        if (phase != "stage 2" || done != at) return;
        if (throwFromProgress) throw cavesim::Cancelled("stopped by the test");
        o.cancel.cancel();
    };
    EXPECT_THROW(api::run(s, o), cavesim::Cancelled);
}

/// Resumes `file`; the first stage-2 iteration reported is `first`.
api::Result resumed(const fs::path& file, long first, int threads = 1) {
    api::RunOptions o;
    o.threads = threads;  // another thread count: the same results
    long seen = 0;
    o.progress = [&](const std::string& phase, long done, long) {
        if (phase == "stage 2" && seen == 0) seen = done;
    };
    api::Result r = api::resume(file.string(), o);
    EXPECT_EQ(seen, first);
    return r;
}

}  // namespace

TEST(Lib, CancelledRunResumesFromItsCheckpointBitForBit) {
    const fs::path dir = scratch("checkpoint");
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    api::RunOptions o;
    o.threads = 2;
    const api::Result whole = api::run(s, o);
    ASSERT_EQ(whole.report().iterations, 150);

    const fs::path file = dir / "small.ckpt";
    runStopped(s, file, 20, 50, false);  // cancelled after iteration 50: the checkpoint after 40 stays
    ASSERT_TRUE(fs::is_regular_file(file));
    const api::Result r = resumed(file, 41);
    expectSameResult(whole, r, "cancelled after 50, checkpoint after 40");
    EXPECT_EQ(r.scenario().toToml(), s.toToml());
    EXPECT_EQ(r.scenario().sourceName(), kSmall);

    // A resumed run checkpoints in turn, into the file it resumed from; stopped again and resumed.
    api::RunOptions again;
    again.threads = 2;
    again.checkpointPath = file.string();
    again.checkpointEvery = 30;
    again.progress = [&](const std::string& phase, long done, long) {
        if (phase == "stage 2" && done == 100) throw cavesim::Cancelled("stopped again");
    };
    EXPECT_THROW(api::resume(file.string(), again), cavesim::Cancelled);
    expectSameResult(whole, resumed(file, 91), "stopped again after 100, checkpoint after 90");
}

TEST(Lib, CheckpointsPassBetweenTheCommandAndTheLibrary) {
    const fs::path dir = scratch("checkpoint_command");
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    const api::Result whole = api::run(s);
    // The command kills itself after iteration 70, its checkpoint after 60 left beside --out.
    const int code =
        command("run '" + kSmall + "' --out '" + (dir / "out").string() + "' --quiet --threads 2 --checkpoint-every 30",
                dir, nullptr, "CAVESIM_TEST_KILL_AT_ITERATION=70 ");
    EXPECT_NE(code, 0);
    const fs::path file = dir / ".out.checkpoint" / "checkpoint.cavesim";
    ASSERT_TRUE(fs::is_regular_file(file));
    expectSameResult(whole, resumed(file, 61, 2), "the command's checkpoint after 60");

    // The other way: the library's checkpoint, where `cavesim resume DIR` looks for it, finishes the
    // command's folder with the state file of a run that never stopped.
    const fs::path ours = dir / ".lib.checkpoint" / "checkpoint.cavesim";
    fs::create_directories(ours.parent_path());
    runStopped(s, ours, 20, 50, false);
    ASSERT_EQ(command("resume '" + (dir / "lib").string() + "' --quiet --threads 2", dir), 0);
    whole.writeState((dir / "state.vdb").string());
    EXPECT_EQ(readFile(dir / "lib" / "state.vdb"), readFile(dir / "state.vdb"));
    EXPECT_FALSE(fs::exists(ours));  // spent once the folder is in place
    // Unless the run took pictures before the checkpoint: the library draws none.
    api::Scenario pictured = s;
    pictured.set("stage2.snapshots", {10});
    const fs::path drawn = dir / ".pic.checkpoint" / "checkpoint.cavesim";
    fs::create_directories(drawn.parent_path());
    runStopped(pictured, drawn, 20, 30, false);
    std::string err;
    EXPECT_EQ(command("resume '" + (dir / "pic").string() + "' --quiet", dir, &err), 2);
    EXPECT_NE(err.find("0 of the 1 stage-2 pictures"), std::string::npos) << err;
}

TEST(Lib, PhasedRunResumesFromItsCheckpointBitForBit) {
    const fs::path dir = scratch("checkpoint_phased");
    // Base-level phases under a dipping water table (tests/cli/checkpoint.sh's, shorter).
    const api::Scenario s = api::Scenario::fromTomlString(R"(name = "phased"
seed = 5
[domain]
size = [28, 14, 20]
[rock]
porosity = 0.05
noise = { amplitude = 0.01, scale = 4.0 }
[[source]]
at = [5, 4, 19]
[[source]]
at = [12, 10, 19]
[[sink]]
box = [[27, 5, 12], [27, 8, 14]]
[[sink]]
box = [[27, 5, 3], [27, 8, 5]]
[stage1]
enabled = false
[stage2]
p_rate = 0.05
p_rate_channel = 0.001
source_porosity = 0.5
[hydrology]
water_table = 13
dip = 5
dip_direction = 90
vadose_lateral = 0.1
[[phase]]
iterations = 30
sinks = [1]
[[phase]]
iterations = 30
water_table = 4
sinks = [2]
sources = [1]
[[phase]]
iterations = 10
water_table = 4
)",
                                                          "phased.toml");
    api::RunOptions o;
    o.threads = 2;
    o.mesh = false;
    const api::Result whole = api::run(s, o);
    ASSERT_EQ(whole.report().iterations, 70);
    const fs::path file = dir / "phased.ckpt";
    runStopped(s, file, 15, 31, true);  // the checkpoint after 30, the end of phase 1
    api::RunOptions ro;
    ro.mesh = false;
    const api::Result atBoundary = api::resume(file.string(), ro);
    expectSameResult(whole, atBoundary, "checkpoint at the phase boundary");
    runStopped(s, file, 15, 50, false);  // the checkpoint after 45, inside phase 2
    expectSameResult(whole, api::resume(file.string(), ro), "checkpoint inside phase 2");
}

TEST(Lib, BadCheckpointIsAnInputErrorAndAFailedWriteARuntimeError) {
    const fs::path dir = scratch("checkpoint_bad");
    const api::Scenario s = api::Scenario::fromTomlFile(kSmall);
    EXPECT_NE(inputErrorOf([&] { api::resume((dir / "missing.ckpt").string()); }).find("no checkpoint to resume from"),
              std::string::npos);
    std::ofstream(dir / "garbage.ckpt") << "not a checkpoint at all, just text";
    EXPECT_NE(inputErrorOf([&] { api::resume((dir / "garbage.ckpt").string()); }).find("garbage.ckpt"),
              std::string::npos);

    const fs::path file = dir / "good.ckpt";
    runStopped(s, file, 10, 10, false);  // the checkpoint after 10
    const std::string good = readFile(file);
    ASSERT_GT(good.size(), 100u);
    std::ofstream(dir / "cut.ckpt", std::ios::binary) << good.substr(0, good.size() / 2);
    EXPECT_NE(inputErrorOf([&] { api::resume((dir / "cut.ckpt").string()); }).find("cut.ckpt"), std::string::npos);
    std::string flipped = good;
    flipped[flipped.size() / 2] ^= 0x20;
    std::ofstream(dir / "flipped.ckpt", std::ios::binary) << flipped;
    EXPECT_NE(inputErrorOf([&] { api::resume((dir / "flipped.ckpt").string()); }).find("flipped.ckpt"),
              std::string::npos);

    api::RunOptions o;
    o.checkpointEvery = 10;  // without a path
    EXPECT_THROW(api::run(s, o), cavesim::InputError);
    o.checkpointPath = (dir / "no-such-folder" / "x.ckpt").string();
    EXPECT_THROW(api::run(s, o), cavesim::InputError);
    o.checkpointEvery = -1;
    EXPECT_THROW(api::run(s, o), cavesim::InputError);
    // A write that fails (the path is a folder): RuntimeError, at the first checkpoint.
    fs::create_directories(dir / "a-folder");
    o.checkpointEvery = 10;
    o.checkpointPath = (dir / "a-folder").string();
    EXPECT_THROW(api::run(s, o), cavesim::RuntimeError);
}
