// BART AFF loader and Kochanek-Bartels splines.

#include "common/error.h"
#include "scene_loader/aff_loader.h"
#include "scene_loader/kb_spline.h"
#include "tests/scene_loader/aff_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim {
namespace {

using namespace aff_test;

struct Timed {
  Scene scene;
  double seconds;
};

Timed load_timed(const fs::path& p, double time) {
  Timed r;
  auto t0 = std::chrono::steady_clock::now();
  load_aff(p.string(), time, r.scene);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void expect_materials_valid(const Scene& s) {
  ASSERT_FALSE(s.materials.empty());
  for (const Triangle& t : s.triangles) ASSERT_LT(t.material, s.materials.size());
}

TEST(AffScenes, KitchenAtTimeZero) {
  RTSIM_REQUIRE_SHARED_SCENES();
  Timed r = load_timed(test::shared_scenes() / "bart/kitchen/kitchen.aff", 0.0);
  std::cout << "kitchen: " << r.scene.triangles.size() << " triangles in " << r.seconds * 1e3
            << " ms\n";
  const Scene& s = r.scene;
  EXPECT_EQ(s.triangles.size(), 110561u);
  EXPECT_EQ(s.time, 0.0);
  ASSERT_TRUE(s.has_camera);
  expect_vec(s.camera.eye, 3.75, 2.3, 3.6, 1e-4);
  expect_vec(s.camera.dir, -0.3134643, -0.4198143, -0.8517605, 1e-4);
  expect_vec(s.camera.up, -0.1270031, 0.9074437, -0.4005198, 1e-4);
  EXPECT_NEAR(glm::length(s.camera.dir), 1.0, 1e-6);
  EXPECT_NEAR(s.camera.vfov_deg, 40.0, 1e-4);
  EXPECT_EQ(s.width, 800);
  EXPECT_EQ(s.height, 600);

  ASSERT_EQ(s.lights.size(), 6u);
  const double pos[6][3] = {{2.15, 2, 0.9}, {2.35, 2, 0.9},   {2.15, 2, 1.1},
                            {2.35, 2, 1.1}, {4.35, 1.4, 1.0}, {0.25, 1.4, 1.0}};
  for (int i = 0; i < 6; ++i) {
    expect_vec(s.lights[i].position, pos[i][0], pos[i][1], pos[i][2], 1e-6);
    double c = i < 4 ? 0.3 : 0.4;
    expect_vec(s.lights[i].color, c, c, c, 1e-6);
  }
  expect_materials_valid(s);
}

TEST(AffScenes, RobotsAtTimeZero) {
  RTSIM_REQUIRE_SHARED_SCENES();
  Timed r = load_timed(test::shared_scenes() / "bart/robots/Robot.aff", 0.0);
  std::cout << "robots: " << r.scene.triangles.size() << " triangles in " << r.seconds * 1e3
            << " ms\n";
  const Scene& s = r.scene;
  EXPECT_EQ(s.triangles.size(), 71708u);
  ASSERT_TRUE(s.has_camera);
  expect_vec(s.camera.eye, -3.5, 2.0, -203.0, 1e-4);
  expect_vec(s.camera.dir, 0.0588120, 0.0987075, -0.9933771, 1e-4);
  expect_vec(s.camera.up, -0.0058429, 0.9951165, 0.0985344, 1e-4);
  EXPECT_NEAR(s.camera.vfov_deg, 36.8699, 1e-4);
  ASSERT_EQ(s.lights.size(), 1u);
  expect_vec(s.lights[0].position, 1, 500, 1, 1e-6);
  expect_vec(s.lights[0].color, 1, 1, 1, 0);
  expect_materials_valid(s);
}

// BART's kbsplrot.c flips rotation keys into their predecessor's hemisphere for the interior keys
// only; with that rule the robots camera at t = 10 looks where BART's own code looks (flipping the
// last key too, as we once did, gives (-0.350, -0.236, -0.906) there).
TEST(AffScenes, RobotsCameraAtTimeTenIsBarts) {
  RTSIM_REQUIRE_SHARED_SCENES();
  Scene s;
  load_aff((test::shared_scenes() / "bart/robots/Robot.aff").string(), 10.0, s);
  expect_vec(s.camera.dir, -0.5153, -0.2569, -0.8176, 5e-4);
  Scene all;  // the other rule, a scene file's `rotation_keys: all`
  load_aff((test::shared_scenes() / "bart/robots/Robot.aff").string(), 10.0, all,
           KbQuatSpline::Flip::kAll);
  expect_vec(all.camera.dir, -0.350, -0.236, -0.906, 5e-4);
}

TEST(AffScenes, KitchenCameraFollowsKeysOverTime) {
  RTSIM_REQUIRE_SHARED_SCENES();
  Scene s;
  load_aff((test::shared_scenes() / "bart/kitchen/kitchen.aff").string(), 5.0, s);
  EXPECT_EQ(s.time, 5.0);
  EXPECT_EQ(s.triangles.size(), 110561u);  // no visibility keys in the kitchen
  // Key at t = 5: eye (3.5, 0.2, 0.1), rotation -180 deg about -Y: looks down +Z.
  expect_vec(s.camera.eye, 3.5, 0.2, 0.1, 1e-5);
  expect_vec(s.camera.dir, 0, 0, 1, 1e-5);
  expect_vec(s.camera.up, 0, 1, 0, 1e-5);

  // The toy car moves between t = 0 and t = 8 (its transl keys go from x = 4.45 to ~3.2).
  Scene s0, s8;
  load_aff((test::shared_scenes() / "bart/kitchen/kitchen.aff").string(), 0.0, s0);
  load_aff((test::shared_scenes() / "bart/kitchen/kitchen.aff").string(), 8.0, s8);
  ASSERT_EQ(s0.triangles.size(), s8.triangles.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < s0.triangles.size(); ++i)
    if (s0.triangles[i].v0 != s8.triangles[i].v0) ++moved;
  EXPECT_GT(moved, 1000u);
  EXPECT_LT(moved, s0.triangles.size() / 2);
}

TEST(AffScenes, FiniteGeometryAcrossTheAnimations) {
  // Times inside the kitchen wheels' coincident keys (7.16) and the robots' key list that
  // jumps back in time (Robot1.aff), near the ends of the camera paths, and past them.
  RTSIM_REQUIRE_SHARED_SCENES();
  struct Case {
    const char* file;
    std::size_t triangles;
    std::vector<double> times;
  };
  for (const Case& c : {Case{"bart/kitchen/kitchen.aff", 110561u, {7.16, 7.2, 19.9, 30.0}},
                        Case{"bart/robots/Robot.aff", 71708u, {12.5, 43.0, 48.2, 60.0}}}) {
    for (double t : c.times) {
      Scene s;
      load_aff((test::shared_scenes() / c.file).string(), t, s);
      EXPECT_EQ(s.triangles.size(), c.triangles) << c.file << " t=" << t;
      std::size_t bad = 0;
      for (const Triangle& tri : s.triangles)
        for (Vec3 v : {tri.v0, tri.v1, tri.v2})
          if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) ++bad;
      EXPECT_EQ(bad, 0u) << c.file << " t=" << t;
      EXPECT_NEAR(glm::length(s.camera.dir), 1.0, 1e-5) << c.file << " t=" << t;
      EXPECT_NEAR(glm::length(s.camera.up), 1.0, 1e-5) << c.file << " t=" << t;
    }
  }
}

// ---- small synthetic scenes ------------------------------------------------------------------

TEST(AffLoader, StaticTransformsComposeOuterTimesInner) {
  // xs: scale 2, rotate 90 about Y, translate (1,0,0): (1,0,0) -> (2,0,0) -> (0,0,-2) -> (1,0,-2).
  Scene s = load_text(std::string("xs 2 2 2  0 1 0 90  1 0 0 {\n") + kOneTriangle + "}\n");
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_vec(s.triangles[0].v0, 1, 0, -2, 1e-6);
  expect_vec(s.triangles[0].v1, 1, 2, 0, 1e-6);
  // Outer translate, inner scale: (1,0,0) -> (3,0,0) -> (3,5,0).
  Scene n = load_text(std::string("xs 1 1 1 1 0 0 0  0 5 0 {\n xs 3 3 3 1 0 0 0 0 0 0 {\n") +
                      kOneTriangle + "}\n}\n");
  expect_vec(n.triangles[0].v0, 3, 5, 0, 1e-6);
}

TEST(AffLoader, AnimatedTransformUsesLaterKeysAndVisibility) {
  std::string text =
      std::string("x mover {\n") + kOneTriangle +
      "}\nk mover {\n  transl 4\n   -1  0 0 0  0 0 0\n    0  0 0 0  0 0 0\n    2  4 0 0  0 0 0\n   "
      " 3  4 0 0  0 0 0\n  rot 4\n   -1  0 0 1 0  0 0 0\n    0  0 0 1 0  0 0 0\n    2  0 0 1 90  0 "
      "0 0\n    3  0 0 1 90  0 0 0\n  visibility 2\n    5 0\n    7 1\n}\n";
  Scene s0 = load_text(text, 0.0);
  expect_vec(s0.triangles.at(0).v0, 1, 0, 0, 1e-6);
  // t = 2: rotate (1,0,0) by 90 deg about Z -> (0,1,0), then translate by (4,0,0).
  Scene s2 = load_text(text, 2.0);
  expect_vec(s2.triangles.at(0).v0, 4, 1, 0, 1e-6);
  // Between the keys the translation is the KB curve (symmetric here: halfway at t = 1).
  Scene s1 = load_text(text, 1.0);
  EXPECT_NEAR(s1.triangles.at(0).v2.x, 2.0, 1e-6);
  EXPECT_TRUE(load_text(text, 5.0).triangles.empty());  // invisible from t = 5
  EXPECT_TRUE(load_text(text, 6.5).triangles.empty());
  EXPECT_EQ(load_text(text, 7.0).triangles.size(), 1u);  // visible again from t = 7
  EXPECT_EQ(load_text(text, 4.9).triangles.size(), 1u);
}

// tpa: each triangle is the linear interpolation of its two samples around the load time,
// clamped to the first and last; a thousand of them, five samples each, load as BART files hold
// them.
TEST(AffLoader, AnimatedTrianglesInterpolateTheirSamplesLinearly) {
  constexpr int kTris = 1000, kSamples = 5;
  const double times[kSamples] = {0.0, 1.0, 2.5, 3.0, 6.0};
  // Vertex j of triangle i at sample k: (i + k * k, j, 10 * i + times[k]).
  auto vertex = [&](int i, int j, int k) { return glm::dvec3(i + k * k, j, 10.0 * i + times[k]); };
  std::string text;
  for (int i = 0; i < kTris; ++i) {
    text += "tpa " + std::to_string(kSamples) + "\n";
    for (int k = 0; k < kSamples; ++k) {
      text += std::to_string(times[k]) + "\n";
      for (int j = 0; j < 3; ++j) {
        const glm::dvec3 v = vertex(i, j, k);
        text += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) +
                "  0 0 1\n";
      }
    }
  }
  for (double t : {-1.0, 0.5, 3.7, 9.0}) {
    const Scene s = load_text(text, t);
    ASSERT_EQ(s.triangles.size(), size_t(kTris)) << t;
    int k = 0;
    while (k + 1 < kSamples && times[k + 1] <= t) ++k;
    const double w =
        k + 1 < kSamples && t > times[k] ? (t - times[k]) / (times[k + 1] - times[k]) : 0.0;
    for (int i : {0, 417, 999}) {
      const Vec3* got[3] = {&s.triangles[i].v0, &s.triangles[i].v1, &s.triangles[i].v2};
      for (int j = 0; j < 3; ++j) {
        const glm::dvec3 want = k + 1 < kSamples
                                    ? (1 - w) * vertex(i, j, k) + w * vertex(i, j, k + 1)
                                    : vertex(i, j, k);
        expect_vec(*got[j], want.x, want.y, want.z, 1e-3);
      }
    }
  }
  // Bad input: a missing vertex, a time out of order.
  expect_text_error(
      "tpa 2\n0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1\n0 0 0 0 0 1\n1 0 0 0 0 1\n", 8,
      "end of file");
  expect_text_error("tpa 2\n1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0.5\n", 6,
                    "expected increasing times");
}

