// What the AFF tests share: writing a scene file, loading text as a scene, and the checks that
// bad input names its file and line.
#pragma once

#include "common/error.h"
#include "scene_loader/aff_loader.h"
#include "scene_loader/kb_spline.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim::aff_test {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

// ---- helpers ---------------------------------------------------------------------------------

inline void write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

// Loads `text` written to DIR/name (DIR fresh per call).
inline Scene load_text(const std::string& text, double time = 0.0,
                       const std::string& name = "scene.aff") {
  fs::path dir = test::temp_dir("aff");
  write_file(dir / name, text);
  Scene s;
  load_aff((dir / name).string(), time, s);
  return s;
}

// Expects InputError whose message has "<file>:<line>:" and `also`.
inline void expect_input_error(const std::string& path, const std::string& file_name, long line,
                               const std::string& also) {
  try {
    Scene s;
    load_aff(path, 0.0, s);
    FAIL() << "no InputError for " << file_name;
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(file_name + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find(also), std::string::npos) << msg;
  }
}

inline void expect_text_error(const std::string& text, long line, const std::string& also) {
  fs::path dir = test::temp_dir("aff_err");
  write_file(dir / "bad.aff", text);
  expect_input_error((dir / "bad.aff").string(), "bad.aff", line, also);
}

inline void expect_vec(const Vec3& got, double x, double y, double z, double tol) {
  EXPECT_NEAR(got.x, x, tol);
  EXPECT_NEAR(got.y, y, tol);
  EXPECT_NEAR(got.z, z, tol);
}

const char* kOneTriangle = "m vertices 3  1 0 0  0 1 0  0 0 1  triangles 1  0 1 2\n";

}  // namespace rtsim::aff_test
