#pragma once
// Typed errors of the core library. The core never aborts: it throws one of these with a message that
// names the problem, and callers (ROS layer, tools) log it and keep their last good state.
#include <stdexcept>
#include <string>

namespace deformation_enrichment {

/// Base of every error the core throws.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Input that violates a precondition: wrong sizes, NaN/Inf, empty or degenerate meshes.
class InvalidInputError : public Error {
public:
  using Error::Error;
};

/// A numerical method that could not produce a trustworthy result (no convergence, singular system).
class NumericalError : public Error {
public:
  using Error::Error;
};

/// Files that cannot be read or written, or whose content is corrupt.
class IoError : public Error {
public:
  using Error::Error;
};

}  // namespace deformation_enrichment
