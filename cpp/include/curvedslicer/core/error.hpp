// The one exception hierarchy of the core. The bindings map each class to a Python exception.
//
// Messages read "<what was wrong>: <value>; <what to do>", e.g.
//   "layer thickness must be positive: -1.5 mm; pass a value such as 1.5"
#pragma once

#include <stdexcept>
#include <string>

namespace curvedslicer {

/// Base of every error the core throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad user input: a parameter out of range, a malformed or unusable file, unusable geometry.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// A file could not be opened, read or written (permissions, missing folder, disk full).
class IoError : public Error {
 public:
  using Error::Error;
};

/// The request would exceed a resource budget (memory); the message says what would fit.
class ResourceLimit : public Error {
 public:
  using Error::Error;
};

/// An algorithm could not produce a trustworthy result (degenerate numerics).
class NumericalFailure : public Error {
 public:
  using Error::Error;
};

/// The progress callback asked to stop. No partial result is returned.
class Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace curvedslicer
