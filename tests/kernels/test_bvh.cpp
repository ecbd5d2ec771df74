// BVH builder (Embree's rtcBuildBVH, renumbered by us): structure, exact boxes, leaf sizes,
// child order, determinism, and a walk of the tree against brute force.
#include "config_loader/scene_file.h"
#include "kernels/bvh.h"
#include "kernels/clip.h"
#include "kernels/ray.h"
#include "kernels/traversal.h"
#include "tests/kernels/kdtree_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

namespace rtsim {
namespace {

using kdtree_test::random_soup;
using kdtree_test::tri;

Scene load_city() {
  return load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string(),
                         SceneFileOptions{test::shared_scenes().string(), {}})
      .scene;
}

BvhConfig with_branching(uint32_t branching) {
  BvhConfig c;
  c.branching = branching;
  return c;
}

// Walks the tree depth-first as the builder numbers it and checks every rule of the header.
class Checker {
 public:
  Checker(const std::vector<Triangle>& tris, const Bvh& bvh, const BvhConfig& config)
      : tris_(tris), bvh_(bvh), config_(config), seen_(tris.size(), 0) {}

  void run() {
    ASSERT_FALSE(bvh_.nodes.empty());
    EXPECT_EQ(bvh_.branching, config_.branching);
    const BvhNode& root = bvh_.nodes[0];
    uint64_t expected = 0;
    for (uint32_t i = 0; i < tris_.size(); ++i) expected += !triangle_is_degenerate(tris_[i]);
    if (expected == 0) {
      EXPECT_EQ(root.child_count, 0u);
    }
    if (root.child_count == 1) {
      EXPECT_TRUE(root.children[0].is_leaf()) << "a one-child root holds the whole scene's leaf";
      EXPECT_LE(expected, config_.max_leaf_size);
    }
    const AABB all = node(0, 0);
    EXPECT_EQ(next_node_, bvh_.nodes.size()) << "every node reached once, in pre-order";
    EXPECT_EQ(next_prim_, bvh_.prims.size());
    EXPECT_EQ(bvh_.prims.size(), expected);
    EXPECT_EQ(bvh_.stats.prims, expected);
    EXPECT_EQ(bvh_.stats.left_out, tris_.size() - expected);
    EXPECT_EQ(bvh_.stats.nodes, bvh_.nodes.size());
    EXPECT_EQ(bvh_.stats.leaves, leaves_);
    EXPECT_EQ(bvh_.leaves.size(), leaves_);
    // Leaves are numbered node by node, a node's leaves in slot order.
    uint32_t next_leaf = 0;
    for (const BvhNode& nd : bvh_.nodes)
      for (uint32_t i = 0; i < nd.child_count; ++i)
        if (nd.children[i].is_leaf()) {
          EXPECT_EQ(nd.children[i].index, next_leaf++);
        }
    EXPECT_LE(bvh_.stats.max_depth, config_.max_depth);
    expect_same_box(bvh_.bounds, all, "scene bounds");
    for (uint32_t i = 0; i < tris_.size(); ++i)
      EXPECT_EQ(seen_[i], triangle_is_degenerate(tris_[i]) ? 0 : 1) << "triangle " << i;
  }

 private:
  void expect_same_box(const AABB& a, const AABB& b, const char* what) {
    EXPECT_TRUE(a.lo == b.lo && a.hi == b.hi) << what << " is not the exact union";
  }

  // Checks node `n` (expected to be the next in pre-order) and returns its triangles' union.
  AABB node(uint32_t n, uint32_t depth) {
    EXPECT_EQ(n, next_node_++) << "nodes are numbered in pre-order";
    const BvhNode& nd = bvh_.nodes[n];
    const bool leaf_root = n == 0 && nd.child_count <= 1;
    if (!leaf_root) {
      EXPECT_GE(nd.child_count, 2u) << "node " << n;
      EXPECT_LE(nd.child_count, config_.branching) << "node " << n;
    }
    for (uint32_t i = nd.child_count; i < kBvhMaxBranching; ++i) {
      EXPECT_EQ(nd.children[i].count, 0u);
      EXPECT_EQ(nd.children[i].index, 0u);
    }
    AABB box;
    uint64_t total = 0, previous = UINT64_MAX;
    for (uint32_t i = 0; i < nd.child_count; ++i) {
      const BvhChild& c = nd.children[i];
      const uint64_t before = next_prim_;
      const AABB sub = c.is_leaf() ? leaf(c, depth + 1) : node(c.index, depth + 1);
      expect_same_box(c.box, sub, "a child box");
      box.extend(sub);
      const uint64_t count = next_prim_ - before;
      // Embree sorts a node's children by triangle count, largest first (docs/bvh.md); the
      // size-balanced subtrees near the depth limit are not sorted, and no test scene gets there.
      EXPECT_LE(count, previous) << "node " << n << " child " << i;
      previous = count;
      total += count;
    }
    if (!leaf_root) {
      EXPECT_GT(total, config_.min_leaf_size) << "node " << n << " could be a leaf";
    }
    return box;
  }

