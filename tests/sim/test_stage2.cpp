// Stage 2: the rules that must hold whatever the parameters — water conserved, pressure never
// rising under erosion, incremental pressure equal to a full solve, thread-count independence,
// mirror symmetry, and invariance under scaling the rates and the source pressure together.
#include <cmath>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "sim/domain.h"
#include "sim/scenario_io.h"
#include "sim/stage2.h"
#include "sim/stage2_steps.h"

#include "levels_scenario.h"

using namespace cavesim;

namespace {

/// A 2D section with two hanging protochannels and a sink column on the right (a small Figure 8).
const char* kTwoChannels = R"(name = "two"
seed = 11
[domain]
size = [40, 1, 24]
[rock]
porosity = 0.05
noise = { amplitude = 0.01, scale = 6.0 }
[[rock.channel]]
points = [[10, 0, 23], [10, 0, 10]]
[[rock.channel]]
points = [[24, 0, 23], [24, 0, 14]]
[[source]]
at = [10, 0, 23]
[[source]]
at = [24, 0, 23]
[[sink]]
box = [[39, 0, 0], [39, 0, 23]]
[stage1]
enabled = false
[stage2]
iterations = 60
p_rate = 0.05
p_rate_channel = 0.001
)";

/// Symmetric in x: one source in the middle, sinks on both sides.
const char* kSymmetric = R"(name = "sym"
seed = 2
[domain]
size = [31, 5, 16]
[rock]
porosity = 0.05
[[rock.sphere]]
center = [15, 2, 6]
radius = 3
[[rock.channel]]
points = [[15, 2, 15], [15, 2, 10]]
[[source]]
at = [15, 2, 15]
[[sink]]
box = [[0, 0, 0], [0, 4, 3]]
[[sink]]
box = [[30, 0, 0], [30, 4, 3]]
[stage1]
enabled = false
[stage2]
iterations = 50
p_rate = 0.05
p_rate_channel = 0.001
)";

Domain prepared(const Scenario& s) {
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    prepareStage2(d, s.stage2);
    return d;
}

}  // namespace

TEST(Stage2, WaterIsConserved) {
    const Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    Domain d = prepared(s);
    const Stage2Result r = runStage2(d, s.stage2);
    EXPECT_LT(r.waterBalanceRelError, 1e-12);
    EXPECT_GT(r.totalInjected, 0);
    EXPECT_GT(r.totalDrained, 0);  // water reaches the sink
    double stored = 0;
    for (float w : d.water.data) stored += w;
    EXPECT_NEAR(stored, r.totalInjected - r.totalDrained, 1e-5 * r.totalInjected);
    for (const auto& h : r.history) EXPECT_LT(h.balanceError, 1e-12 * (1 + h.injected + h.stored));
    // Contents never exceed capacity and are never negative.
    for (std::size_t v = 0; v < d.water.size(); ++v) {
        EXPECT_GE(d.water[v], -1e-6f);
        EXPECT_LE(d.water[v], d.porosity[v] + 1e-6f);
    }
}

TEST(Stage2, PressureNeverRisesAndIncrementalEqualsFull) {
    Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    for (int it = 1; it <= s.stage2.iterations; ++it) s.stage2.snapshots.push_back(it);
    Domain d = prepared(s);
    Grid3<float> previous = Grid3<float>(d.dims, std::numeric_limits<float>::infinity());
    int checked = 0;
    runStage2(d, s.stage2, {}, [&](int, const Domain& dom) {
        for (std::size_t v = 0; v < dom.pressure.size(); ++v) ASSERT_LE(dom.pressure[v], previous[v]);
        previous = dom.pressure;
        const Grid3<double> full = solvePressureFull(dom, s.stage2);
        for (std::size_t v = 0; v < full.size(); ++v)
            ASSERT_NEAR(dom.pressure[v], full[v], 1e-5 * (1 + std::abs(full[v])));
        ++checked;
    });
    EXPECT_EQ(checked, s.stage2.iterations);
}

