#include "cli/interrupt.h"

#include <csignal>
#include <string>

#include "core/error.h"

namespace cavesim::cli {
namespace {

volatile std::sig_atomic_t gStop = 0;

extern "C" void onStopSignal(int sig) {
    gStop = sig;
}

}  // namespace

void installStopHandlers() {
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART | SA_RESETHAND;  // a second Ctrl-C ends the process at once
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    std::signal(SIGXFSZ, SIG_IGN);
}

int stopSignal() {
    return int(gStop);
}

void throwIfStopped() {
    const int sig = stopSignal();
    if (sig != 0)
        throw Cancelled(sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal " + std::to_string(sig));
}

}  // namespace cavesim::cli