  AABB leaf(const BvhChild& c, uint32_t depth) {
    ++leaves_;
    if (c.index >= bvh_.leaves.size()) {
      ADD_FAILURE() << "leaf " << c.index << " out of range";
      return {};
    }
    const BvhLeaf& l = bvh_.leaves[c.index];
    EXPECT_EQ(l.count, c.count);
    EXPECT_EQ(l.first, next_prim_) << "leaf lists in walk order";
    EXPECT_GE(c.count, 1u);
    EXPECT_LE(c.count, config_.max_leaf_size);
    EXPECT_LE(depth, bvh_.stats.max_depth);
    AABB box;
    for (uint32_t i = l.first; i < l.first + l.count && i < bvh_.prims.size(); ++i) {
      const uint32_t p = bvh_.prims[i];
      if (i > l.first) {
        EXPECT_LT(bvh_.prims[i - 1], p) << "leaf triangles in index order";
      }
      if (p >= tris_.size()) {
        ADD_FAILURE() << "triangle index " << p << " out of range";
        continue;
      }
      ++seen_[p];
      box.extend(tris_[p].bounds());
    }
    next_prim_ += c.count;
    return box;
  }

  const std::vector<Triangle>& tris_;
  const Bvh& bvh_;
  const BvhConfig& config_;
  std::vector<int> seen_;
  uint64_t next_node_ = 0, next_prim_ = 0, leaves_ = 0;
};

void check_bvh(const std::vector<Triangle>& tris, const BvhConfig& config) {
  const Bvh bvh = build_bvh(tris, config);
  Checker(tris, bvh, config).run();
}

// ---------------------------------------------------------------------------------------------
// Small scenes with a known answer

TEST(Bvh, EmptyAndDegenerateScenesGiveAChildlessRoot) {
  const Triangle flat = tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2});  // collinear: no surface
  for (const auto& tris : {std::vector<Triangle>{}, std::vector<Triangle>{flat, flat}}) {
    const Bvh b = build_bvh(tris);
    ASSERT_EQ(b.nodes.size(), 1u);
    EXPECT_EQ(b.nodes[0].child_count, 0u);
    EXPECT_TRUE(b.prims.empty());
    EXPECT_TRUE(b.bounds.empty());
    EXPECT_EQ(b.stats.left_out, tris.size());
    EXPECT_EQ(b.stats.leaves, 0u);
    EXPECT_EQ(b.stats.sah_cost, 0.0);
  }
}

TEST(Bvh, OneTriangleIsOneLeafUnderTheRoot) {
  const std::vector<Triangle> tris{tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f})};
  const Bvh b = build_bvh(tris);
  ASSERT_EQ(b.nodes.size(), 1u);
  ASSERT_EQ(b.nodes[0].child_count, 1u);
  const BvhChild& c = b.nodes[0].children[0];
  EXPECT_TRUE(c.is_leaf());
  EXPECT_EQ(c.index, 0u);
  EXPECT_EQ(c.count, 1u);
  EXPECT_EQ(c.box.lo, Vec3(0, 0, 0));
  EXPECT_EQ(c.box.hi, Vec3(1, 1, 0.5f));
  EXPECT_EQ(b.prims, std::vector<uint32_t>{0});
  EXPECT_EQ(b.stats.max_depth, 1u);
  Checker(tris, b, BvhConfig{}).run();
}

