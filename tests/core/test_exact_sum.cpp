#include "core/exact_sum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

using cavesim::ExactSum;

namespace {

double sumOf(const std::vector<double>& xs) {
    ExactSum s;
    for (double x : xs) s.add(x);
    return s.value();
}

}  // namespace

// 0.1 + 0.2 + 0.3 rounds to 0.6000000000000001 left to right; the exact sum of the three doubles
// is 0.6000000000000000055…, whose nearest double is 0.6.
TEST(ExactSum, RoundsTheExactTotalOnce) {
    EXPECT_EQ(0.1 + 0.2 + 0.3, 0.6000000000000001);
    EXPECT_EQ(sumOf({0.1, 0.2, 0.3}), 0.6);
    // Cancellation that double arithmetic loses entirely.
    EXPECT_EQ(sumOf({1.0, 1e-17, -1.0}), 1e-17 - std::fmod(1e-17, std::ldexp(1.0, -96)));
    EXPECT_EQ(sumOf({}), 0.0);
}

// Any order and any grouping give the same bits: what lets tiles be summed on any number of
// threads and kept as partial sums.
TEST(ExactSum, AnyOrderAndGroupingGivesTheSameBits) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> xs;
    for (int i = 0; i < 10000; ++i) xs.push_back(std::ldexp(u(rng), -int(rng() % 60)) * (rng() % 7 == 0 ? -1 : 1));
    const double reference = sumOf(xs);
    for (int trial = 0; trial < 5; ++trial) {
        std::shuffle(xs.begin(), xs.end(), rng);
        EXPECT_EQ(sumOf(xs), reference);
        ExactSum a, b;  // two groups, added afterwards
        const std::size_t cut = std::size_t(rng() % xs.size());
        for (std::size_t i = 0; i < xs.size(); ++i) (i < cut ? a : b).add(xs[i]);
        b += a;
        EXPECT_EQ(b.value(), reference);
    }
    // Within a few ulps of a careful long-double sum of the sorted magnitudes.
    std::vector<double> sorted = xs;
    std::sort(sorted.begin(), sorted.end(), [](double x, double y) { return std::abs(x) < std::abs(y); });
    long double careful = 0;
    for (double x : sorted) careful += x;
    EXPECT_NEAR(reference, double(careful), 4 * std::abs(reference) * std::numeric_limits<double>::epsilon());
}

// Replacing a term by differences gives the bits of summing the new terms afresh.
TEST(ExactSum, ReplacingATermEqualsSummingAfresh) {
    std::vector<double> xs = {0.25, 1.0 / 3.0, 7e-12, 0.999999, 1e-25};
    ExactSum kept;
    for (double x : xs) kept.add(x);
    kept.replace(xs[1], 2.0 / 3.0);
    kept.replace(xs[2], 0.0);
    xs[1] = 2.0 / 3.0;
    xs[2] = 0.0;
    EXPECT_EQ(kept.value(), sumOf(xs));
    EXPECT_FALSE(kept.bad());
}

TEST(ExactSum, NonFiniteOrHugeTermsMakeTheSumNaN) {
    for (double x : {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                     std::ldexp(1.0, 31)}) {
        ExactSum s;
        s.add(1.0);
        s.add(x);
        EXPECT_TRUE(s.bad());
        EXPECT_TRUE(std::isnan(s.value()));
        ExactSum t;  // a bad part spoils the total it is added to
        t += s;
        EXPECT_TRUE(std::isnan(t.value()));
    }
    // A total that would reach 2^31 overflows the fixed point: bad, never a wrapped number.
    ExactSum big;
    for (int i = 0; i < 3; ++i) big.add(std::nextafter(std::ldexp(1.0, 30), 0.0));
    EXPECT_TRUE(big.bad());
    EXPECT_TRUE(std::isnan(big.value()));
    // Terms below 2^-96 count as 0 (whatever their sign); the largest allowed term is exact.
    EXPECT_EQ(sumOf({-std::ldexp(1.0, -97)}), 0.0);
    EXPECT_EQ(sumOf({std::ldexp(1.0, -97)}), 0.0);
    EXPECT_EQ(sumOf({std::ldexp(1.0, -96)}), std::ldexp(1.0, -96));
    EXPECT_EQ(sumOf({std::nextafter(std::ldexp(1.0, 30), 0.0)}), std::nextafter(std::ldexp(1.0, 30), 0.0));
}
