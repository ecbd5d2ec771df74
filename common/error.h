// Errors a user can fix: bad scene, config or command-line input.
// The command-line front end turns each into one message and exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace rtsim {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// "FILE:LINE: MESSAGE" (line <= 0 omits the line).
[[noreturn]] void throw_at_line(const std::string& file, long line, const std::string& message);
// "FILE: key 'KEY': MESSAGE".
[[noreturn]] void throw_at_key(const std::string& file, const std::string& key,
                               const std::string& message);

}  // namespace rtsim
