// Stage 2's checkpoint (sim/stage2_checkpoint.h): a run continued from the state saved after
// iteration K ends with the same bits as one that never stopped; saving a restored state gives
// the same bytes; cut or damaged bytes are refused with an InputError, never a crash.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage1.h"
#include "sim/stage2.h"
#include "sim/stage2_checkpoint.h"

using namespace cavesim;

namespace {

/// A small Figure 10: 3D, an obstacle, three sources, stage 1's protochannels; the sources join the
/// sink at iterations 84–87 and the channels keep growing after (so the pending pressure sweep, the
/// reach of the sinks and the events are all carried across checkpoints).
const char* kScenario = R"(name = "ck"
seed = 7
[domain]
size = [30, 30, 10]
[rock]
porosity = 0.05
noise = { amplitude = 0.02, scale = 4.0 }
[[rock.sphere]]
center = [12, 15, 4]
radius = 3
core_porosity = 0.005
[[source]]
at = [3, 5, 8]
[[source]]
at = [4, 24, 7]
[[source]]
at = [13, 26, 8]
[[sink]]
box = [[27, 13, 0], [29, 17, 2]]
[stage2]
iterations = 120
)";

Scenario scenario() {
    return parseScenarioString(kScenario, "ck.toml");
}

Domain build(const Scenario& s) {
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    runStage1(d, s.stage1, rng);
    prepareStage2(d, s.stage2);
    return d;
}

/// The domain of `s` after stage 1 and the interim step (built once per scenario name: a copy).
Domain prepared(const Scenario& s) {
    static std::map<std::string, Domain> built;
    auto it = built.find(s.name);
    if (it == built.end()) it = built.emplace(s.name, build(s)).first;
    return it->second;
}

void expectSameRun(const Domain& a, const Stage2Result& ra, const Domain& b, const Stage2Result& rb) {
    EXPECT_EQ(a.porosity.data, b.porosity.data);
    EXPECT_EQ(a.flags.data, b.flags.data);
    EXPECT_EQ(a.flow.data, b.flow.data);
    EXPECT_EQ(a.water.data, b.water.data);
    EXPECT_EQ(a.pressure.data, b.pressure.data);
    EXPECT_EQ(ra.iterations, rb.iterations);
    EXPECT_EQ(ra.breakthroughIteration, rb.breakthroughIteration);
    EXPECT_EQ(ra.sourceConnectedIteration, rb.sourceConnectedIteration);
    EXPECT_EQ(ra.totalInjected, rb.totalInjected);
    EXPECT_EQ(ra.totalDrained, rb.totalDrained);
    EXPECT_EQ(ra.sourceInjected, rb.sourceInjected);
    EXPECT_EQ(ra.waterBalanceRelError, rb.waterBalanceRelError);
    EXPECT_EQ(ra.workedVoxelIterations, rb.workedVoxelIterations);
    EXPECT_EQ(ra.activeTiles, rb.activeTiles);
    ASSERT_EQ(ra.history.size(), rb.history.size());
    for (std::size_t k = 0; k < ra.history.size(); ++k) {
        const Stage2Record &x = ra.history[k], &y = rb.history[k];
        EXPECT_EQ(x.iteration, y.iteration);
        EXPECT_EQ(x.injected, y.injected);
        EXPECT_EQ(x.drained, y.drained);
        EXPECT_EQ(x.stored, y.stored);
        EXPECT_EQ(x.flow, y.flow);
        EXPECT_EQ(x.eroded, y.eroded);
        EXPECT_EQ(x.channelVoxels, y.channelVoxels);
        EXPECT_EQ(x.pressureUpdates, y.pressureUpdates);
        EXPECT_EQ(x.sourcesConnected, y.sourcesConnected);
        EXPECT_EQ(x.balanceError, y.balanceError);
    }
}

/// The states an uninterrupted run with checkpoints every `every` iterations saves, by iteration.
std::map<int, std::string> savedStates(const Scenario& s, int every, Domain& d, Stage2Result& r) {
    std::map<int, std::string> saved;
    Stage2Checkpoints ck;
    ck.every = every;
    ck.save = [&](int it, const std::string& bytes) { saved[it] = bytes; };
    r = runStage2(d, s.stage2, {}, {}, ck);
    return saved;
}

}  // namespace

TEST(Stage2Checkpoint, CheckpointsChangeNothing) {
    const Scenario s = scenario();
    Domain a = prepared(s), b = prepared(s);
    const Stage2Result ra = runStage2(a, s.stage2);
    Stage2Result rb;
    const auto saved = savedStates(s, 10, b, rb);
    EXPECT_EQ(saved.size(), 11u);  // after 10, 20, …, 110; never after the last iteration
    ASSERT_TRUE(ra.breakthroughIteration.has_value());
    expectSameRun(a, ra, b, rb);
}

TEST(Stage2Checkpoint, ResumeFromEveryCheckpointGivesTheSameBits) {
    const Scenario s = scenario();
    Domain whole = prepared(s);
    Stage2Result rWhole;
    const auto saved = savedStates(s, 10, whole, rWhole);
    for (const auto& [iteration, bytes] : saved) {
        SCOPED_TRACE("resumed after iteration " + std::to_string(iteration));
        Domain d = prepared(s);
        Stage2Checkpoints ck;
        ck.resume = &bytes;
        ck.resumeName = "test";
        // The resumed run saves its own checkpoints; they restore to the same state too.
        std::map<int, std::string> again;
        ck.every = 10;
        ck.save = [&](int it, const std::string& b) { again[it] = b; };
        const Stage2Result r = runStage2(d, s.stage2, {}, {}, ck);
        expectSameRun(whole, rWhole, d, r);
        EXPECT_EQ(again.size(), saved.size() - std::size_t(iteration / 10));
    }
}

TEST(Stage2Checkpoint, SaveLoadSaveGivesTheSameBytes) {
    const Scenario s = scenario();
    Domain d = prepared(s);
    Stage2Result r;
    const auto saved = savedStates(s, 10, d, r);
    for (const auto& [iteration, bytes] : saved) {
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        stage2::decodeCarry(bytes, "test", c, dom);
        EXPECT_EQ(c.iteration, iteration);
        EXPECT_EQ(stage2::encodeCarry(c, dom), bytes) << "after iteration " << iteration;
    }
}

TEST(Stage2Checkpoint, CutOrDamagedStateIsRefused) {
    const Scenario s = scenario();
    Domain d = prepared(s);
    Stage2Result r;
    const std::string bytes = savedStates(s, 30, d, r).at(30);
    // Every cut is refused, at a few hundred places through the whole state.
    for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 300) {
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bytes.substr(0, n), "cut", c, dom), InputError) << n;
    }
    // A byte too many, another grid, another number of sources.
    {
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bytes + "x", "long", c, dom), InputError);
    }
    {
        Scenario other = s;
        other.name = "narrower";
        other.size[0] = 29;
        other.sinks[0].box.hi[0] = 28;
        Domain dom = prepared(other);
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bytes, "grid", c, dom), InputError);
    }
    {
        Domain dom = prepared(s);
        dom.sourceVoxels.pop_back();
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bytes, "sources", c, dom), InputError);
    }
    // Another kind of bytes.
    std::string bad = bytes;
    bad[0] ^= 1;  // the magic
    {
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bad, "magic", c, dom), InputError);
    }
}
