// Stopwatch: non-negative and non-decreasing readings (no timing thresholds).
#include <gtest/gtest.h>

#include "core/timer.h"

namespace cavesim {
namespace {

TEST(Stopwatch, ReadingsAreNonNegativeAndNonDecreasing) {
    const Stopwatch watch;
    double last = watch.seconds();
    EXPECT_GE(last, 0.0);
    for (int i = 0; i < 1000; ++i) {
        const double now = watch.seconds();
        ASSERT_GE(now, last);
        last = now;
    }
}

TEST(Stopwatch, LapAndRestartStartAgain) {
    Stopwatch watch;
    volatile double sink = 0;
    for (int i = 0; i < 100000; ++i) sink = sink + i;
    const double before = watch.seconds();
    const double lap = watch.lap();
    EXPECT_GE(lap, before);  // the lap covers at least what was read before it
    EXPECT_GE(watch.seconds(), 0.0);
    watch.restart();
    EXPECT_GE(watch.seconds(), 0.0);
}

}  // namespace
}  // namespace cavesim
