#include "common/error.h"

#include <fmt/format.h>

namespace rtsim {

void throw_at_line(const std::string& file, long line, const std::string& message) {
  if (line > 0) throw InputError(fmt::format("{}:{}: {}", file, line, message));
  throw InputError(fmt::format("{}: {}", file, message));
}

void throw_at_key(const std::string& file, const std::string& key, const std::string& message) {
  throw InputError(fmt::format("{}: key '{}': {}", file, key, message));
}

}  // namespace rtsim
