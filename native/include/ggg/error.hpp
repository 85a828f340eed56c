#pragma once
// The errors the library throws. Everything reachable from the CLI or Python ends in one of
// these (never an assert or abort), so callers can tell bad input from bad usage.
#include <stdexcept>
#include <string>

namespace ggg {

// Base of every error of the project.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A file that cannot be read as a road graph: missing, corrupt, truncated, no roads, ...
class InputError : public Error {
public:
    using Error::Error;
};

// A grammar that is malformed or inconsistent.
class GrammarError : public Error {
public:
    using Error::Error;
};

// The caller asked to stop through the progress callback.
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled") {}
};

// An argument out of its documented range (bad usage rather than bad data).
class UsageError : public Error {
public:
    using Error::Error;
};

} // namespace ggg
