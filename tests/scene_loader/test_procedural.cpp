// The procedural city: the same bits for the same parameters, the documented triangle count at
// every scale (the blocks knob), and its parameters validated.
#include "common/error.h"
#include "scene_loader/procedural.h"
#include "tests/scene_loader/loader_test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace rtsim {
namespace {

using namespace loader_test;

// The documented count (procedural.h), written out again here rather than taken from the library.
size_t expected_triangles(const CityParams& p) {
  const size_t b = static_cast<size_t>(p.blocks), s = static_cast<size_t>(p.sphere_segments);
  return 2 + 10 * b * b + ((b * b + 1) / 2 + b) * 2 * s * (s / 2 - 1);
}

TEST(Procedural, SameSeedSameTrianglesDifferentSeedDifferent) {
  Scene a, b, c;
  make_city(CityParams{}, a);
  make_city(CityParams{}, b);
  CityParams other;
  other.seed = 2;
  make_city(other, c);
  EXPECT_TRUE(same_triangles(a.triangles, b.triangles));
  EXPECT_EQ(a.triangles.size(), c.triangles.size());
  EXPECT_FALSE(same_triangles(a.triangles, c.triangles));
}

// Bit-identical everywhere: a hash of the default city's bits, fixed when the generator was
// written. Changing the city on purpose means updating it.
TEST(Procedural, DefaultCityHashIsStable) {
  Scene s;
  make_city(CityParams{}, s);
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  auto mix = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i)
      h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  for (const Triangle& t : s.triangles) {
    mix(&t.v0, 12);
    mix(&t.v1, 12);
    mix(&t.v2, 12);
    mix(&t.material, 4);
  }
  for (const Light& l : s.lights) mix(&l.position, 12);
  mix(&s.camera.eye, 12);
  mix(&s.camera.dir, 12);
  std::printf("default city hash: 0x%016llx\n", static_cast<unsigned long long>(h));
  EXPECT_EQ(h, 0xfaceea412c9c2552ull);
}

TEST(Procedural, TriangleCountFollowsParams) {
  for (int blocks : {1, 2, 5, 8})
    for (int seg : {4, 5, 16, 33}) {
      CityParams p;
      p.blocks = blocks;
      p.sphere_segments = seg;
      p.lights = 1 + blocks % 15;
      Scene s;
      make_city(p, s);
      SCOPED_TRACE("blocks " + std::to_string(blocks) + " segments " + std::to_string(seg));
      EXPECT_EQ(s.triangles.size(), expected_triangles(p));
      EXPECT_EQ(city_triangles(p), expected_triangles(p));
      EXPECT_EQ(s.lights.size(), static_cast<size_t>(p.lights));
      // Everything inside the city's footprint, on or above the ground.
      const float w = 10.f * blocks + 3.f;
      const AABB b = s.bounds();
      EXPECT_GE(b.lo.x, 0.f);
      EXPECT_GE(b.lo.y, 0.f);
      EXPECT_GE(b.lo.z, 0.f);
      EXPECT_LE(b.hi.x, w);
      EXPECT_LE(b.hi.z, w);
      for (const Light& l : s.lights) EXPECT_GT(l.position.y, b.hi.y);
    }
}

TEST(Procedural, SceneSetup) {
  Scene s;
  make_city(CityParams{}, s);
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 360);
  EXPECT_TRUE(s.has_camera);
  EXPECT_NEAR(glm::length(s.camera.dir), 1.f, 1e-6f);
  EXPECT_LT(s.camera.dir.y, 0.f);  // looking down at the city
  bool mirror = false;
  for (const Material& m : s.materials) mirror |= m.reflectance == 0.5f;
  EXPECT_TRUE(mirror);
  for (const Triangle& t : s.triangles) ASSERT_LT(t.material, s.materials.size());
}

TEST(Procedural, ParamsAreValidated) {
  auto bad = [](std::function<void(CityParams&)> edit) {
    CityParams p;
    edit(p);
    Scene s;
    return input_error([&] { make_city(p, s); });
  };
  EXPECT_NE(bad([](CityParams& p) { p.blocks = 0; }).find("blocks"), std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.blocks = kMaxCityBlocks + 1; }).find("blocks"),
            std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.sphere_segments = 3; }).find("sphere_segments"),
            std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.sphere_segments = 257; }).find("sphere_segments"),
            std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.lights = 0; }).find("lights"), std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.lights = 16; }).find("lights"), std::string::npos);
}

// The scale knob: blocks grows the city as the documented formula says, up to the scale series'
// 4 M triangles (configs/scenes/city-*.yaml), and a big city is the same bits every time.
TEST(Procedural, BlocksScaleTheCityAsDocumented) {
  const std::vector<std::pair<int, uint64_t>> series = {
      {8, 9'602}, {28, 101'922}, {90, 1'008'362}, {181, 4'037'500}};  // procedural.h's examples
  for (const auto& [blocks, triangles] : series) {
    CityParams p;
    p.blocks = blocks;
    EXPECT_EQ(city_triangles(p), triangles) << "blocks " << blocks;
    EXPECT_EQ(city_triangles(p), expected_triangles(p)) << "blocks " << blocks;
  }
  CityParams p;
  p.blocks = 90;
  Scene a, b;
  make_city(p, a);
  make_city(p, b);
  EXPECT_EQ(a.triangles.size(), 1'008'362u);
  EXPECT_TRUE(same_triangles(a.triangles, b.triangles));
  // The camera and the lights follow the city's extent: all of it stays below the lights.
  const AABB box = a.bounds();
  EXPECT_LE(box.hi.x, 10.f * 90 + 3.f);
  for (const Light& l : a.lights) EXPECT_GT(l.position.y, box.hi.y);
  p.seed = 7;
  Scene c;
  make_city(p, c);
  EXPECT_EQ(c.triangles.size(), a.triangles.size());
  EXPECT_FALSE(same_triangles(a.triangles, c.triangles));
}

TEST(Procedural, TooManyTrianglesIsAnErrorBeforeAnyIsMade) {
  CityParams p;
  p.blocks = kMaxCityBlocks;  // in range, but with 16-segment spheres about 128 M triangles
  ASSERT_GT(city_triangles(p), kMaxCityTriangles);
  Scene s;
  const std::string msg = input_error([&] { make_city(p, s); });
  EXPECT_NE(msg.find("blocks"), std::string::npos) << msg;
  EXPECT_NE(msg.find(std::to_string(kMaxCityTriangles)), std::string::npos) << msg;
  EXPECT_TRUE(s.triangles.empty());
  p.sphere_segments = 4;  // the same blocks with the smallest spheres fit
  EXPECT_LE(city_triangles(p), kMaxCityTriangles);
}

}  // namespace
}  // namespace rtsim
