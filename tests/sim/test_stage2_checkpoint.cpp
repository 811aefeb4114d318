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

#include "levels_scenario.h"

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

/// Base-level phases under a dipping water table: each phase drains another sink or refills other
/// sources, the cave grows in all three; phases of 30 iterations, so checkpoints every 10 fall on
/// both phase boundaries and between them.
const char* kPhased = R"(name = "ckphases"
seed = 5
[domain]
size = [20, 10, 16]
[rock]
porosity = 0.05
noise = { amplitude = 0.01, scale = 4.0 }
[[source]]
at = [4, 3, 15]
[[source]]
at = [9, 7, 15]
[[sink]]
box = [[19, 3, 9], [19, 6, 11]]
[[sink]]
box = [[19, 3, 2], [19, 6, 4]]
[stage1]
enabled = false
[stage2]
p_rate = 0.05
p_rate_channel = 0.001
source_porosity = 0.5
[hydrology]
water_table = 10
dip = 5
dip_direction = 90
[[phase]]
iterations = 30
sinks = [1]
[[phase]]
iterations = 30
water_table = 3
sinks = [2]
sources = [1]
[[phase]]
iterations = 20
water_table = 3
)";

Scenario phased() {
    return parseScenarioString(kPhased, "ckphases.toml");
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

/// The same cave, water, events and history; `sameSweep` = false allows `pressure_updates` to
/// differ (a run that settles its pressure more often splits the same sweep otherwise).
void expectSameRun(const Domain& a, const Stage2Result& ra, const Domain& b, const Stage2Result& rb,
                   bool sameSweep = true) {
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
        if (sameSweep) { EXPECT_EQ(x.pressureUpdates, y.pressureUpdates); }
        EXPECT_EQ(x.sourcesConnected, y.sourcesConnected);
        EXPECT_EQ(x.balanceError, y.balanceError);
    }
    ASSERT_EQ(ra.phases.size(), rb.phases.size());
    for (std::size_t k = 0; k < ra.phases.size(); ++k) {
        const Stage2PhaseRecord &x = ra.phases[k], &y = rb.phases[k];
        EXPECT_EQ(x.firstIteration, y.firstIteration);
        EXPECT_EQ(x.iterations, y.iterations);
        EXPECT_EQ(x.waterTable, y.waterTable);
        EXPECT_EQ(x.fromSite, y.fromSite);
        EXPECT_EQ(x.sinks, y.sinks);
        EXPECT_EQ(x.sources, y.sources);
        EXPECT_EQ(x.breakthroughIteration, y.breakthroughIteration);
        EXPECT_EQ(x.channelVoxelsStart, y.channelVoxelsStart);
        EXPECT_EQ(x.channelVoxelsEnd, y.channelVoxelsEnd);
        EXPECT_EQ(x.caveBelow, y.caveBelow);
        EXPECT_EQ(x.caveAbove, y.caveAbove);
        EXPECT_EQ(x.aboveLo, y.aboveLo);
        EXPECT_EQ(x.aboveHi, y.aboveHi);
        EXPECT_EQ(x.belowLo, y.belowLo);
        EXPECT_EQ(x.belowHi, y.belowHi);
        EXPECT_EQ(x.aboveSliceMean, y.aboveSliceMean);
        EXPECT_EQ(x.injected, y.injected);
        EXPECT_EQ(x.drained, y.drained);
        EXPECT_EQ(x.eroded, y.eroded);
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

/// Resumes `s` from `bytes`, the state after `iteration` of a run with checkpoints every `every`
/// (`saved` of them) that ended as `whole`, `rWhole`: the same bits, and the resumed run saves the
/// checkpoints after it.
void expectResumeSame(const Scenario& s, int iteration, const std::string& bytes, int every, std::size_t saved,
                      const Domain& whole, const Stage2Result& rWhole) {
    Domain d = prepared(s);
    Stage2Checkpoints ck;
    ck.resume = &bytes;
    ck.resumeName = "test";
    std::map<int, std::string> again;
    ck.every = every;
    ck.save = [&](int it, const std::string& b) { again[it] = b; };
    const Stage2Result r = runStage2(d, s.stage2, {}, {}, ck);
    expectSameRun(whole, rWhole, d, r);
    EXPECT_EQ(again.size(), saved - std::size_t(iteration / every));
}

/// Every cut of `bytes` (a stage-2 state of `s`), at a few hundred places through it, is refused.
void expectEveryCutRefused(const Scenario& s, const std::string& bytes) {
    for (std::size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 300) {
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        EXPECT_THROW(stage2::decodeCarry(bytes.substr(0, n), "cut", c, dom), InputError) << n;
    }
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

/// Each iteration settles the pressure only as far as the next one reads it (the rest of the
/// sweep waits); a run that settles it everywhere after every iteration (a snapshot each time)
/// grows the same cave, bit for bit: three sources at different heads, stage 1's protochannels
/// stepping their rates down, growth on after the breakthrough.
TEST(Stage2, PressureSettledOnlyWhereTheWaterReadsItGivesTheSameCave) {
    const Scenario lazy = scenario();
    Scenario eager = lazy;
    for (int it = 1; it <= eager.stage2.iterations; ++it) eager.stage2.snapshots.push_back(it);
    Domain a = prepared(lazy), b = prepared(eager);  // the same domain: snapshots are a stage-2 option
    const Stage2Result ra = runStage2(a, lazy.stage2);
    const Stage2Result rb = runStage2(b, eager.stage2, {}, [](int, const Domain&) {});
    expectSameRun(a, ra, b, rb, false);
    EXPECT_GT(ra.history.back().channelVoxels, 20);  // the cave grew: pressure fell many times
}

TEST(Stage2Checkpoint, ResumeFromEveryCheckpointGivesTheSameBits) {
    const Scenario s = scenario();
    Domain whole = prepared(s);
    Stage2Result rWhole;
    const auto saved = savedStates(s, 10, whole, rWhole);
    for (const auto& [iteration, bytes] : saved) {
        SCOPED_TRACE("resumed after iteration " + std::to_string(iteration));
        // The resumed run saves its own checkpoints; they restore to the same state too.
        expectResumeSame(s, iteration, bytes, 10, saved.size(), whole, rWhole);
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
    expectEveryCutRefused(s, bytes);
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

/// Resumes a phased run from each checkpoint (every `every`) and expects the same bits.
void resumeEveryCheckpoint(const Scenario& s, int every, int phaseLength) {
    Domain a = prepared(s), whole = prepared(s);
    const Stage2Result ra = runStage2(a, s.stage2);
    Stage2Result rWhole;
    const auto saved = savedStates(s, every, whole, rWhole);
    expectSameRun(a, ra, whole, rWhole);  // checkpoints change nothing
    for (const auto& [iteration, bytes] : saved) {
        SCOPED_TRACE("resumed after iteration " + std::to_string(iteration));
        expectResumeSame(s, iteration, bytes, every, saved.size(), whole, rWhole);
        // Saving the restored state gives the same bytes.
        Domain dom = prepared(s);
        stage2::Carry c(dom.dims);
        stage2::decodeCarry(bytes, "test", c, dom);
        EXPECT_EQ(c.result.phases.size(), std::size_t((iteration - 1) / phaseLength));
        EXPECT_EQ(stage2::encodeCarry(c, dom), bytes);
    }
}

TEST(Stage2Checkpoint, PhasedRunResumesFromEveryCheckpoint) {
    const Scenario s = phased();
    Domain a = prepared(s);
    const Stage2Result ra = runStage2(a, s.stage2);
    ASSERT_EQ(ra.phases.size(), 3u);
    EXPECT_GT(ra.phases[1].channelVoxelsEnd, ra.phases[1].channelVoxelsStart);
    EXPECT_GT(ra.phases[2].channelVoxelsEnd, ra.phases[2].channelVoxelsStart);
    resumeEveryCheckpoint(s, 10, 30);  // after 10, …, 70; 30 and 60 end a phase
}

TEST(Stage2Checkpoint, PhaseBreakthroughSurvivesResume) {
    const Scenario s = parseScenarioString(test::kLevelsScenario, "cklevels.toml");
    Domain a = prepared(s);
    const Stage2Result ra = runStage2(a, s.stage2);
    ASSERT_EQ(ra.phases.size(), 2u);
    ASSERT_TRUE(ra.phases[0].breakthroughIteration.has_value());
    EXPECT_GT(*ra.phases[0].breakthroughIteration, 25);
    resumeEveryCheckpoint(s, 25, 150);  // before and after phase 1's breakthrough, at its end
}

TEST(Stage2Checkpoint, StateOfOtherPhasesIsRefused) {
    const Scenario s = phased();
    Domain d = prepared(s);
    Stage2Result r;
    const auto saved = savedStates(s, 10, d, r);
    const auto refused = [](const Scenario& other, const std::string& bytes) {
        Domain dom = prepared(other);
        Stage2Checkpoints ck;
        ck.resume = &bytes;
        ck.resumeName = "other";
        EXPECT_THROW(runStage2(dom, other.stage2, {}, {}, ck), InputError);
    };
    // Every cut of a state with phase records is refused.
    expectEveryCutRefused(s, saved.at(40));
    // Another sink in phase 2, another table in phase 1 (the grid and terminals are the same).
    Scenario sinks = s;
    sinks.stage2.phases[1].sinks = {1};
    refused(sinks, saved.at(40));
    refused(sinks, saved.at(60));
    Scenario table = s;
    table.stage2.phases[0].waterTable = 9;
    refused(table, saved.at(20));
    refused(table, saved.at(50));
    // A plain run's state under phases, and a phased state in a plain run.
    Scenario plain = s;
    plain.stage2.phases.clear();
    plain.stage2.hydrology.waterTable = -1;
    plain.stage2.iterations = 80;
    Domain p = prepared(plain);
    Stage2Result rp;
    refused(s, savedStates(plain, 10, p, rp).at(40));
    refused(plain, saved.at(40));
}

TEST(Stage2Checkpoint, StateOfCheckpointVersion1IsRead) {
    // Checkpoint format version 1 wrote the same stage-2 state without the phase records (no
    // phases done, an empty record in progress) under the magic "STE2": such a state resumes.
    const Scenario s = scenario();
    Domain whole = prepared(s);
    Stage2Result rWhole;
    const std::string bytes = savedStates(s, 40, whole, rWhole).at(40);
    std::string records;
    ByteWriter out(records);
    out.put(std::uint64_t(0));  // phases done
    out.put(std::int32_t(0));   // first iteration
    out.put(std::int32_t(0));   // iterations
    out.put(-1.0);              // water table
    out.put(std::uint8_t(0));   // from the site
    out.put(std::uint64_t(0));  // sinks
    out.put(std::uint64_t(0));  // sources
    out.put(std::uint8_t(0));   // breakthrough
    out.put(std::int32_t(0));
    for (int k = 0; k < 4; ++k) out.put(std::int64_t(0));  // voxel counts
    for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) out.put(std::int32_t(k % 2 == 0 ? 0 : -1));  // boxes
    for (int k = 0; k < 4; ++k) out.put(0.0);                                    // totals
    const std::size_t at = bytes.find(records);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes.find(records, at + 1), std::string::npos);
    ASSERT_EQ(bytes.substr(0, 4), "STE3");
    std::string old = bytes;
    old.erase(at, records.size());
    old[3] = '2';
    Domain d = prepared(s);
    Stage2Checkpoints ck;
    ck.resume = &old;
    ck.resumeName = "version 1";
    const Stage2Result r = runStage2(d, s.stage2, {}, {}, ck);
    expectSameRun(whole, rWhole, d, r);
    // Under phases it is refused: it holds no phase records.
    Domain p = prepared(phased());
    EXPECT_THROW(runStage2(p, phased().stage2, {}, {}, ck), InputError);
}
