// The area lights' sample pattern: deterministic, one sample per stratum, and a point light's one
// sample is the point.
#include "kernels/light_samples.h"

#include <gtest/gtest.h>

#include <set>

namespace rtsim {
namespace {

TEST(LightSamples, GridIsTheSquarestFactorisation) {
  const std::pair<uint32_t, SampleGrid> cases[] = {{1, {1, 1}},  {2, {1, 2}},     {4, {2, 2}},
                                                   {6, {2, 3}},  {7, {1, 7}},     {16, {4, 4}},
                                                   {64, {8, 8}}, {256, {16, 16}}, {200, {10, 20}}};
  for (const auto& [n, g] : cases) {
    const SampleGrid got = sample_grid(n);
    EXPECT_EQ(got.rows, g.rows) << n;
    EXPECT_EQ(got.cols, g.cols) << n;
  }
}

TEST(LightSamples, OneSamplePerStratumAndDeterministic) {
  for (uint32_t n : {1u, 2u, 3u, 4u, 7u, 16u, 64u, 200u, 256u}) {
    const SampleGrid g = sample_grid(n);
    for (uint32_t pixel : {0u, 1u, 123457u}) {
      std::set<std::pair<int, int>> cells;
      for (uint32_t k = 0; k < n; ++k) {
        const SampleUv s = light_sample_uv(pixel, 0, 2, k, n);
        ASSERT_GE(s.u, 0.f);
        ASSERT_LE(s.u, 1.f);
        ASSERT_GE(s.v, 0.f);
        ASSERT_LE(s.v, 1.f);
        // The cell the sample lies in (a sample on a cell's upper edge belongs to the cell below
        // it).
        const int cu = std::min(int(s.u * float(g.cols)), int(g.cols) - 1);
        const int cv = std::min(int(s.v * float(g.rows)), int(g.rows) - 1);
        cells.insert({cu, cv});
        const SampleUv again = light_sample_uv(pixel, 0, 2, k, n);
        EXPECT_EQ(s.u, again.u);
        EXPECT_EQ(s.v, again.v);
      }
      EXPECT_EQ(cells.size(), size_t(n)) << "n " << n << " pixel " << pixel;
    }
  }
}

TEST(LightSamples, JitterDependsOnPixelBounceAndLight) {
  const SampleUv a = light_sample_uv(10, 0, 0, 3, 16);
  for (const SampleUv& b : {light_sample_uv(11, 0, 0, 3, 16), light_sample_uv(10, 1, 0, 3, 16),
                            light_sample_uv(10, 0, 1, 3, 16)}) {
    EXPECT_TRUE(a.u != b.u || a.v != b.v);
    // Same stratum whatever the scramble.
    EXPECT_EQ(int(a.u * 4), int(b.u * 4));
    EXPECT_EQ(int(a.v * 4), int(b.v * 4));
  }
}

TEST(LightSamples, PointLightSampleIsThePoint) {
  image::LightRecord l;
  l.position = Vec3(1, 2, 3);
  EXPECT_EQ(light_sample_point(l, 5, 0, 0, 0), l.position);
  l.area = true;
  l.samples = 4;
  l.edge1 = Vec3(2, 0, 0);
  l.edge2 = Vec3(0, 0, 2);
  for (uint32_t k = 0; k < 4; ++k) {
    const Vec3 p = light_sample_point(l, 5, 0, 0, k);
    EXPECT_EQ(p.y, 2.f);
    EXPECT_GE(p.x, 1.f);
    EXPECT_LE(p.x, 3.f);
    EXPECT_GE(p.z, 3.f);
    EXPECT_LE(p.z, 5.f);
  }
  // One-sided: emits towards edge1 x edge2 = (0, -4, 0), i.e. downwards.
  l.two_sided = false;
  EXPECT_TRUE(light_faces(l, Vec3(2, 2, 4), Vec3(2, 0, 4)));
  EXPECT_FALSE(light_faces(l, Vec3(2, 2, 4), Vec3(2, 5, 4)));
}

}  // namespace
}  // namespace rtsim
