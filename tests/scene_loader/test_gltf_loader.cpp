// The glTF loader: a .gltf and its .glb give the same world-space scene (node transforms, the
// three triangle modes, a point light, the camera); no scene means every root; errors name the
// file.
#include "common/error.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
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

// Hand-rolled transforms for the expected values (independent of the loader's glm code).
struct Trs {
  std::array<double, 3> t{0, 0, 0};
  std::array<double, 4> r{0, 0, 0, 1};  // x y z w
  std::array<double, 3> s{1, 1, 1};
  Vec3 apply(const Vec3& p) const {
    const double v[3] = {p.x * s[0], p.y * s[1], p.z * s[2]};
    // v' = v + 2w (q x v) + 2 q x (q x v)
    const double q[3] = {r[0], r[1], r[2]}, w = r[3];
    const double c1[3] = {q[1] * v[2] - q[2] * v[1], q[2] * v[0] - q[0] * v[2],
                          q[0] * v[1] - q[1] * v[0]};
    const double c2[3] = {q[1] * c1[2] - q[2] * c1[1], q[2] * c1[0] - q[0] * c1[2],
                          q[0] * c1[1] - q[1] * c1[0]};
    return Vec3(static_cast<float>(v[0] + 2 * w * c1[0] + 2 * c2[0] + t[0]),
                static_cast<float>(v[1] + 2 * w * c1[1] + 2 * c2[1] + t[1]),
                static_cast<float>(v[2] + 2 * w * c1[2] + 2 * c2[2] + t[2]));
  }
};

Vec3 apply_matrix(const std::vector<double>& m, const Vec3& p) {  // column-major 4x4
  return Vec3(static_cast<float>(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12]),
              static_cast<float>(m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13]),
              static_cast<float>(m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]));
}

// The test scene: root node 0 (TRS) with children 1 (mesh 0 = indexed quad with strided
// positions, translated) and 2 (matrix; mesh 1 = a plain triangle, a u8-indexed strip and a
// skipped POINTS primitive) whose child 3 carries a point light; root node 4 holds the camera.
struct GltfFixture {
  tinygltf::Model model;
  Trs root, quad_node, light_node, camera_node;
  std::vector<double> matrix;
  std::vector<Vec3> quad, tri, strip;  // local positions

