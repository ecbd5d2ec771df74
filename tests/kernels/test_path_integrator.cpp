// The reference tracer's path integrator (TracerOptions::integrator = kPath, issue 52): the same
// bytes on any thread count and twice in a row, counts that add up bounce by bounce, an estimate
// that converges, and bad settings refused. Cosine-weighted directions are unit vectors in the
// normal's hemisphere, distributed as cos(theta) / pi.
#include "common/error.h"
#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "kernels/path_sampling.h"
#include "kernels/reference_tracer.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>

namespace rtsim {
namespace {

struct City {
  City() {
    const SceneSetup setup =
        load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
    scene = setup.scene;
    tree = build_kdtree(scene.triangles, setup.kdtree);
    image = std::make_unique<MemoryImage>(scene, tree);
  }
  TraceResult trace(int spp, int threads, int max_depth = 3) const {
    TracerOptions o;
    o.width = 64;
    o.height = 36;
    o.integrator = Integrator::kPath;
    o.path.spp = spp;
    o.path.max_depth = max_depth;
    o.threads = threads;
    return ReferenceTracer(*image).trace_frame(scene.camera, o);
  }
  Scene scene;
  KdTree tree;
  std::unique_ptr<MemoryImage> image;
};

double mean(const std::vector<float>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

TEST(PathIntegrator, TheSameBytesOnAnyThreadCountAndTwiceInARow) {
  const City city;
  const TraceResult one = city.trace(4, 1), two = city.trace(4, 2), again = city.trace(4, 2);
  EXPECT_EQ(one.rgb, two.rgb);
  EXPECT_EQ(one.radiance, two.radiance);  // float for float
  EXPECT_EQ(two.radiance, again.radiance);
  ASSERT_EQ(one.stats.bounces.size(), 4u);
  for (size_t b = 0; b < 4; ++b) EXPECT_EQ(one.stats.bounces[b].rays, two.stats.bounces[b].rays);
}

// Bounce 0 is every sample's primary ray; a bounce's rays come from the hits before it (fewer when
// the roulette ends paths); every hit decides a shadow ray per light sample.
TEST(PathIntegrator, TheBouncesCountsAddUp) {
  const City city;
  const TraceResult r = city.trace(2, 2);
  const std::vector<BounceCounters>& b = r.stats.bounces;
  uint32_t samples = 0;
  for (const Light& l : city.scene.lights) samples += l.samples;
  EXPECT_EQ(b[0].rays, uint64_t(64 * 36 * 2));
  EXPECT_EQ(r.stats.primary_rays, b[0].rays);
  EXPECT_GT(b[3].rays, 0u);
  for (size_t k = 0; k < b.size(); ++k) {
    EXPECT_LE(b[k].hits, b[k].rays);
    EXPECT_EQ(b[k].shadow_rays, b[k].hits * samples) << "bounce " << k;
    EXPECT_LE(b[k].occluded, b[k].shadow_rays);
    if (k > 0) {
      EXPECT_LE(b[k].rays, b[k - 1].hits) << "bounce " << k;
    }
  }
  EXPECT_EQ(b[1].rays, b[0].hits);  // no roulette before bounce 2 (roulette_depth 2)
  EXPECT_LT(b[3].rays, b[2].hits);  // the roulette ends some paths
}

// The mean radiance of 16 and 64 paths a pixel agree within 1%; one path a pixel is noisier.
TEST(PathIntegrator, TheEstimateConverges) {
  const City city;
  const double m16 = mean(city.trace(16, 2).radiance), m64 = mean(city.trace(64, 2).radiance);
  EXPECT_NEAR(m16, m64, 0.01 * m64);
  // With no bounce the frame is darker: the bounces add light.
  EXPECT_LT(mean(city.trace(16, 2, 0).radiance), m64);
}

TEST(PathIntegrator, BadSettingsAreRefused) {
  const City city;
  TracerOptions o;
  o.width = 8;
  o.height = 8;
  o.integrator = Integrator::kPath;
  o.path.spp = 0;
  EXPECT_THROW(ReferenceTracer(*city.image).trace_frame(city.scene.camera, o), InputError);
  o.path.spp = 1;
  o.path.max_depth = -1;
  EXPECT_THROW(ReferenceTracer(*city.image).trace_frame(city.scene.camera, o), InputError);
}

TEST(PathSampling, CosineDirectionsLieInTheHemisphereWithACosineDensity) {
  const Vec3 normals[] = {Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(0.3f, -0.8f, 0.2f))};
  for (const Vec3& n : normals) {
    double mean_cos = 0;
    const int kN = 20000;
    for (int i = 0; i < kN; ++i) {
      const Vec3 d = cosine_direction(n, path_random(uint32_t(i), 0, 0, kPathU1),
                                      path_random(uint32_t(i), 0, 0, kPathU2));
      ASSERT_NEAR(glm::length(d), 1.f, 1e-5f);
      ASSERT_GE(glm::dot(d, n), -1e-6f);
      mean_cos += glm::dot(d, n);
    }
    // E[cos theta] under cos(theta) / pi is 2/3.
    EXPECT_NEAR(mean_cos / kN, 2.0 / 3.0, 0.01);
  }
}

TEST(PathSampling, NumbersDependOnEveryPartOfTheirCounter) {
  const float base = path_random(7, 3, 2, kPathU1);
  EXPECT_NE(base, path_random(8, 3, 2, kPathU1));
  EXPECT_NE(base, path_random(7, 4, 2, kPathU1));
  EXPECT_NE(base, path_random(7, 3, 1, kPathU1));
  EXPECT_NE(base, path_random(7, 3, 2, kPathU2));
  EXPECT_EQ(base, path_random(7, 3, 2, kPathU1));
}

}  // namespace
}  // namespace rtsim
