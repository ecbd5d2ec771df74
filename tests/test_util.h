// Helpers shared by the test files.
#pragma once

#include <filesystem>
#include <string>

namespace rtsim::test {

inline std::filesystem::path shared_scenes() { return RTSIM_SHARED_SCENES; }
inline std::filesystem::path source_dir() { return RTSIM_SOURCE_DIR; }
inline bool have_shared_scenes() { return std::filesystem::exists(shared_scenes() / "README.md"); }

// A fresh temporary directory per call, removed by the caller if wanted.
std::filesystem::path temp_dir(const std::string& tag);

}  // namespace rtsim::test

#define RTSIM_REQUIRE_SHARED_SCENES()                                          \
  do {                                                                         \
    if (!::rtsim::test::have_shared_scenes()) GTEST_SKIP() << "no ../shared/scenes"; \
  } while (0)
