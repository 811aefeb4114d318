/// @file progress.h
/// @brief Progress reporting from library code to the caller (the command draws it).
#pragma once

#include <functional>
#include <string>

namespace cavesim {

/// Called by long operations: `phase` names the work, `done` of `total` units are finished.
/// May be empty. Library code never prints. Every call is a safe point: the callback may throw
/// `Cancelled` (core/error.h) to stop the operation there, and library code must then unwind
/// without leaving anything half-written (destructors clean up; nothing catches it on the way).
using ProgressFn = std::function<void(const std::string& phase, long done, long total)>;

inline void reportProgress(const ProgressFn& fn, const std::string& phase, long done, long total) {
    if (fn) fn(phase, done, total);
}

}  // namespace cavesim