TEST(Bvh, TwoFarApartTrianglesGiveTwoLeaves) {
  // Splitting costs 1 x halfArea(both) + 1 x (halfArea(a) + halfArea(b)), a leaf 2 x
  // halfArea(both): far apart, the split wins. Equal counts keep the split's order: the lower
  // side first. Input in reverse order, so the leaves' order is the builder's, not the input's.
  const std::vector<Triangle> tris{tri({100, 0, 0}, {101, 0, 0}, {100, 1, 1}),
                                   tri({0, 0, 0}, {1, 0, 0}, {0, 1, 1})};
  for (uint32_t branching : {2u, 4u, 8u}) {
    const Bvh b = build_bvh(tris, with_branching(branching));
    ASSERT_EQ(b.nodes.size(), 1u);
    ASSERT_EQ(b.nodes[0].child_count, 2u);
    const BvhChild* c = b.nodes[0].children;
    EXPECT_TRUE(c[0].is_leaf() && c[1].is_leaf());
    EXPECT_EQ(c[0].count, 1u);
    EXPECT_EQ(c[1].count, 1u);
    EXPECT_EQ(b.prims, (std::vector<uint32_t>{1, 0}));
    EXPECT_EQ(c[0].box.lo, Vec3(0, 0, 0));
    EXPECT_EQ(c[0].box.hi, Vec3(1, 1, 1));
    EXPECT_EQ(c[1].box.lo, Vec3(100, 0, 0));
    EXPECT_EQ(c[1].box.hi, Vec3(101, 1, 1));
    // SAH cost relative to the scene box: the root (1) + both leaves' areas over the root's.
    const double root = b.bounds.surface_area(), leaf = c[0].box.surface_area();
    EXPECT_DOUBLE_EQ(b.stats.sah_cost, (root + 2 * leaf) / root);
  }
}

TEST(Bvh, MinLeafSizeKeepsSmallScenesInOneLeaf) {
  const auto tris = random_soup(6, 4);
  BvhConfig c;
  c.min_leaf_size = 8;
  c.max_leaf_size = 8;
  const Bvh b = build_bvh(tris, c);
  ASSERT_EQ(b.nodes.size(), 1u);
  ASSERT_EQ(b.nodes[0].child_count, 1u);
  EXPECT_EQ(b.nodes[0].children[0].count, 6u);
  EXPECT_EQ(b.prims, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  Checker(tris, b, c).run();
}

// ---------------------------------------------------------------------------------------------
// Bad configuration: one error naming the key

TEST(Bvh, BadConfigNamesTheKey) {
  struct Case {
    const char* key;
    void (*set)(BvhConfig&);
  };
  const Case cases[] = {
      {"bvh.branching", [](BvhConfig& c) { c.branching = 3; }},
      {"bvh.branching", [](BvhConfig& c) { c.branching = 16; }},
      {"bvh.max_leaf_size", [](BvhConfig& c) { c.max_leaf_size = 0; }},
      {"bvh.max_leaf_size", [](BvhConfig& c) { c.max_leaf_size = 33; }},
      {"bvh.min_leaf_size", [](BvhConfig& c) { c.min_leaf_size = 0; }},
      {"bvh.min_leaf_size", [](BvhConfig& c) { c.min_leaf_size = 9; }},
      {"bvh.traversal_cost", [](BvhConfig& c) { c.traversal_cost = 0.f; }},
      {"bvh.intersection_cost", [](BvhConfig& c) { c.intersection_cost = NAN; }},
      {"bvh.max_depth", [](BvhConfig& c) { c.max_depth = 65; }},
      {"bvh.build_threads", [](BvhConfig& c) { c.build_threads = 5000; }},
  };
  const auto tris = random_soup(10, 1);
  for (const Case& k : cases) {
    BvhConfig c;
    k.set(c);
    try {
      build_bvh(tris, c);
      ADD_FAILURE() << k.key << ": no error";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string(k.key) + ": expected ", 0), 0u) << e.what();
    }
  }
  BvhConfig ok;
  ok.branching = 8;
  ok.min_leaf_size = ok.max_leaf_size = 32;
  ok.max_depth = 64;
  EXPECT_NO_THROW(ok.validate());
}

// ---------------------------------------------------------------------------------------------
// Random scenes and the city

TEST(Bvh, RandomScenesForEveryBranching) {
  auto soup = random_soup(4000, 11);
  soup.push_back(tri({1, 1, 1}, {1, 1, 1}, {2, 2, 2}));  // degenerate: in no leaf
  const auto big = random_soup(2000, 12, 3.f);           // large, overlapping triangles
  for (uint32_t branching : {2u, 4u, 8u}) {
    SCOPED_TRACE(branching);
    check_bvh(soup, with_branching(branching));
    check_bvh(big, with_branching(branching));
    BvhConfig c = with_branching(branching);
    c.min_leaf_size = 2;
    c.max_leaf_size = 3;  // cwbvh8's limit
    c.intersection_cost = 2.f;
    check_bvh(soup, c);
  }
  check_bvh(kdtree_test::grid_mesh(40, 40, true), with_branching(4));  // one plane
  check_bvh(kdtree_test::box_city(60, 5), with_branching(8));          // shared planes
}