// la NAME: a light placed by the keyframes NAME, given before or after it; none is an error.
TEST(AffLoader, AnimatedLightsFollowTheirKeyframes) {
  const std::string keys =
      "k lamp {\n  transl 4\n  -1 0 0 0 0 0 0\n  0 0 0 0 0 0 0\n  2 4 0 0 0 0 0\n  3 4 0 0 0 0 "
      "0\n}\n";
  const Scene s = load_text("la lamp 1 2 3 0.5 0.5 0.5\n" + keys, 2.0);
  ASSERT_EQ(s.lights.size(), 1u);
  expect_vec(s.lights[0].position, 5, 2, 3, 1e-6);  // (1, 2, 3) moved by (4, 0, 0)
  expect_vec(s.lights[0].color, 0.5, 0.5, 0.5, 1e-6);
  const Scene inside = load_text("xs 1 1 1  0 1 0 0  0 10 0 {\nla lamp 1 2 3\n}\n" + keys, 0.0);
  expect_vec(inside.lights.at(0).position, 1, 12, 3, 1e-6);  // the enclosing static transform too
  expect_text_error("l 0 0 0\nla nowhere 1 2 3\n", 2, "expected keyframes 'k nowhere'");
}

// d LEVEL sets the detail level; an include `i LEVEL FILE` above it is skipped (BART's rule), so
// one file can hold a coarse and a fine version of an object. ttp is a textured triangle patch.
TEST(AffLoader, DetailLevelsChooseIncludesAndTexturedPatchesLoad) {
  const fs::path dir = test::temp_dir("aff_detail");
  write_file(dir / "coarse.aff", kOneTriangle);
  write_file(dir / "fine.aff", std::string(kOneTriangle) + kOneTriangle);
  auto triangles_at = [&](const std::string& d) {
    write_file(dir / "top.aff", d + "i 0 coarse.aff\ni 1 fine.aff\n");
    Scene s;
    load_aff((dir / "top.aff").string(), 0.0, s);
    return s.triangles.size();
  };
  EXPECT_EQ(triangles_at(""), 1u);       // default level 0: the level-1 include is skipped
  EXPECT_EQ(triangles_at("d 1\n"), 3u);  // both
  const Scene t = load_text("ttp tex.ppm  0 0 0 0 0 1 0 0  1 0 0 0 0 1 1 0  0 1 0 0 0 1 0 1\n");
  ASSERT_EQ(t.triangles.size(), 1u);
  expect_vec(t.triangles[0].v1, 1, 0, 0, 0);
}

