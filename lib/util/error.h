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

// The program's own installation is incomplete (a module it loads is missing or from another
// build): not the user's input, not a bug; programs exit with code 3 and the message says what to do.
class SetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cdbench
