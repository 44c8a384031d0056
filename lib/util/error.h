#pragma once
// Errors that carry a complete, human-readable explanation for the user.
#include <stdexcept>
#include <string>

namespace cdbench {

// Bad input (a file, an option): the message names what is wrong; programs exit with code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cdbench
