// Runs the example a test file is built for (RTSIM_EXAMPLE_BINARY) and returns the JSON lines it
// printed; a non-zero exit is a test failure.
#pragma once

#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

namespace rtsim::test {

inline std::vector<nlohmann::json> run_example(const std::string& args) {
  const RunResult r = run_command(std::string(RTSIM_EXAMPLE_BINARY) + " " + args);
  EXPECT_EQ(r.code, 0) << r.err;
  std::vector<nlohmann::json> lines;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] == '{') lines.push_back(nlohmann::json::parse(line));
  return lines;
}

}  // namespace rtsim::test
