/// @file timer.h
/// @brief A stopwatch on the monotonic clock, for the timing fields of results and reports.
///
/// Timings are reported, never acted on: no result may depend on them (CODING_STYLE.md, determinism).
#pragma once

#include <chrono>

namespace cavesim {

/// Measures elapsed wall time from its construction (or its last `restart`) on `std::chrono::steady_clock`,
/// which never goes backwards.
///
///     Stopwatch t;
///     work();
///     stats.seconds = t.seconds();
class Stopwatch {
public:
    using Clock = std::chrono::steady_clock;

    Stopwatch() : start_(Clock::now()) {}

    /// Seconds since construction or the last `restart` (≥ 0, non-decreasing between restarts).
    double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

    /// Starts counting again from now.
    void restart() { start_ = Clock::now(); }

    /// Seconds since construction or the last restart, then restarts: the time of one step of a sequence.
    double lap() {
        const Clock::time_point now = Clock::now();
        const double s = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return s;
    }

private:
    Clock::time_point start_;
};

}  // namespace cavesim
