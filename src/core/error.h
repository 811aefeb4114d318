/// @file error.h
/// @brief The exception hierarchy of cavesim. Library code throws; only the command prints and exits.
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

/// The caller asked the operation to stop (a `ProgressFn` throws it at a safe point, e.g. when the
/// command received SIGINT or SIGTERM). Library code lets it pass, cleaning up as it unwinds; the
/// command removes what it staged and exits 130 or 143.
class CancelledError : public Error {
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

}  // namespace cavesim
