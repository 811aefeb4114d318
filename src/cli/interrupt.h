/// @file interrupt.h
/// @brief SIGINT and SIGTERM stop a run at its next safe point instead of killing it mid-write.
#pragma once

namespace cavesim::cli {

/// Installs handlers that only record SIGINT / SIGTERM (a second one of either kills at once, as
/// usual), and ignores SIGXFSZ so that a file-size limit makes a write fail with an error the run
/// reports, instead of killing the process with its staging folder left behind.
void installStopHandlers();

/// The signal received since installStopHandlers(), or 0.
int stopSignal();

/// Throws `Cancelled` naming the signal when one was received: called from the progress and
/// log callbacks, the safe points of a run.
void throwIfStopped();

}  // namespace cavesim::cli
