// compute_lvb and lvb_lazy_stats: the preprocessor (kernels/lvb_preprocessor.h) over every
// non-empty leaf of a kd-tree or a BVH, seen alike through a LeafView, and its counters summed.
// Threads share one preprocessor and take interleaved blocks of leaves: a word depends on its
// leaf alone, so the words and counters do not depend on the thread count.
#include "kernels/lvb.h"

#include "kernels/lvb_preprocessor.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

namespace rtsim {

namespace {

using lvb_detail::Counters;
using lvb_detail::LazyCounters;
using lvb_detail::LeafView;
using lvb_detail::Preprocessor;

// The leaves and triangle list of a kd-tree or a BVH; `box` reads a leaf's box.
template <class Tree, class LeafBox>
LeafView leaves_of(const Tree& tree, LeafBox box) {
  LeafView v;
  v.bounds = tree.bounds;
  v.leaves.reserve(tree.leaves.size());
  for (const auto& l : tree.leaves) v.leaves.push_back({l.first, l.count, box(l)});
  v.prims = &tree.prims;
  return v;
}

LeafView view_of(const KdTree& tree) {
  LeafView v = leaves_of(tree, [](const KdLeaf& l) { return l.cell; });
  v.kd = &tree;
  return v;
}

LeafView view_of(const Bvh& bvh) {
  LeafView v = leaves_of(bvh, [](const BvhLeaf& l) { return l.box; });
  v.bvh = &bvh;
  return v;
}

LvbResult compute(const Scene& scene, const LeafView& view, const LvbParams& params,
                  const LvbChange* change, LvbLazyStats* lazy_stats) {
  const auto t0 = std::chrono::steady_clock::now();
  LvbResult out;
  const uint32_t all = scene.lights.size() >= 32 ? ~0u : (1u << scene.lights.size()) - 1u;
  out.words.assign(view.leaves.size(), all);
  Preprocessor pre(scene, view, params);
  pre.set_change(change);
  const int threads = std::max(1, params.threads);
  std::vector<Counters> counters(threads);
  std::vector<LazyCounters> lazy(threads);
  auto body = [&](int w) {
    // Interleaved blocks of leaves: every leaf's word is computed independently of the others.
    constexpr uint32_t kBlock = 64;
    const uint32_t n = uint32_t(view.leaves.size());
    for (uint32_t start = w * kBlock; start < n; start += threads * kBlock)
      for (uint32_t l = start; l < std::min<uint32_t>(start + kBlock, n); ++l)
        if (view.leaves[l].count > 0)
          out.words[l] = pre.word(l, counters[w], change ? &lazy[w] : nullptr);
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(body, w);
  body(0);
  for (auto& t : pool) t.join();

  out.stats.per_light.assign(scene.lights.size(), {});
  for (size_t l = 0; l < view.leaves.size(); ++l) {
    if (view.leaves[l].count == 0) continue;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
      ++out.stats.per_light[i].nonempty_leaves;
      if (!((out.words[l] >> i) & 1u)) ++out.stats.per_light[i].culled_leaves;
    }
  }
  if (change) {
    LvbLazyStats& z = *lazy_stats;
    z.moved_triangles = change->moved.size();
    z.moved_lights =
        uint64_t(std::count(change->light_moved.begin(), change->light_moved.end(), 1));
    for (const LazyCounters& c : lazy) {
      z.pairs += c.pairs;
      z.dirty_pairs += c.dirty_pairs;
      z.dirty_tests += c.dirty_tests;
      z.nodes_visited += c.work.nodes_visited;
      z.region_tests += c.work.region_tests;
      z.pair_tests += c.work.pair_tests;
    }
  }
  for (const Counters& c : counters) {
    out.stats.nodes_visited += c.nodes_visited;
    out.stats.region_tests += c.region_tests;
    out.stats.pair_tests += c.pair_tests;
  }
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

LvbLazyStats lazy_stats(const Scene& scene, const LeafView& view, const LvbParams& params,
                        const LvbChange& change) {
  LvbLazyStats z;
  compute(scene, view, params, &change, &z);
  return z;
}

}  // namespace

LvbResult compute_lvb(const Scene& scene, const KdTree& tree, const LvbParams& params) {
  return compute(scene, view_of(tree), params, nullptr, nullptr);
}

LvbLazyStats lvb_lazy_stats(const Scene& scene, const KdTree& tree, const LvbParams& params,
                            const LvbChange& change) {
  return lazy_stats(scene, view_of(tree), params, change);
}

LvbResult compute_lvb(const Scene& scene, const Bvh& bvh, const LvbParams& params) {
  return compute(scene, view_of(bvh), params, nullptr, nullptr);
}

LvbLazyStats lvb_lazy_stats(const Scene& scene, const Bvh& bvh, const LvbParams& params,
                            const LvbChange& change) {
  return lazy_stats(scene, view_of(bvh), params, change);
}

}  // namespace rtsim
