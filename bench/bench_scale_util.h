// Helpers shared by the scale benchmarks (bench_sim_scale.cpp, bench_flownet_scale.cpp): the Figure 10
// scenario scaled by k, and the process's memory and CPU time read from Linux.
#pragma once

#include <sys/resource.h>

#include <fstream>
#include <string>

#include "core/memory.h"
#include "sim/scenario_io.h"

namespace cavesim::bench {

/// Figure 10 scaled by k (as bench/fig10_scaled.py); with `pad`, the same features in the corner of a
/// block pad × wider and deeper and (pad == 2: 2×2×2 = 8× the volume) pad × higher.
inline Scenario scaledFig10(int k, int pad = 1) {
    Scenario s = defaultScenario();
    s.name = "fig10_k" + std::to_string(k);
    s.size = {60 * k * pad, 60 * k * pad, 20 * k * pad};
    s.noise.scale *= k;
    for (auto& o : s.spheres) {
        for (auto& c : o.center) c *= k;
        o.radius *= k;
    }
    for (auto& src : s.sources)
        for (int a = 0; a < 3; ++a) {
            src.box.lo[std::size_t(a)] *= k;
            src.box.hi[std::size_t(a)] *= k;
        }
    for (auto& sink : s.sinks)
        for (int a = 0; a < 3; ++a) {
            sink.box.lo[std::size_t(a)] *= k;
            sink.box.hi[std::size_t(a)] *= k;
        }
    s.stage2.iterations *= k;
    validateScenario(s);
    return s;
}

/// The value, in kB, of the /proc/self/status line starting with `key` ("VmRSS:", "VmHWM:"); 0 if none.
inline double statusKb(const std::string& key) {
    std::string text;
    const std::string name = key.substr(0, key.find(':'));
    return readWholeFile("/proc/self/status", text) ? parseProcKilobytes(text, name) / 1024.0 : 0;
}

/// Resets VmHWM to the current resident size (Linux: clear_refs 5).
inline void resetPeak() {
    std::ofstream("/proc/self/clear_refs") << "5";
}

/// User CPU time of the process so far, in seconds.
inline double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec);
}

}  // namespace cavesim::bench
