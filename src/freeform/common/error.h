// Exception hierarchy of the core library. Every error a user can cause derives from Error and
// carries a message that says what to fix; internal invariant failures are InternalError.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace freeform {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Input data the library cannot accept (bad arguments, bad regions, bad edits).
class InvalidInput : public Error {
 public:
  using Error::Error;
};

// A file could not be read or written. what() is "file:line: message" (line omitted when 0).
class IoError : public Error {
 public:
  IoError(std::string file, std::size_t line, const std::string& message);
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string message_;
};

// Connectivity the halfedge structure cannot represent (non-manifold edge or vertex, ...).
class TopologyError : public Error {
 public:
  using Error::Error;
};

// A linear solve failed (singular or indefinite system, numerical breakdown).
class SolverError : public Error {
 public:
  using Error::Error;
};

// The process may not allocate what a step needs (an address-space limit, or none left); the
// message names the step and the sizes.
class OutOfMemory : public Error {
 public:
  using Error::Error;
};

// A broken internal invariant: a bug in this library, never the user's fault.
class InternalError : public Error {
 public:
  using Error::Error;
};

[[noreturn]] void throw_internal(const char* condition, const char* file, int line, const std::string& message);

}  // namespace freeform

// Internal invariant check; stays on in every build type (cheap conditions only).
#define FF_CHECK(cond, msg)                                             \
  do {                                                                  \
    if (!(cond)) ::freeform::throw_internal(#cond, __FILE__, __LINE__, (msg)); \
  } while (0)