TEST(AffLoader, InvisibleParentHidesChildrenButNotSiblings) {
  std::string text = std::string("x outer {\n x inner {\n") + kOneTriangle + " }\n" + kOneTriangle +
                     "}\n" + kOneTriangle + "k outer { visibility 1  0 0 }\n";
  EXPECT_EQ(load_text(text, 1.0).triangles.size(), 1u);
  EXPECT_EQ(load_text(text, -1.0).triangles.size(), 3u);
}

TEST(AffLoader, CameraFromViewAndFromCameraKeys) {
  std::string view =
      "v\nfrom 1 2 3\nat 1 2 -7\nup 0 2 0\nangle 30\nhither 0.5\nresolution 640 480\n";
  Scene s = load_text(view);
  ASSERT_TRUE(s.has_camera);
  expect_vec(s.camera.eye, 1, 2, 3, 0);
  expect_vec(s.camera.dir, 0, 0, -1, 1e-7);
  expect_vec(s.camera.up, 0, 2, 0, 0);  // kept as given
  EXPECT_FLOAT_EQ(s.camera.vfov_deg, 30.f);
  EXPECT_FLOAT_EQ(s.camera.hither, 0.5f);
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 480);

  // k camera overrides v: rotation 90 deg about Y turns -Z into -X.
  Scene k = load_text(
      view +
      "k camera {\n transl 4\n -1 9 9 9 0 0 0\n 0 5 6 7 0 0 0\n 1 5 6 7 0 0 0\n 2 9 9 9 0 0 0\n "
      "rot 4\n -1 0 1 0 90 0 0 0\n 0 0 1 0 90 0 0 0\n 1 0 1 0 90 0 0 0\n 2 0 1 0 0 0 0 0\n}\n");
  expect_vec(k.camera.eye, 5, 6, 7, 1e-6);
  expect_vec(k.camera.dir, -1, 0, 0, 1e-6);
  expect_vec(k.camera.up, 0, 1, 0, 1e-6);
  EXPECT_FLOAT_EQ(k.camera.vfov_deg, 30.f);
}

