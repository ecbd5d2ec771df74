// The boxes of the triangles that moved since the last frame (an animation's change), in a
// bounding-volume hierarchy, so the lazy LVB rebuild's "may this pair have changed?" test costs a
// walk, not a scan (kernels/lvb_preprocessor.cpp).
#pragma once

#include "kernels/light_region.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rtsim {

// A bounding-volume hierarchy over the moved boxes, so a dirty test costs a walk, not a scan.
class MovedBoxes {
 public:
  explicit MovedBoxes(const std::vector<AABB>& boxes) {
    for (const AABB& b : boxes)
      if (!b.empty()) boxes_.push_back(DBox(b));
    if (!boxes_.empty()) build(0, uint32_t(boxes_.size()));
  }

  // Does `hit` accept a box of the hierarchy (a node's bounds, or a moved box)?
  template <class Hit>
  bool any(Hit hit) const {
    if (nodes_.empty()) return false;
    uint32_t stack[64];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
      const Node& n = nodes_[stack[--sp]];
      if (!hit(n.box)) continue;
      if (n.count > 0) {
        for (uint32_t k = n.first; k < n.first + n.count; ++k)
          if (hit(boxes_[k])) return true;
      } else {
        stack[sp++] = n.first;  // left child
        stack[sp++] = n.right;
      }
    }
    return false;
  }

 private:
  struct Node {
    DBox box;
    uint32_t first = 0, count = 0, right = 0;  // leaf: boxes [first, first+count); inner: children
  };
  static constexpr uint32_t kLeafSize = 4;

  uint32_t build(uint32_t lo, uint32_t hi) {
    const uint32_t id = uint32_t(nodes_.size());
    nodes_.emplace_back();
    DBox box = boxes_[lo];
    for (uint32_t k = lo + 1; k < hi; ++k) {
      box.lo = glm::min(box.lo, boxes_[k].lo);
      box.hi = glm::max(box.hi, boxes_[k].hi);
    }
    nodes_[id].box = box;
    if (hi - lo <= kLeafSize) {
      nodes_[id].first = lo;
      nodes_[id].count = hi - lo;
      return id;
    }
    // Median split on the longest axis (depth about log2(n / 4), within the walk's stack).
    const DVec3 ext = box.hi - box.lo;
    const int a = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const uint32_t mid = lo + (hi - lo) / 2;
    std::nth_element(
        boxes_.begin() + lo, boxes_.begin() + mid, boxes_.begin() + hi,
        [a](const DBox& x, const DBox& y) { return x.lo[a] + x.hi[a] < y.lo[a] + y.hi[a]; });
    nodes_[id].first = build(lo, mid);
    nodes_[id].right = build(mid, hi);
    return id;
  }

  std::vector<DBox> boxes_;
  std::vector<Node> nodes_;
};

}  // namespace rtsim