TEST(Stage2, SameResultWithOneAndTwoThreads) {
    const Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    Domain a = prepared(s), b = prepared(s);
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        runStage2(a, s.stage2);
    }
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        runStage2(b, s.stage2);
    }
    EXPECT_EQ(a.porosity.data, b.porosity.data);
    EXPECT_EQ(a.water.data, b.water.data);
    EXPECT_EQ(a.pressure.data, b.pressure.data);
    EXPECT_EQ(a.flags.data, b.flags.data);
}

TEST(Stage2, MirrorSymmetricScenarioGivesMirrorSymmetricCave) {
    const Scenario s = parseScenarioString(kSymmetric, "sym.toml");
    Domain d = prepared(s);
    runStage2(d, s.stage2);
    const Dims& g = d.dims;
    long channels = 0;
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const int m = g.nx - 1 - i;
                ASSERT_EQ(d.porosity.at(i, j, k), d.porosity.at(m, j, k)) << i << "," << j << "," << k;
                ASSERT_EQ(d.pressure.at(i, j, k), d.pressure.at(m, j, k));
                ASSERT_EQ(d.flags.at(i, j, k) & kChannel, d.flags.at(m, j, k) & kChannel);
                channels += (d.flags.at(i, j, k) & kChannel) ? 1 : 0;
            }
    EXPECT_GT(channels, 0);
}

TEST(Stage2, OnlyTheRateRatioMatters) {
    // Paper §3.2: the result is unchanged while p_rate : p_rate_channel is unchanged; the source
    // pressure scales with them.
    Scenario a = parseScenarioString(kTwoChannels, "two.toml");
    a.stage2.pressureScale = 10.0;
    Scenario b = a;
    b.stage2.pRate *= 4;
    b.stage2.pRateChannel *= 4;
    b.stage2.pressureScale *= 4;
    Domain da = prepared(a), db = prepared(b);
    runStage2(da, a.stage2);
    runStage2(db, b.stage2);
    EXPECT_EQ(da.flags.data, db.flags.data);
    EXPECT_EQ(da.porosity.data, db.porosity.data);
}

TEST(Stage2, ChannelsGrowFromProtochannelsTowardTheSink) {
    const Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    Domain d = prepared(s);
    const Stage2Result r = runStage2(d, s.stage2);
    ASSERT_FALSE(r.history.empty());
    EXPECT_GT(r.history.back().channelVoxels, 0);
    // Erosion only raises porosity.
    Domain fresh = prepared(s);
    for (std::size_t v = 0; v < d.porosity.size(); ++v) EXPECT_GE(d.porosity[v], fresh.porosity[v]);
}

TEST(Stage2, InterimResetsStageOneErosionAndOpensSourcesAndSinks) {
    const Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    d.porosity.at(5, 0, 5) = 0.9f;  // stage-1 display erosion
    d.flags.at(5, 0, 5) |= kChannel;
    prepareStage2(d, s.stage2);
    EXPECT_FLOAT_EQ(d.porosity.at(5, 0, 5), d.porosity0.at(5, 0, 5));
    EXPECT_FALSE(d.flags.at(5, 0, 5) & kChannel);
    // Protochannels are raised to protochannel_porosity, never lowered below their own porosity.
    EXPECT_FLOAT_EQ(d.porosity.at(10, 0, 15),
                    std::max(d.porosity0.at(10, 0, 15), float(s.stage2.protochannelPorosity)));
    EXPECT_TRUE(d.flags.at(10, 0, 15) & kProtochannel);
    EXPECT_FLOAT_EQ(d.porosity.at(10, 0, 23), float(s.stage2.sourcePorosity));  // source
    EXPECT_FLOAT_EQ(d.porosity.at(39, 0, 3), 1.f);                              // sink
}

