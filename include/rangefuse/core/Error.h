// Error types shared by every stage.
#pragma once

#include <stdexcept>
#include <string>

namespace rangefuse {

/// Bad input: a file or a parameter the user gave. The message names the file and
/// the line, element or option that is wrong, so it can be printed as it is.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace rangefuse
