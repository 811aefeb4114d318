/// @file exact_sum.h
/// @brief An order-free sum of doubles: each term is rounded once to a fixed point of 2⁻⁹⁶ and the
/// terms are added as integers, so any grouping and order (tiles summed on any number of threads,
/// partial sums kept and updated by differences) gives the same bits.
///
/// A sum of doubles taken in another order rounds differently; a fixed-point sum does not. Terms
/// whose magnitude is below 2⁻⁹⁶ (1.3·10⁻²⁹) count as 0, which is far below the round-off of any
/// total taken in double precision. Terms must be finite and below 2³⁰ in magnitude, and every
/// partial total below 2³¹: a term out of range or a total that would overflow marks the sum `bad`,
/// and its value is NaN (the caller reports it as a non-finite quantity).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace cavesim {

class ExactSum {
public:
    /// The fixed-point value of one term (what `add` adds); `bad` is set for a term out of range.
    static __int128 fixed(double x, bool& bad) {
        // Read from the bits: |x| = mant · 2^(e − 1075) for a normal number (e the biased exponent).
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        const int e = int((bits >> 52) & 0x7ff);
        if (e >= 1023 + 30) {  // |x| ≥ 2^30, infinite or NaN
            bad = true;
            return 0;
        }
        const int shift = e - 1075 + kFraction;  // |x| · 2^96 = mant · 2^shift
        if (shift <= -53) return 0;              // below 2^-96 (and every subnormal, and zero)
        const std::int64_t mant = std::int64_t((bits & ((std::uint64_t(1) << 52) - 1)) | (std::uint64_t(1) << 52));
        const __int128 v = shift >= 0 ? __int128(mant) << shift : __int128(mant >> -shift);  // toward 0
        return (bits >> 63) ? -v : v;
    }

    void add(double x) { accumulate(fixed(x, bad_)); }
    /// Adds the change from `before` to `after` of one term of the sum.
    void replace(double before, double after) {
        accumulate(fixed(after, bad_));
        accumulate(-fixed(before, bad_));
    }
    ExactSum& operator+=(const ExactSum& o) {
        accumulate(o.sum_);
        bad_ = bad_ || o.bad_;
        return *this;
    }
    ExactSum& operator-=(const ExactSum& o) {
        accumulate(-o.sum_);
        bad_ = bad_ || o.bad_;
        return *this;
    }
    bool bad() const { return bad_; }
    /// The total rounded to the nearest double, or NaN when a term was out of range.
    double value() const { return bad_ ? std::nan("") : std::ldexp(double(sum_), -kFraction); }

private:
    static constexpr int kFraction = 96;
    void accumulate(__int128 v) {
        if (__builtin_add_overflow(sum_, v, &sum_)) bad_ = true;  // a total of 2³¹ or more
    }
    __int128 sum_ = 0;
    bool bad_ = false;
};

}  // namespace cavesim
