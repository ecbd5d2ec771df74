// What the rtsim command's end-to-end tests share: running the binary, writing input files, the
// check that bad input is one line and exit code 2, and reading what a run wrote.
#pragma once

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace rtsim::cli_test {

namespace fs = std::filesystem;
using test::RunResult;
using test::slurp;

inline std::string fmt_shape(int h, int w) {
  return "'shape': (" + std::to_string(h) + ", " + std::to_string(w) + ")";
}

inline RunResult run(const std::string& args) {
  return test::run_command(std::string(RTSIM_BINARY) + " " + args);
}

inline void write(const fs::path& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}

// Bad input: exit code 2 and one line on stderr that contains every expected fragment.
inline void expect_input_error(const std::string& args, const std::vector<std::string>& fragments) {
  const RunResult r = run(args);
  EXPECT_EQ(r.code, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  for (const std::string& f : fragments)
    EXPECT_NE(r.err.find(f), std::string::npos) << "'" << f << "' not in: " << r.err;
}

// Reads a (H, W) uint16 .npy written by rtsim.
inline std::vector<uint16_t> read_npy_u16(const fs::path& p, int h, int w) {
  const std::string npy = slurp(p);
  const size_t header_len = uint8_t(npy[8]) | (uint8_t(npy[9]) << 8);
  EXPECT_NE(npy.find(fmt_shape(h, w)), std::string::npos);
  std::vector<uint16_t> v(size_t(h) * w);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = uint8_t(npy[10 + header_len + 2 * i]) | (uint8_t(npy[11 + header_len + 2 * i]) << 8);
  return v;
}

// The report without what depends on the host (docs/reports.md: "host" and "host_seconds").
inline nlohmann::json without_host(nlohmann::json r) {
  r.erase("host");
  r.erase("host_seconds");
  return r;
}

inline std::string city_run(const fs::path& out, const std::string& extra = "") {
  return "run " + (test::source_dir() / "configs/scenes/city.yaml").string() + " --hw " +
         (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
         " --width 64 --height 36 --no-plots --out " + out.string() + " " + extra;
}

}  // namespace rtsim::cli_test
