// Errors inside the core: thrown as bounce::Error with a BounceStatus, turned into a status code and a
// last-error string at the C API boundary (api.cpp). Nothing throws across that boundary.
#pragma once

#include <stdexcept>
#include <string>

#include "bounce/bounce.h"

namespace bounce {

class Error : public std::runtime_error {
 public:
  Error(BounceStatus status, const std::string& message) : std::runtime_error(message), status_(status) {}
  BounceStatus status() const { return status_; }

 private:
  BounceStatus status_;
};

[[noreturn]] inline void fail(BounceStatus status, const std::string& message) { throw Error(status, message); }

inline void require(bool condition, const std::string& message) {
  if (!condition) fail(BOUNCE_ERROR_INVALID_ARGUMENT, message);
}

}  // namespace bounce