TEST(Bvh, CityForEveryBranching) {
  const Scene city = load_city();
  ASSERT_GT(city.triangles.size(), 1000u);
  for (uint32_t branching : {2u, 4u, 8u}) {
    SCOPED_TRACE(branching);
    check_bvh(city.triangles, with_branching(branching));
  }
}

// Identical triangles have no split: Embree's fallback halves them in index order.
TEST(Bvh, IdenticalTrianglesSplitBySize) {
  const std::vector<Triangle> same(100, tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  for (uint32_t branching : {2u, 8u}) check_bvh(same, with_branching(branching));
}

// ---------------------------------------------------------------------------------------------
// Determinism

TEST(Bvh, SameInputGivesTheSameBytes) {
  const Scene city = load_city();
  const auto soup = random_soup(20000, 21);  // above Embree's parallel thresholds
  for (uint32_t branching : {2u, 4u, 8u}) {
    SCOPED_TRACE(branching);
    for (const auto* tris : {&soup, &city.triangles}) {
      BvhConfig c = with_branching(branching);
      const std::vector<uint8_t> first = serialize_bvh(build_bvh(*tris, c));
      ASSERT_GT(first.size(), 100u);
      // Several times, then with more Embree threads (0 = all the machine has).
      for (uint32_t threads : {1u, 1u, 1u, 2u, 0u, 0u, 0u}) {
        c.build_threads = threads;
        EXPECT_TRUE(serialize_bvh(build_bvh(*tris, c)) == first) << "threads " << threads;
      }
    }
  }
}

// One line per tree: the city and a soup at every branching factor, built with `threads`.
std::string tree_hashes(uint32_t threads) {
  const std::vector<Triangle> scenes[] = {load_city().triangles, random_soup(20000, 22)};
  std::string out;
  for (const auto& tris : scenes)
    for (uint32_t branching : {2u, 4u, 8u}) {
      BvhConfig c = with_branching(branching);
      c.build_threads = threads;
      out += std::to_string(bvh_hash(build_bvh(tris, c))) + "\n";
    }
  return out;
}

// This test's executable runs it once more in a child process (new addresses, all threads),
// which writes its hashes to the file RTSIM_BVH_HASHES names.
TEST(Bvh, SameBytesInAnotherProcess) {
  if (const char* path = std::getenv("RTSIM_BVH_HASHES")) {
    std::ofstream(path) << tree_hashes(0);
    return;
  }
  const auto dir = test::temp_dir("bvh_hashes");
  const auto file = dir / "hashes.txt";
  const auto self = std::filesystem::read_symlink("/proc/self/exe");
  const test::RunResult r =
      test::run_command("RTSIM_BVH_HASHES=" + file.string() + " " + self.string() +
                        " --gtest_filter=Bvh.SameBytesInAnotherProcess");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string here = tree_hashes(1);
  EXPECT_EQ(std::count(here.begin(), here.end(), '\n'), 6);
  EXPECT_EQ(test::slurp(file), here);
  std::filesystem::remove_all(dir);
}

TEST(Bvh, HashSeesAnyChange) {
  const auto soup = random_soup(500, 3);
  const Bvh a = build_bvh(soup);
  EXPECT_EQ(bvh_hash(a), bvh_hash(build_bvh(soup)));
  Bvh b = a;
  b.nodes.back().children[0].box.hi.x = std::nextafter(b.nodes.back().children[0].box.hi.x, 1e9f);
  EXPECT_NE(bvh_hash(a), bvh_hash(b));
  EXPECT_NE(bvh_hash(a), bvh_hash(build_bvh(soup, with_branching(4))));
}

// ---------------------------------------------------------------------------------------------
// A walk of the tree against brute force: the boxes hold what they must for a tracer

struct TestHit {
  uint32_t tri = kNoHit;
  float t = 0;
  bool operator==(const TestHit& o) const { return tri == o.tri && (tri == kNoHit || t == o.t); }
};

// Offers triangle p to `best`: nearer wins, an equal t goes to the lower index (the tracer's rule).
bool offer(const std::vector<Triangle>& tris, uint32_t p, const Ray& ray, const RayShear& shear,
           TestHit& best) {
  Ray r = ray;
  if (best.tri != kNoHit) r.tmax = std::nextafter(best.t, INFINITY);
  float t;
  const Triangle& tr = tris[p];
  if (!intersect_triangle(r, shear, tr.v0, tr.v1, tr.v2, t)) return false;
  if (best.tri == kNoHit || t < best.t || (t == best.t && p < best.tri)) best = {p, t};
  return true;
}

// Any order of children will do; boxes beyond the best hit (with slack for ties) are skipped.
TestHit walk(const Bvh& bvh, const std::vector<Triangle>& tris, const Ray& ray, bool any_hit) {
  const Vec3 inv(1.f / ray.d.x, 1.f / ray.d.y, 1.f / ray.d.z);
  const RayShear shear(ray.d);
  TestHit best;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const BvhNode& n = bvh.nodes[stack.back()];
    stack.pop_back();
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const BvhChild& c = n.children[i];
      Ray r = ray;
      if (best.tri != kNoHit) r.tmax = std::min(ray.tmax, best.t * (1.f + 1e-5f) + 1e-6f);
      float t0, t1;
      if (!clip_ray_to_box(r, inv, c.box, t0, t1)) continue;
      if (!c.is_leaf()) {
        stack.push_back(c.index);
        continue;
      }
      const BvhLeaf& l = bvh.leaves[c.index];
      for (uint32_t k = l.first; k < l.first + l.count; ++k)
        if (offer(tris, bvh.prims[k], ray, shear, best) && any_hit) return best;
    }
  }
  return best;
}