  GltfFixture() {
    root.t = {1, 2, 3};
    root.r = {0, std::sin(M_PI / 4), 0, std::cos(M_PI / 4)};  // 90 degrees about +Y
    root.s = {2, 2, 2};
    quad_node.t = {0, 0, -1};
    light_node.t = {0, 5, 0};
    camera_node.t = {0, 1, 10};
    camera_node.r = {std::sin(-M_PI / 36), 0, 0, std::cos(-M_PI / 36)};  // -10 degrees about +X
    // 90 degrees about +Z, then x += 5
    matrix = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1};
    quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    tri = {{0, 0, 0}, {0, 2, 0}, {0, 0, 2}};
    strip = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 2}};
    add_meshes();
    add_nodes();
    add_light_camera_and_scene();
  }

  // The buffer's views and accessors, and the two meshes: a quad (16-byte stride, 16-bit
  // indices), then a triangle, a strip (8-bit indices) and a skipped POINTS primitive.
  void add_meshes() {
    const uint16_t quad_idx[6] = {0, 1, 2, 0, 2, 3};
    const uint8_t strip_idx[4] = {0, 1, 2, 3};
    tinygltf::Primitive pq;
    pq.attributes["POSITION"] = positions(quad, 16);
    pq.indices =
        add_accessor(add_view(quad_idx, sizeof quad_idx, 0, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, 6);
    pq.material = 0;
    pq.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Primitive pt;
    pt.attributes["POSITION"] = positions(tri, 12);
    pt.material = 1;
    pt.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Primitive ps;
    ps.attributes["POSITION"] = positions(strip, 12);
    ps.indices =
        add_accessor(add_view(strip_idx, sizeof strip_idx, 0, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, 4);
    ps.material = 1;
    ps.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
    tinygltf::Primitive pp = pt;
    pp.mode = TINYGLTF_MODE_POINTS;
    tinygltf::Buffer buffer;
    buffer.data = data_;
    model.buffers.push_back(buffer);
    tinygltf::Mesh m0, m1;
    m0.primitives = {pq};
    m1.primitives = {pt, ps, pp};
    model.meshes = {m0, m1};
    tinygltf::Material red, green;
    red.pbrMetallicRoughness.baseColorFactor = {1, 0, 0, 1};
    green.pbrMetallicRoughness.baseColorFactor = {0, 1, 0, 0.5};
    model.materials = {red, green};
  }

  void add_nodes() {
    auto trs_node = [](const Trs& t) {
      tinygltf::Node n;
      n.translation = {t.t[0], t.t[1], t.t[2]};
      n.rotation = {t.r[0], t.r[1], t.r[2], t.r[3]};
      n.scale = {t.s[0], t.s[1], t.s[2]};
      return n;
    };
    tinygltf::Node n0 = trs_node(root), n1 = trs_node(quad_node), n2, n3,
                   n4 = trs_node(camera_node);
    n0.children = {1, 2};
    n1.mesh = 0;
    n2.matrix = matrix;
    n2.mesh = 1;
    n2.children = {3};
    n3.translation = {light_node.t[0], light_node.t[1], light_node.t[2]};
    n3.extensions["KHR_lights_punctual"] =
        tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(0)}});
    n4.camera = 0;
    model.nodes = {n0, n1, n2, n3, n4};
  }

  void add_light_camera_and_scene() {
    tinygltf::Light light;
    light.type = "point";
    light.color = {1, 0.5, 0.25};
    light.intensity = 3;
    model.lights = {light};
    tinygltf::Camera cam;
    cam.type = "perspective";
    cam.perspective.yfov = 0.8;
    cam.perspective.znear = 0.1;
    cam.perspective.aspectRatio = 1.5;
    model.cameras = {cam};
    tinygltf::Scene scene;
    scene.nodes = {0, 4};
    model.scenes = {scene};
    model.defaultScene = 0;
    model.asset.version = "2.0";
  }

  int add_view(const void* p, size_t n, size_t stride, int target) {
    while (data_.size() % 4) data_.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = data_.size();
    v.byteLength = n;
    v.byteStride = stride;
    v.target = target;
    data_.insert(data_.end(), static_cast<const unsigned char*>(p),
                 static_cast<const unsigned char*>(p) + n);
    model.bufferViews.push_back(v);
    return static_cast<int>(model.bufferViews.size() - 1);
  }
  int add_accessor(int view, int component, int type, size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component;
    a.type = type;
    a.count = count;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  }
  int positions(const std::vector<Vec3>& pts, size_t stride) {
    std::vector<float> f(pts.size() * stride / 4, -99.f);  // padding that must not be read
    for (size_t i = 0; i < pts.size(); ++i) std::memcpy(&f[i * stride / 4], &pts[i], 12);
    return add_accessor(
        add_view(f.data(), f.size() * 4, stride == 12 ? 0 : stride, TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, pts.size());
  }
  std::vector<unsigned char> data_;  // the buffer

  std::vector<Triangle> expected() const {
    std::vector<Triangle> out;
    auto quad_world = [&](const Vec3& p) { return root.apply(quad_node.apply(p)); };
    auto mesh1_world = [&](const Vec3& p) { return root.apply(apply_matrix(matrix, p)); };
    out.push_back({quad_world(quad[0]), quad_world(quad[1]), quad_world(quad[2]), 0});
    out.push_back({quad_world(quad[0]), quad_world(quad[2]), quad_world(quad[3]), 0});
    out.push_back({mesh1_world(tri[0]), mesh1_world(tri[1]), mesh1_world(tri[2]), 1});
    out.push_back({mesh1_world(strip[0]), mesh1_world(strip[1]), mesh1_world(strip[2]), 1});
    out.push_back({mesh1_world(strip[1]), mesh1_world(strip[3]), mesh1_world(strip[2]), 1});
    return out;
  }
  Vec3 light_position() const {
    return root.apply(apply_matrix(matrix, light_node.apply(Vec3(0.f))));
  }
};