TEST(AffLoader, MaterialsAreGlobalInParseOrder) {
  std::string text =
      std::string("f 1 0.5 0.25  0.8 0.2  30 0.1 1.5\n") + kOneTriangle +
      "xs 1 1 1 1 0 0 0 0 0 0 {\n  fm 0.1 0.1 0.1  0.9 0.8 0.7  0.3 0.6 0.9  12 0 1.3\n}\n" +
      kOneTriangle;
  Scene s = load_text(text);
  ASSERT_EQ(s.triangles.size(), 2u);
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& f = s.materials[s.triangles[0].material];
  expect_vec(f.diffuse, 0.8, 0.4, 0.2, 1e-6);
  expect_vec(f.specular, 0.2, 0.1, 0.05, 1e-6);
  EXPECT_FLOAT_EQ(f.shininess, 30.f);
  EXPECT_FLOAT_EQ(f.reflectance, 0.2f);
  EXPECT_FLOAT_EQ(f.transmittance, 0.1f);
  EXPECT_FLOAT_EQ(f.ior, 1.5f);
  // The fm inside the braces still applies after the closing brace.
  const Material& fm = s.materials[s.triangles[1].material];
  expect_vec(fm.diffuse, 0.9, 0.8, 0.7, 1e-6);
  expect_vec(fm.specular, 0.3, 0.6, 0.9, 1e-6);
  EXPECT_NEAR(fm.reflectance, 0.6, 1e-6);
  EXPECT_FLOAT_EQ(fm.shininess, 12.f);
}

