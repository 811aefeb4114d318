/// @file exact_sum.h
/// @brief An order-free sum of doubles: each term is rounded once to a fixed point of 2⁻⁹⁶ and the
/// terms are added as integers, so any grouping and order (tiles summed on any number of threads,
/// partial sums kept and updated by differences) gives the same bits.
///
/// A sum of doubles taken in another order rounds differently; a fixed-point sum does not. Terms
/// whose magnitude is below 2⁻⁹⁶ (1.3·10⁻²⁹) count as 0 (their sign kept), which is far below the
/// round-off of any total taken in double precision. Terms must be finite and below 2³⁰ in
/// magnitude, totals below 2³¹: anything else marks the sum `bad` and its value is NaN (the caller
/// reports it as a non-finite quantity).
#pragma once

#include <cmath>
#include <cstdint>

namespace cavesim {

class ExactSum {
public:
    /// The fixed-point value of one term (what `add` adds); `bad` is set for a term out of range.
    static __int128 fixed(double x, bool& bad) {
        if (!(std::abs(x) < kLimit)) {  // NaN, infinite or too large
            bad = true;
            return 0;
        }
        if (x == 0) return 0;
        int e = 0;
        const double m = std::frexp(std::abs(x), &e);               // |x| = m · 2^e, m in [0.5, 1)
        const std::int64_t mant = std::int64_t(std::ldexp(m, 53));  // exact: 53 bits
        const int shift = e - 53 + kFraction;                       // |x| · 2^96 = mant · 2^shift
        __int128 v;
        if (shift >= 0)
            v = __int128(mant) << shift;
        else
            v = shift > -64 ? __int128(mant >> -shift) : 0;  // truncated toward 0 (then signed below)
        return x < 0 ? -v : v;
    }

    void add(double x) { sum_ += fixed(x, bad_); }
    /// Adds the change from `before` to `after` of one term of the sum.
    void replace(double before, double after) {
        sum_ += fixed(after, bad_);
        sum_ -= fixed(before, bad_);
    }
    ExactSum& operator+=(const ExactSum& o) {
        sum_ += o.sum_;
        bad_ = bad_ || o.bad_;
        return *this;
    }
    ExactSum& operator-=(const ExactSum& o) {
        sum_ -= o.sum_;
        bad_ = bad_ || o.bad_;
        return *this;
    }
    bool bad() const { return bad_; }
    /// The total rounded to the nearest double, or NaN when a term was out of range.
    double value() const { return bad_ ? std::nan("") : std::ldexp(double(sum_), -kFraction); }

private:
    static constexpr int kFraction = 96;
    static constexpr double kLimit = 1073741824.0;  // 2^30
    __int128 sum_ = 0;
    bool bad_ = false;
};

}  // namespace cavesim
