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

}  // namespace cavesim