TEST(AffLoader, PrimitivesLightsCommentsAndMeshSections) {
  std::string text =
      "# comment line\n% another comment\nl 1 2 3\nl 4 5 6  0.5 0.25 1\nb 0 0 0\nam 1 1 1\na 0 10 "
      "100\np 5  0 0 0  1 0 0  2 1 0  1 2 0  0 1 0\npp 3  0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 "
      "1\ntt tex.ppm 0 0 0 0 0  1 0 0 1 0  0 1 0 0 1\nm vertices 4  0 0 0  1 0 0  1 1 0  0 1 0\n  "
      "normals 1  0 0 1\n  texturecoords 4 missing_texture.ppm  0 0 1 0 1 1 0 1\n  triangles 2  0 "
      "1 2  0 0 0  0 1 2   0 2 3  0 0 0  0 2 3\n";
  Scene s = load_text(text);
  EXPECT_EQ(s.triangles.size(), 3u + 1u + 1u + 2u);
  ASSERT_EQ(s.lights.size(), 2u);
  expect_vec(s.lights[0].color, 1, 1, 1, 0);
  expect_vec(s.lights[1].position, 4, 5, 6, 0);
  expect_vec(s.lights[1].color, 0.5, 0.25, 1, 0);
  EXPECT_FALSE(s.has_camera);
}

TEST(AffLoader, SpheresAndConesAreTessellated) {
  Scene s = load_text("s 1 2 3 2\n");
  EXPECT_EQ(s.triangles.size(), 528u);
  for (const Triangle& t : s.triangles) {
    for (Vec3 v : {t.v0, t.v1, t.v2}) EXPECT_NEAR(glm::length(v - Vec3(1, 2, 3)), 2.0, 1e-5);
    // Counter-clockwise seen from outside: the normal points away from the centre.
    EXPECT_GT(glm::dot(t.normal(), (t.v0 + t.v1 + t.v2) / 3.f - Vec3(1, 2, 3)), 0.f);
  }
  Scene c = load_text("c\n0 0 0 1\n0 3 0 0.5\n");
  EXPECT_EQ(c.triangles.size(), 48u);
  Scene cone = load_text("c 0 0 0 1  0 0 2 0\n");  // pointed cone: one triangle per side
  EXPECT_EQ(cone.triangles.size(), 24u);
  for (const Triangle& t : c.triangles) {
    Vec3 mid = (t.v0 + t.v1 + t.v2) / 3.f;
    EXPECT_GT(glm::dot(t.normal(), Vec3(mid.x, 0, mid.z)), 0.f);
  }
}

TEST(AffLoader, IncludesResolveRelativeToIncludingFile) {
  fs::path dir = test::temp_dir("aff_inc");
  fs::create_directories(dir / "sub");
  write_file(dir / "top.aff", "xs 1 1 1 1 0 0 0  10 0 0 {\n i 0 sub/a.aff\n}\n");
  write_file(dir / "sub" / "a.aff", std::string("i 0 b.aff\n") + kOneTriangle);
  write_file(dir / "sub" / "b.aff", kOneTriangle);
  Scene s;
  load_aff((dir / "top.aff").string(), 0.0, s);
  ASSERT_EQ(s.triangles.size(), 2u);
  expect_vec(s.triangles[0].v0, 11, 0, 0, 1e-6);
}

TEST(AffLoader, AppendsToExistingScene) {
  fs::path dir = test::temp_dir("aff_append");
  write_file(dir / "a.aff", std::string("fm 0 0 0 1 0 0 0 0 0 1 0 1\n") + kOneTriangle);
  Scene s;
  s.add_material(Material{});
  s.triangles.push_back(Triangle{});
  load_aff((dir / "a.aff").string(), 0.0, s);
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.triangles[1].material, 1u);
  EXPECT_FLOAT_EQ(s.materials[1].diffuse.x, 1.f);
}

// ---- malformed input -------------------------------------------------------------------------

}  // namespace
}  // namespace rtsim
