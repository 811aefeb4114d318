// The pre-flight estimate (sim/preflight.h): grows with the block, follows the phase that needs
// most, and refuses a run above the smallest known limit with both numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/error.h"
#include "sim/preflight.h"
#include "sim/scenario_io.h"

using namespace cavesim;

TEST(Preflight, EstimateGrowsWithTheBlockAndNamesItsPeakPhase) {
    Scenario s = defaultScenario();
    const RunEstimate small = estimateRun(s, 2);
    s.size = {512, 512, 128};
    const RunEstimate big = estimateRun(s, 2);
    EXPECT_EQ(big.voxels, 512.0 * 512 * 128);
    EXPECT_GT(big.peakBytes, 20 * small.peakBytes);
    EXPECT_GT(big.seconds, small.seconds);
    // The peak is the largest phase plus the program's own memory.
    const double largest = std::max({big.stage1Bytes, big.stage2Bytes, big.outputBytes});
    EXPECT_GT(big.peakBytes, largest);
    EXPECT_LT(big.peakBytes, largest + 1e9);
    // Stage 1 alone: one zone of the whole block, one network of 450 bytes per voxel.
    s.size = {128, 128, 128};
    s.sources.resize(1);
    s.stage2.enabled = false;
    const RunEstimate zone = estimateRun(s, 2);
    EXPECT_STREQ(zone.peakPhase, "stage 1");
    EXPECT_GT(zone.stage1Bytes, 128.0 * 128 * 128 * 450);
    EXPECT_EQ(zone.stage2Bytes, 0.0);
}

TEST(Preflight, DenseFractureNetworksAndPhasesCountInTheTime) {
    // 407 000 discs of 40 voxels with a 3-voxel aperture in a 40³ block took 12 s; the estimate
    // once ignored them (about 1 s), and counted [stage2] iterations instead of the phases'.
    Scenario s = defaultScenario();
    s.size = {40, 40, 40};
    s.stage1.enabled = false;
    s.stage2.iterations = 1;
    const double plain = estimateRun(s, 2).seconds;
    FractureFamily f;
    f.spacing = 0.001;
    f.minLength = f.maxLength = 40;
    f.aperture = 3;
    s.fractureFamilies = {f};
    const double dense = estimateRun(s, 2).seconds;
    EXPECT_GT(dense, plain + 6.0);
    EXPECT_LT(dense, plain + 25.0);
    s.fractureFamilies.clear();
    Stage2Phase ph;
    ph.iterations = 100000;
    s.stage2.phases = {ph, ph};
    EXPECT_NEAR(estimateRun(s, 2).seconds - plain, (40.0 * 40 * 40 * 40e-9 + 13e-6) * (200000 - 1), 1e-6);
}

TEST(Preflight, LongRunsCountTheirHistory) {
    // Every iteration's history row stays in memory and goes into report.json: 200 000 iterations of
    // a 2-voxel block peaked at 590 MB, which the estimate once put at 65 MB.
    Scenario s = defaultScenario();
    s.size = {2, 1, 1};
    s.sources.resize(1);
    s.sources[0].box = {{0, 0, 0}, {0, 0, 0}};
    s.sinks.resize(1);
    s.sinks[0].box = {{1, 0, 0}, {1, 0, 0}};
    s.stage2.iterations = 200000;
    const RunEstimate e = estimateRun(s, 2);
    EXPECT_GT(e.peakBytes, 500e6);
    EXPECT_LT(e.peakBytes, 800e6);
    EXPECT_STREQ(e.peakPhase, "output");
    EXPECT_GT(e.seconds, 2.0);  // 2.8 s measured
    Stage2Phase ph;
    ph.iterations = 1000000;
    s.stage2.phases = std::vector<Stage2Phase>(64, ph);  // 6.4·10⁷ iterations: refused on any machine here
    EXPECT_GT(estimateRun(s, 2).peakBytes, 100e9);
}

