// The OBJ loader: faces and their MTL materials, a missing MTL only a warning, bad indices named
// by file and line.
#include "common/error.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
#include "scene_loader/procedural.h"
#include "tests/scene_loader/loader_test_util.h"
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

namespace rtsim {
namespace {

using namespace loader_test;

TEST(ObjLoader, LoadsFacesAndMtlMaterials) {
  const fs::path dir = test::temp_dir("obj");
  write_text(dir / "m.mtl",
             "newmtl red\nKd 1 0 0\nKs 0.5 0.25 0.125\nNs 32\nnewmtl blue\nKd 0 0 1\n");
  write_text(
      dir / "m.obj",
      "# test\nmtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nusemtl red\nf "
      "1//1 2//1 3//1 4//1\nusemtl blue\nf 1 2 5\ng other\nusemtl none\nf -3 -2 -1\n");
  Scene s;
  s.add_material(Material{});  // loaders append after what is there
  load_obj((dir / "m.obj").string(), s);
  ASSERT_EQ(s.triangles.size(), 4u);
  ASSERT_EQ(s.materials.size(), 4u);  // existing, red, blue, default
  const Material& red = s.materials[s.triangles[0].material];
  EXPECT_EQ(red.diffuse, Vec3(1, 0, 0));
  EXPECT_EQ(red.specular, Vec3(0.5f, 0.25f, 0.125f));
  EXPECT_EQ(red.shininess, 32.f);
  EXPECT_EQ(s.triangles[0].material, 1u);
  EXPECT_EQ(s.triangles[1].material, 1u);
  EXPECT_EQ(s.triangles[2].material, 2u);
  EXPECT_EQ(s.materials[2].diffuse, Vec3(0, 0, 1));
  EXPECT_EQ(s.triangles[3].material, 3u);  // unknown material -> default
  // The quad is fan-triangulated: (1 2 3) (1 3 4).
  EXPECT_EQ(s.triangles[0].v0, Vec3(0, 0, 0));
  EXPECT_EQ(s.triangles[0].v1, Vec3(1, 0, 0));
  EXPECT_EQ(s.triangles[0].v2, Vec3(1, 1, 0));
  EXPECT_EQ(s.triangles[1].v2, Vec3(0, 1, 0));
  EXPECT_EQ(s.triangles[2].v2, Vec3(0, 0, 1));
  // Negative indices count back from the last vertex.
  EXPECT_EQ(s.triangles[3].v0, Vec3(1, 1, 0));
  EXPECT_EQ(s.triangles[3].v2, Vec3(0, 0, 1));
  fs::remove_all(dir);
}

TEST(ObjLoader, MissingMtlIsOnlyAWarning) {
  const fs::path dir = test::temp_dir("obj_nomtl");
  write_text(dir / "m.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
  Scene s;
  load_obj((dir / "m.obj").string(), s);
  ASSERT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].diffuse, Material{}.diffuse);
  fs::remove_all(dir);
}

TEST(ObjLoader, IndexOutOfRangeNamesFileAndLine) {
  const fs::path dir = test::temp_dir("obj_bad");
  const std::string file = (dir / "bad.obj").string();
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\nf 1 2 9\nf 1 2 3\n");
  std::string msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":6: face vertex index 9 is out of range (the file has 3 vertices)"),
            std::string::npos)
      << msg;
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":4: face vertex index -4"), std::string::npos) << msg;
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");  // tinyobjloader's own error
  msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":4:"), std::string::npos) << msg;
  msg = input_error([&] {
    Scene s;
    load_obj(file + ".missing", s);
  });
  EXPECT_NE(msg.find(file + ".missing: cannot open"), std::string::npos) << msg;
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// glTF

}  // namespace
}  // namespace rtsim
