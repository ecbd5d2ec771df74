#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <systemc>

#include <sys/wait.h>
#include <unistd.h>
#include <atomic>
#include <fstream>
#include <sstream>

namespace rtsim::test {

namespace {
std::vector<std::string> expected_types;
}

std::filesystem::path temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  auto dir =
      std::filesystem::temp_directory_path() /
      ("rtsim_test_" + tag + "_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

RunResult run_command(const std::string& command) {
  const std::filesystem::path dir = temp_dir("run");
  const std::string cmd = command + " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  std::filesystem::remove_all(dir);
  return r;
}

ExpectReports::ExpectReports(std::vector<std::string> types) : saved_(expected_types) {
  expected_types.insert(expected_types.end(), types.begin(), types.end());
}

ExpectReports::~ExpectReports() { expected_types = saved_; }

void simulate() {
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    ADD_FAILURE() << "the simulation ended with " << r.get_msg_type() << ": " << r.get_msg();
    return;
  }
  EXPECT_FALSE(sc_core::sc_pending_activity()) << "the simulation stopped with activity pending";
}

namespace {

// Warnings and errors fail the running test unless expected; the default actions still apply.
void report_handler(const sc_core::sc_report& r, const sc_core::sc_actions& actions) {
  if (r.get_severity() >= sc_core::SC_WARNING) {
    bool expected = false;
    for (const std::string& t : expected_types) expected = expected || t == r.get_msg_type();
    if (!expected)
      ADD_FAILURE() << "SystemC " << (r.get_severity() == sc_core::SC_WARNING ? "warning" : "error")
                    << " " << r.get_msg_type() << ": " << r.get_msg();
  }
  sc_core::sc_report_handler::default_handler(r, actions);
}

}  // namespace

}  // namespace rtsim::test

// Every test executable links SystemC, whose library owns main() and calls sc_main: run the
// tests from here, so SystemC's kernel is set up as it would be in the simulator.
// Weak: a test file may bring its own sc_main (to drive one SystemC scenario itself).
extern "C" __attribute__((weak)) int sc_main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  sc_core::sc_report_handler::set_handler(rtsim::test::report_handler);
  return RUN_ALL_TESTS();
}