void expect_fixture_scene(const GltfFixture& f, const Scene& s) {
  const auto want = f.expected();
  ASSERT_EQ(s.triangles.size(), want.size());
  ASSERT_EQ(s.materials.size(), 2u);
  for (size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("triangle " + std::to_string(i));
    expect_near(s.triangles[i].v0, want[i].v0);
    expect_near(s.triangles[i].v1, want[i].v1);
    expect_near(s.triangles[i].v2, want[i].v2);
    EXPECT_EQ(s.materials[s.triangles[i].material].diffuse,
              want[i].material ? Vec3(0, 1, 0) : Vec3(1, 0, 0));
  }
  ASSERT_EQ(s.lights.size(), 1u);
  expect_near(s.lights[0].position, f.light_position());
  EXPECT_EQ(s.lights[0].color, Vec3(1, 0.5f, 0.25f));
  ASSERT_TRUE(s.has_camera);
  expect_near(s.camera.eye, Vec3(0, 1, 10));
  const float a = static_cast<float>(M_PI / 18);  // the camera is pitched 10 degrees down
  expect_near(s.camera.dir, Vec3(0, -std::sin(a), -std::cos(a)));
  expect_near(s.camera.up, Vec3(0, std::cos(a), -std::sin(a)));
  EXPECT_NEAR(s.camera.vfov_deg, 0.8 * 180 / M_PI, 1e-4);
}

TEST(GltfLoader, GltfAndGlbLoadTheSameWorldSpaceScene) {
  GltfFixture f;
  const fs::path dir = test::temp_dir("gltf");
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.gltf").string(), true, true, true, false));
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.glb").string(), true, true, false, true));
  Scene a, b;
  load_gltf((dir / "s.gltf").string(), a);
  load_gltf((dir / "s.glb").string(), b);
  {
    SCOPED_TRACE(".gltf");
    expect_fixture_scene(f, a);
  }
  {
    SCOPED_TRACE(".glb");
    expect_fixture_scene(f, b);
  }
  EXPECT_TRUE(same_triangles(a.triangles, b.triangles));
  fs::remove_all(dir);
}

TEST(GltfLoader, NoSceneMeansAllRootNodes) {
  GltfFixture f;
  f.model.scenes.clear();
  f.model.defaultScene = -1;
  const fs::path dir = test::temp_dir("gltf_noscene");
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.gltf").string(), true, true, true, false));
  Scene s;
  load_gltf((dir / "s.gltf").string(), s);
  expect_fixture_scene(f, s);
  fs::remove_all(dir);
}

TEST(GltfLoader, ErrorsNameTheFile) {
  const fs::path dir = test::temp_dir("gltf_bad");
  const std::string file = (dir / "bad.gltf").string();
  write_text(file, "{ \"asset\": {\"version\": \"2.0\"}, \"nodes\": [ ");
  std::string msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_EQ(msg.rfind(file + ": tinygltf: ", 0), 0u) << msg;

  GltfFixture f;
  f.model.nodes[1].mesh = 7;
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&f.model, file, true, true, true, false));
  msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_EQ(msg.rfind(file + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find("mesh 7 out of range"), std::string::npos) << msg;

  GltfFixture g;
  g.model.nodes[2].children = {3, 0};  // a cycle
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&g.model, file, true, true, true, false));
  msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_NE(msg.find("cycle"), std::string::npos) << msg;

  msg = input_error([&] {
    Scene s;
    load_gltf(file + ".missing.glb", s);
  });
  EXPECT_NE(msg.find(file + ".missing.glb"), std::string::npos) << msg;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim
