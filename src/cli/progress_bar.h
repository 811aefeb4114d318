/// @file progress_bar.h
/// @brief Progress on stderr: a redrawn bar on a terminal, plain log lines otherwise.
#pragma once

#include <chrono>
#include <string>

namespace cavesim::cli {

class ProgressBar {
public:
    explicit ProgressBar(bool quiet = false);
    /// Library progress callback target.
    void update(const std::string& phase, long done, long total);
    /// A one-line message (finishes any bar first).
    void log(const std::string& message);

private:
    void finishBar();
    bool tty_ = false, quiet_ = false, barOpen_ = false;
    std::string phase_;
    int lastDecile_ = -1;
    std::chrono::steady_clock::time_point lastDraw_{};
};

}  // namespace cavesim::cli
