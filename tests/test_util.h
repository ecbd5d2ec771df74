// Helpers shared by the test files, and the SystemC test harness: every test executable's sc_main
// (test_util.cpp) runs GoogleTest under a report handler that turns each SystemC warning or error
// into a test failure, unless a test says it expects that report type (ExpectReports).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rtsim::test {

inline std::filesystem::path shared_scenes() { return RTSIM_SHARED_SCENES; }
inline std::filesystem::path source_dir() { return RTSIM_SOURCE_DIR; }
inline bool have_shared_scenes() { return std::filesystem::exists(shared_scenes() / "README.md"); }

// A fresh temporary directory per call, removed by the caller if wanted.
std::filesystem::path temp_dir(const std::string& tag);
std::string slurp(const std::filesystem::path& p);

// A command run through the shell, with its exit code and output.
struct RunResult {
  int code = -1;
  std::string out, err;
};
RunResult run_command(const std::string& command);

// While one lives, SystemC reports of these message types are expected (a test of an error path):
// they act as usual (an error throws) but fail no test.
class ExpectReports {
 public:
  explicit ExpectReports(std::vector<std::string> types);
  ~ExpectReports();
  ExpectReports(const ExpectReports&) = delete;
  ExpectReports& operator=(const ExpectReports&) = delete;

 private:
  std::vector<std::string> saved_;
};

// sc_start(), then checks that the simulation ended normally: no exception, nothing left to do.
void simulate();

}  // namespace rtsim::test

#define RTSIM_REQUIRE_SHARED_SCENES()                                                \
  do {                                                                               \
    if (!::rtsim::test::have_shared_scenes()) GTEST_SKIP() << "no ../shared/scenes"; \
  } while (0)
