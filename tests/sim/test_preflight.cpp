// The pre-flight estimate (sim/preflight.h): grows with the block, follows the phase that needs
// most, and refuses a run above the smallest known limit with both numbers.
#include <gtest/gtest.h>

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
