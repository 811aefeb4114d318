/// @file check.h
/// @brief Precondition and invariant checks: `CAVESIM_CHECK(cond, message)` throws `InternalError`.
///
/// The error policy of cavesim (CODING_STYLE.md): `InputError` is only for what a user supplied
/// (scenario file, command-line value, a file handed to the command), `RuntimeError` for failures
/// while running (I/O, numerical breakdown), and `CAVESIM_CHECK` for contract violations inside the
/// library, i.e. bugs. The check stays on in release builds: it guards cheap conditions only.
#pragma once

#include <string>

#include "core/error.h"

namespace cavesim::detail {

/// Builds the `InternalError` of a failed check; out of line of the caller's hot path.
[[noreturn]] inline void throwCheckFailure(const char* file, int line, const char* condition,
                                           const std::string& message) {
    std::string where(file);
    const auto src = where.rfind("src/");  // the path inside the repository, whatever the build directory
    if (src != std::string::npos) where.erase(0, src);
    throw InternalError("internal error at " + where + ":" + std::to_string(line) + ": check `" + condition +
                        "` failed: " + message);
}

}  // namespace cavesim::detail

/// Throws `cavesim::InternalError` naming file:line, the failed condition and `message` (anything a
/// `std::string` can be built from; evaluated only when the check fails) unless `cond` holds.
#define CAVESIM_CHECK(cond, message)                                                             \
    do {                                                                                         \
        if (!(cond)) ::cavesim::detail::throwCheckFailure(__FILE__, __LINE__, #cond, (message)); \
    } while (false)