TEST(Preflight, RefusesAboveTheSmallestLimitWithTheNumbers) {
    Scenario s = defaultScenario();
    s.size = {1000, 1000, 100};
    const RunEstimate e = estimateRun(s, 2);
    MemoryLimits generous;
    generous.available = 2 * e.peakBytes;
    EXPECT_NO_THROW(checkMemory(e, generous));
    EXPECT_NO_THROW(checkMemory(e, MemoryLimits{}));  // nothing known: nothing refused
    MemoryLimits tight = generous;
    tight.cgroup = e.peakBytes / 2;
    try {
        checkMemory(e, tight);
        FAIL();
    } catch (const InputError& x) {
        const std::string m = x.what();
        EXPECT_NE(m.find("this process may use"), std::string::npos) << m;
        EXPECT_NE(m.find("cgroup limit"), std::string::npos) << m;
        EXPECT_NE(m.find("100000000 voxels"), std::string::npos) << m;
    }
}

TEST(Preflight, SpeleothemStageCountsItsLevelSetAndSteps) {
    Scenario s = defaultScenario();  // the Figure 10 block: 60 × 60 × 20 voxels of 1 m
    const RunEstimate plain = estimateRun(s, 2);
    EXPECT_EQ(plain.speleoBytes, 0.0);
    EXPECT_EQ(plain.speleoVoxels, 0.0);
    // The cave surface assumed: 0.14 of the bounding box's 2·(60·60 + 60·20 + 60·20) = 12 000 m².
    EXPECT_DOUBLE_EQ(expectedCaveSurface(s), 0.14 * 12000);

    s.speleothems.enabled = true;
    s.speleothems.voxelSize = 0.05;
    s.speleothems.years = 20000;
    const RunEstimate fine = estimateRun(s, 2);
    EXPECT_DOUBLE_EQ(fine.speleoVoxels, 6.0 * 1680 / (0.05 * 0.05));
    // Stable steps: half a voxel at the fastest drip site's α·l_Q = 1e-4·e^0.3 m/yr.
    EXPECT_EQ(fine.speleoSteps, std::ceil(20000 / (0.5 * 0.05 / (1e-4 * std::exp(0.3)))));
    EXPECT_STREQ(fine.peakPhase, "speleothems");
    EXPECT_GT(fine.peakBytes, plain.peakBytes + 100 * fine.speleoVoxels);
    EXPECT_GT(fine.seconds, plain.seconds + fine.speleoSeconds * 0.999);
    EXPECT_NE(describeEstimate(fine).find("speleothems: about 4.0 M level-set voxels"), std::string::npos)
        << describeEstimate(fine);

    // Coarser voxels: a quarter of the voxels, half the steps.
    s.speleothems.voxelSize = 0.1;
    const RunEstimate coarse = estimateRun(s, 2);
    EXPECT_DOUBLE_EQ(coarse.speleoVoxels, fine.speleoVoxels / 4);
    EXPECT_EQ(coarse.speleoSteps, std::ceil(20000 / (0.5 * 0.1 / (1e-4 * std::exp(0.3)))));
    EXPECT_LT(coarse.speleoSeconds, fine.speleoSeconds / 4);
    // time_step caps the step; a water-filled cave grows nothing (no steps, the level set still made).
    s.speleothems.timeStep = 100;
    EXPECT_EQ(estimateRun(s, 2).speleoSteps, 200.0);
    s.speleothems.drained = false;
    EXPECT_EQ(estimateRun(s, 2).speleoSteps, 0.0);

    // `run` refuses a decorated run that the undecorated one would fit in, naming the phase.
    MemoryLimits limits;
    limits.available = 0.5 * (plain.peakBytes + fine.peakBytes);
    EXPECT_NO_THROW(checkMemory(plain, limits));
    try {
        checkMemory(fine, limits);
        FAIL();
    } catch (const InputError& x) {
        EXPECT_NE(std::string(x.what()).find("(speleothems,"), std::string::npos) << x.what();
    }
}

TEST(Preflight, SiteSinkholesShareTheBlockLikeOtherSources) {
    // A site's sinkholes are sources: with more of them each zone, and with it the largest
    // stage-1 network, is smaller (the estimate once counted only [[source]] and [[recharge]]).
    Scenario s = defaultScenario();
    s.size = {128, 128, 32};
    s.stage2.enabled = false;
    s.sources.resize(1);
    const double alone = estimateRun(s, 1).stage1Bytes;
    auto site = std::make_shared<SiteData>();
    site->sources.assign(7, s.sources.front());
    s.siteData = site;
    EXPECT_LT(estimateRun(s, 1).stage1Bytes, alone / 4);
}
