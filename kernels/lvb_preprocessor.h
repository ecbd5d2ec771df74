// The LVB preprocessor's insides, shared by its two files and by nothing else (kernels/lvb.h is
// the interface): kernels/lvb_preprocessor.cpp decides one (leaf, light) bit, kernels/lvb.cpp runs
// it over every leaf on threads. The class is declared here, not in either file, because both
// use it: the driver builds one and shares it between its threads.
#pragma once

#include "kernels/light_region.h"
#include "kernels/lvb.h"
#include "kernels/moved_boxes.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace rtsim {
namespace lvb_detail {

struct TriangleInfo {
  DVec3 v[3];
  DVec3 n;   // unit normal
  double c;  // n . v0
};

struct Counters {
  uint64_t nodes_visited = 0, region_tests = 0, pair_tests = 0;
};

// An area light as the search sees it: its corners, and how far a sample point computed in float
// (corner + u edge1 + v edge2) may stray from the exact parallelogram.
struct AreaLight {
  LightPolygon polygon;
  double error = 0;
};

struct LazyCounters {
  uint64_t pairs = 0, dirty_pairs = 0, dirty_tests = 0;
  Counters work;
};

// What the preprocessor reads of a kd-tree or a BVH: its leaves (first, count, box) over its
// triangle list, its bounds, and the tree for the walk (one of the two).
// - kd-tree: a leaf's box is its cell. Cells tile the scene and may cut triangles: a leaf holds
//   the parts of its triangles inside its cell, and accepts hits a little outside it.
// - BVH: a leaf's box is the union of its triangles' boxes. Boxes may overlap; every triangle is
//   whole in exactly one leaf, and a hit anywhere on it is credited to that leaf.
struct LeafView {
  struct Leaf {
    uint32_t first = 0, count = 0;
    AABB box;
  };
  AABB bounds;
  std::vector<Leaf> leaves;
  const std::vector<uint32_t>* prims = nullptr;
  const KdTree* kd = nullptr;
  const Bvh* bvh = nullptr;
};

// One leaf's word at a time, any number of leaves concurrently: after construction (and
// set_change) nothing in it changes.
class Preprocessor {
 public:
  Preprocessor(const Scene& scene, const LeafView& view, const LvbParams& p);

  // With `lazy`, also counts which bits a lazy rebuild would redo and that work.
  uint32_t word(uint32_t leaf, Counters& c, LazyCounters* lazy) const {
    uint32_t w = 0;
    for (size_t i = 0; i < scene_.lights.size(); ++i) {
      const Counters before = c;
      bool dirty = false;
      if (bit(leaf, i, c, lazy ? &dirty : nullptr, lazy)) w |= 1u << i;
      if (!lazy) continue;
      ++lazy->pairs;
      if (!dirty) continue;
      ++lazy->dirty_pairs;
      lazy->work.nodes_visited += c.nodes_visited - before.nodes_visited;
      lazy->work.region_tests += c.region_tests - before.region_tests;
      lazy->work.pair_tests += c.pair_tests - before.pair_tests;
    }
    return w;
  }

  void set_change(const LvbChange* change) {
    change_ = change;
    if (change) moved_ = std::make_unique<MovedBoxes>(change->moved);
  }

  const DBox& box(uint32_t leaf) const {
    return p_.bounds == LvbBounds::kCell ? cell_[leaf] : geom_[leaf];
  }

 private:
  struct Origin;  // what the exact mode knows about one of b's own triangles, for one light
  struct Query;   // one (leaf, light) decision

  void add_leaf_references(size_t l, double slack);
  bool bit(uint32_t b, size_t light_index, Counters& c, bool* dirty, LazyCounters* lazy) const;
  // The search under bit, defined in kernels/lvb_preprocessor.cpp and called only there. GCC
  // folded the walks and prepare_origins (each called once) into their caller while the class
  // lived in one file's anonymous namespace; with external linkage it keeps them apart, so they
  // are always inlined, as they were: no call per (leaf, light) or per origin list.
  inline bool candidate_blocks(Query& q, uint32_t l, Counters& c) const;
  [[gnu::always_inline]] inline bool walk_kdtree(Query& q, Counters& c) const;
  [[gnu::always_inline]] inline bool walk_bvh(Query& q, Counters& c) const;
  [[gnu::always_inline]] inline void prepare_origins(Query& q) const;
  inline bool pair_blocks(Query& q, uint32_t l, Counters& c) const;

  const Scene& scene_;
  const LeafView& view_;
  const std::vector<uint32_t>& prims_;
  LvbParams p_;
  const LvbChange* change_ = nullptr;
  std::unique_ptr<MovedBoxes> moved_;
  bool exact_;
  double tolerance_ = 0, point_error_ = 0, cell_growth_ = 0;
  bool halfspace_ok_ = false;
  std::vector<std::optional<AreaLight>> areas_;  // per light; empty for a point light
  std::vector<TriangleInfo> tris_;
  std::vector<DBox> cell_, geom_;
  std::vector<DBox> in_cell_;        // per reference: the triangle clipped to its leaf's cell
  std::vector<DBox> origin_;         // per reference: where its shadow rays may start (exact mode)
  std::vector<DBox> origin_region_;  // per leaf: union of its references' origin boxes
};

}  // namespace lvb_detail
}  // namespace rtsim
