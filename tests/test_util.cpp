#include "tests/test_util.h"

#include <atomic>
#include <unistd.h>

namespace rtsim::test {

std::filesystem::path temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  auto dir = std::filesystem::temp_directory_path() /
             ("rtsim_test_" + tag + "_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace rtsim::test

// Every test executable links SystemC, whose library owns main() and calls sc_main: run the
// tests from here, so SystemC's kernel is set up as it would be in the simulator.
#include <gtest/gtest.h>

// Weak: a test file may bring its own sc_main (to drive one SystemC scenario itself).
extern "C" __attribute__((weak)) int sc_main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