TestHit brute(const std::vector<Triangle>& tris, const Ray& ray, bool any_hit) {
  const RayShear shear(ray.d);
  TestHit best;
  for (uint32_t i = 0; i < tris.size(); ++i)
    if (!triangle_is_degenerate(tris[i]) && offer(tris, i, ray, shear, best) && any_hit) break;
  return best;
}

// Closest-hit rays from anywhere in the box in random directions, and any-hit segments between
// two random points (as shadow rays are).
void check_walk(const std::vector<Triangle>& tris, int rays, uint32_t seed) {
  AABB box;
  for (const Triangle& t : tris) box.extend(t.bounds());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::normal_distribution<float> g(0.f, 1.f);
  auto point = [&] { return box.lo + Vec3(u(rng), u(rng), u(rng)) * box.extent(); };
  for (uint32_t branching : {2u, 4u, 8u}) {
    SCOPED_TRACE(branching);
    const Bvh bvh = build_bvh(tris, with_branching(branching));
    int hits = 0, occluded = 0, mismatches = 0;
    for (int i = 0; i < rays; ++i) {
      Ray ray;
      ray.o = point();
      ray.d = Vec3(g(rng), g(rng), g(rng));
      if (glm::length(ray.d) < 1e-3f) continue;
      const TestHit h = walk(bvh, tris, ray, false), b = brute(tris, ray, false);
      hits += b.tri != kNoHit;
      if (!(h == b) && ++mismatches <= 5)
        ADD_FAILURE() << "ray " << i << ": bvh " << h.tri << " t " << h.t << ", brute force "
                      << b.tri << " t " << b.t;
      Ray segment;
      segment.o = point();
      segment.d = point() - segment.o;
      segment.tmax = 1.f;
      const bool ho = walk(bvh, tris, segment, true).tri != kNoHit;
      const bool bo = brute(tris, segment, true).tri != kNoHit;
      occluded += bo;
      if (ho != bo && ++mismatches <= 5) ADD_FAILURE() << "segment " << i << ": bvh " << ho;
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(hits, rays / 10) << "too few hits for the test to mean much";
    EXPECT_GT(occluded, rays / 20);
    EXPECT_LT(occluded, rays) << "some segments must be free";
  }
}

TEST(Bvh, WalkEqualsBruteForceOnRandomScenes) {
  check_walk(random_soup(3000, 31), 2000, 1);
  check_walk(kdtree_test::box_city(60, 5), 2000, 2);
}

TEST(Bvh, WalkEqualsBruteForceOnTheCity) { check_walk(load_city().triangles, 1500, 3); }

}  // namespace
}  // namespace rtsim
