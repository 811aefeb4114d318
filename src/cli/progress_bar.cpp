#include "cli/progress_bar.h"

#include <cstdio>
#include <unistd.h>

namespace cavesim::cli {

ProgressBar::ProgressBar(bool quiet) : tty_(::isatty(STDERR_FILENO) != 0), quiet_(quiet) {}

void ProgressBar::finishBar() {
    if (barOpen_) {
        std::fputc('\n', stderr);
        barOpen_ = false;
    }
}

void ProgressBar::update(const std::string& phase, long done, long total) {
    if (quiet_ || total <= 0) return;
    if (phase != phase_) {
        finishBar();
        phase_ = phase;
        lastDecile_ = -1;
    }
    const double frac = double(done) / double(total);
    if (tty_) {
        const auto now = std::chrono::steady_clock::now();
        if (done != total && now - lastDraw_ < std::chrono::milliseconds(80)) return;
        lastDraw_ = now;
        const int width = 40, filled = int(frac * width + 0.5);
        std::string bar(std::size_t(filled), '#');
        bar.append(std::size_t(width - filled), '.');
        std::fprintf(stderr, "\r%-10s [%s] %3d%% (%ld/%ld)", phase.c_str(), bar.c_str(), int(frac * 100 + 0.5), done, total);
        std::fflush(stderr);
        barOpen_ = true;
        if (done == total) finishBar();
    } else {
        const int decile = int(frac * 10);
        if (decile != lastDecile_) {
            lastDecile_ = decile;
            std::fprintf(stderr, "cavesim: %s %d%% (%ld/%ld)\n", phase.c_str(), decile * 10, done, total);
        }
    }
}

void ProgressBar::log(const std::string& message) {
    if (quiet_) return;
    finishBar();
    std::fprintf(stderr, "cavesim: %s\n", message.c_str());
}

}  // namespace cavesim::cli
