#pragma once
// Bad input, from any file salsa reads: one line naming the file, the field, the value and what is allowed.
#include <stdexcept>

namespace salsa {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace salsa
