// What the PLY, OBJ and glTF tests share: writing files, catching an input error's message,
// comparing triangles.
#pragma once

#include "common/error.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
#include "scene_loader/procedural.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <vector>

namespace rtsim::loader_test {

namespace fs = std::filesystem;

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// The message of the InputError that `f` throws; fails the test if it throws nothing.
inline std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

inline bool same_triangles(const std::vector<Triangle>& a, const std::vector<Triangle>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].v0 != b[i].v0 || a[i].v1 != b[i].v1 || a[i].v2 != b[i].v2 ||
        a[i].material != b[i].material)
      return false;
  return true;
}

inline void expect_near(const Vec3& got, const Vec3& want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// ---------------------------------------------------------------------------------------------
// PLY

}  // namespace rtsim::loader_test
