/// @file error.h
/// @brief The exception hierarchy of cavesim. Library code throws; only the command prints and exits.
///
/// Part of the public API (include/cavesim/cavesim.h includes it): the same classes are thrown by
/// the internal modules and caught by users of the library. Only the standard library is used here.
#pragma once

#include <stdexcept>
#include <string>

namespace cavesim {

/// Base of every cavesim error.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Bad user input (scenario file, command-line value): the command exits with code 2.
class InputError : public Error {
public:
    using Error::Error;
};

/// A failure while running (I/O, numerical breakdown): the command exits with code 1.
class RuntimeError : public Error {
public:
    using Error::Error;
};

/// A broken contract inside the library: a caller passed arguments that violate a documented
/// precondition, or an invariant that the code itself maintains does not hold. It is a bug, never
/// the user's fault; the command exits with code 1 and reports "internal error". Thrown by
/// `CAVESIM_CHECK` (core/check.h), whose message names file:line and the failed condition.
class InternalError : public Error {
public:
    using Error::Error;
};

/// The caller asked the operation to stop: `api::CancelToken`, an exception thrown from the progress
/// callback of a Python run, or the command's progress callback after SIGINT or SIGTERM
/// (cli/interrupt.h). It is thrown at a safe point (at most one stage-2 iteration late); library
/// code lets it pass, cleaning up as it unwinds (nothing staged is left behind, the output
/// directory keeps its previous run). The command exits with 130 (SIGINT) or 143 (SIGTERM).
class Cancelled : public Error {
public:
    using Error::Error;
};

}  // namespace cavesim