TEST(Stage2, IncrementalConnectivityEqualsTheFullSearchEveryIteration) {
    Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    s.stage2.iterations = 200;  // long enough for both sources to connect
    for (int it = 1; it <= s.stage2.iterations; ++it) s.stage2.snapshots.push_back(it);
    Domain d = prepared(s);
    std::vector<int> full;
    const Stage2Result r = runStage2(d, s.stage2, {}, [&](int, const Domain& dom) {
        int n = 0;
        for (bool c : stage2::connectedSources(dom)) n += c ? 1 : 0;
        full.push_back(n);
    });
    ASSERT_EQ(full.size(), r.history.size());
    for (std::size_t i = 0; i < full.size(); ++i) EXPECT_EQ(full[i], r.history[i].sourcesConnected) << i;
    EXPECT_EQ(full.back(), 2);
}

// Base-level phases under a falling water table: water is conserved every iteration, the second
// phase grows cave at its lower table below the first level (a shaft cuts down to it), and the terminals' flags are as
// given when the run returns (an inactive sink is only switched off for its phase).
TEST(Stage2, PhasesConserveWaterAndGrowALowerLevel) {
    const Scenario s = parseScenarioString(test::kLevelsScenario, "levels.toml");
    Domain d = prepared(s);
    const Grid3<std::uint8_t> flagsBefore = d.flags;
    const Stage2Result r = runStage2(d, s.stage2);
    EXPECT_EQ(r.iterations, 300);
    EXPECT_LT(r.waterBalanceRelError, 1e-12);
    for (const auto& h : r.history) EXPECT_LT(h.balanceError, 1e-12 * (1 + h.injected + h.stored));
    ASSERT_EQ(r.phases.size(), 2u);
    const Stage2PhaseRecord &a = r.phases[0], &b = r.phases[1];
    EXPECT_EQ(a.sinks, std::vector<int>{1});
    EXPECT_EQ(b.sinks, std::vector<int>{2});
    EXPECT_EQ(b.firstIteration, 151);
    ASSERT_TRUE(a.breakthroughIteration.has_value());
    ASSERT_TRUE(a.breakthroughIteration.has_value());  // the upper spring is reached in phase 1
    EXPECT_LE(*a.breakthroughIteration, 150);
    EXPECT_GE(a.belowLo[2], 17);  // phase 1's phreatic cave lies at its table
    EXPECT_LE(a.aboveHi[2], 29);
    EXPECT_GT(b.caveBelow, 5);  // phase 2 grows cave at its own table, below the first level
    EXPECT_LE(b.belowHi[2], 5);
    EXPECT_LE(b.aboveLo[2], 7);  // the shaft cut down through the abandoned level to the new table
    for (const auto& sink : d.sinkVoxels)
        for (std::size_t v : sink) EXPECT_EQ(d.flags[v] & (kSink | kInert), flagsBefore[v] & (kSink | kInert));
}

// A site's water table (`[hydrology] from_site`, per column in index units) that is level at 20 grows
// exactly the cave of the plane `water_table = 20`.
TEST(Stage2, SiteWaterTableActsAsTheSamePlane) {
    Scenario s = parseScenarioString(kTwoChannels, "two.toml");
    s.stage2.hydrology.waterTable = 20;
    Domain plane = prepared(s);
    const Stage2Result a = runStage2(plane, s.stage2);
    s.stage2.hydrology.waterTable = -1;
    s.stage2.hydrology.fromSite = true;
    Domain site = prepared(s);
    site.siteWaterTable.assign(std::size_t(site.dims.nx) * std::size_t(site.dims.ny), 20.0);
    const Stage2Result b = runStage2(site, s.stage2);
    ASSERT_EQ(b.phases.size(), 1u);
    EXPECT_TRUE(b.phases[0].fromSite);
    EXPECT_EQ(a.phases[0].caveAbove, b.phases[0].caveAbove);
    EXPECT_GT(a.phases[0].caveAbove, 0);
    EXPECT_EQ(plane.flags.data, site.flags.data);
    EXPECT_EQ(plane.porosity.data, site.porosity.data);
}
