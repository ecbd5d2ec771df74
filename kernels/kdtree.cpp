// SAH kd-tree builder after Wald & Havran 2006, "On building fast kd-trees for ray tracing, and
// on doing that in O(N log N)".
//
// Each node keeps, per axis, the sorted list of its triangles' split events (start/end of the
// triangle's extent, or one planar event when the extent is flat). The best plane is found by
// one sweep over those lists; splitting partitions the lists in order and merges in the (few)
// events regenerated for triangles clipped to a child cell, so the events are sorted only once.
//
// Cells are closed: a triangle that touches a cell, even only on its boundary, is referenced by
// that cell's leaf (the contract the LVB preprocessor and the tracer's face-slack rely on). A
// plane exactly at an event position therefore puts everything touching it on both sides. The
// paper's choice of side for triangles lying in the plane is kept by also offering the planes
// just below and just above each event position: there, what begins (or ends) at the position
// lies on one side only. Straddling triangles are clipped to each child cell in double, with
// outward rounding ("perfect splits", kernels/clip.h).
#include "kernels/kdtree.h"

#include "kernels/clip.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>

namespace rtsim {

namespace {

enum EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// Floats mapped to unsigned integers of the same order (finite values, -0 folded into +0 first).
inline uint32_t order_key(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
inline float from_order_key(uint32_t k) {
  const uint32_t b = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// 8 bytes: position on the list's axis (as its order key), triangle index and event type, packed
// so that one integer comparison orders events by (position, triangle, type). That total order
// makes every list, and so the tree, deterministic.
struct Event {
  uint64_t key;
  Event() = default;
  Event(float pos, uint32_t tri, uint32_t type)
      : key(uint64_t(order_key(pos + 0.f)) << 32 | (tri << 2 | type)) {}  // + 0.f: -0 -> +0
  uint32_t pos_key() const { return uint32_t(key >> 32); }
  float pos() const { return from_order_key(pos_key()); }
  uint32_t tri() const { return uint32_t(key) >> 2; }
  uint32_t type() const { return uint32_t(key) & 3u; }
};
inline bool operator<(const Event& a, const Event& b) { return a.key < b.key; }

// A growable event array that, unlike std::vector, does not zero what it grows into: the split
// step sizes its outputs for the worst case and trims them afterwards.
class EventList {
 public:
  const Event* begin() const { return data_.get(); }
  const Event* end() const { return data_.get() + size_; }
  Event* data() { return data_.get(); }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const Event& operator[](size_t i) const { return data_[i]; }
  void clear() { size_ = 0; }
  // Room for n events in all, keeping the current ones.
  void reserve(size_t n) {
    if (n <= capacity_) return;
    const size_t cap = std::max(n, capacity_ + capacity_ / 2);
    std::unique_ptr<Event[]> d(new Event[cap]);
    std::copy(begin(), end(), d.get());
    data_ = std::move(d);
    capacity_ = cap;
  }
  void set_size(size_t n) { size_ = n; }
  void push_back(const Event& e) {
    if (size_ == capacity_) reserve(size_ + 1);
    data_[size_++] = e;
  }
  void sort() { std::sort(data_.get(), data_.get() + size_); }

 private:
  std::unique_ptr<Event[]> data_;
  size_t size_ = 0, capacity_ = 0;
};

using EventLists = std::array<EventList, 3>;

// The neighbouring floats of a finite x.
float float_below(float x) {
  if (x == 0.f) return -std::numeric_limits<float>::denorm_min();
  uint32_t b;
  std::memcpy(&b, &x, 4);
  b = x > 0.f ? b - 1 : b + 1;
  std::memcpy(&x, &b, 4);
  return x;
}
float float_above(float x) { return -float_below(-x); }

// How one triangle of the node being split goes to the children.
enum SideFlags : uint8_t {
  kKeepLeft = 1,   // its extent in the node already lies in the below cell: keep its events
  kKeepRight = 2,  // ... in the above cell
  kClipLeft = 4,   // it reaches into the below cell: clip it to that cell, new events
  kClipRight = 8,
};

struct SplitPlane {
  int axis = -1;
  float pos = 0;
  double cost = std::numeric_limits<double>::infinity();
};

double surface_area(const AABB& b) { return b.empty() ? 0.0 : double(b.surface_area()); }

// Pushes the events of a triangle whose (clipped) extent in a cell is b.
void add_events(EventLists& ev, uint32_t tri, const AABB& b) {
  for (int a = 0; a < 3; ++a) {
    if (b.lo[a] == b.hi[a]) {
      ev[a].push_back(Event(b.lo[a], tri, kPlanar));
    } else {
      ev[a].push_back(Event(b.lo[a], tri, kStart));
      ev[a].push_back(Event(b.hi[a], tri, kEnd));
    }
  }
}

class Builder {
 public:
  Builder(const std::vector<Triangle>& tris, const KdTreeParams& params, KdTree& tree)
      : tris_(tris), params_(params), tree_(tree) {}

  void run() {
    // Event codes and node records keep 30 bits for a triangle index or a count.
    if (tris_.size() >= (size_t(1) << 30))
      throw std::length_error("build_kdtree: more than 2^30 triangles");
    const uint32_t n_input = static_cast<uint32_t>(tris_.size());
    flags_.assign(n_input, 0);

    // Root events from every triangle with a surface; degenerate ones are left out entirely.
    EventLists& root = root_;
    for (auto& l : root) l.reserve(2 * size_t(n_input) + 1);
    AABB bounds;
    uint32_t n = 0;
    for (uint32_t i = 0; i < n_input; ++i) {
      if (triangle_is_degenerate(tris_[i])) continue;
      const AABB b = tris_[i].bounds();
      bounds.extend(b);
      add_events(root, i, b);
      ++n;
    }
    for (auto& l : root) l.sort();

    depth_limit_ = params_.max_depth > 0
                       ? params_.max_depth
                       : int(std::lround(8.0 + 1.3 * std::log2(double(std::max<uint32_t>(n, 1)))));
    levels_.resize(size_t(depth_limit_) + 2);
    tree_.bounds = bounds;
    root_sa_ = surface_area(bounds);
    if (!bounds.empty()) {
      const Vec3 m = glm::max(glm::abs(bounds.lo), glm::abs(bounds.hi));
      min_offset_ = std::max({m.x, m.y, m.z}) * 0x1p-30f;
    }

    tree_.nodes.reserve(4 * size_t(n) + 1);
    tree_.prims.reserve(2 * size_t(n));
    build(0, root, bounds, n);

    KdTreeStats& s = tree_.stats;
    s.nodes = tree_.nodes.size();
    s.leaves = tree_.leaves.size();
    s.inner_nodes = s.nodes - s.leaves;
    s.prim_refs = tree_.prims.size();
    const uint64_t full = s.leaves - s.empty_leaves;
    s.mean_prims_per_leaf = full ? double(s.prim_refs) / double(full) : 0.0;
    s.depth_limit = depth_limit_;
  }

 private:
  // Builds the subtree of a cell whose triangles are given by `ev` (n triangles).
  void build(int depth, EventLists& ev, const AABB& cell, uint32_t n) {
    const uint32_t index = static_cast<uint32_t>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    const double rel_area = root_sa_ > 0 ? surface_area(cell) / root_sa_ : 0.0;

    SplitPlane plane;
    if (n > 0 && depth < depth_limit_) {
      SplitPlane best, forced;
      const bool want_forced =
          params_.max_prims_per_leaf > 0 && n > uint32_t(params_.max_prims_per_leaf);
      find_plane(ev, cell, n, best, forced, want_forced);
      if (best.axis >= 0 && best.cost < double(params_.intersection_cost) * n)
        plane = best;
      else if (want_forced)
        plane = forced;  // axis stays -1 when no plane separates anything
    }
    if (plane.axis < 0) {
      make_leaf(index, ev, cell, n, depth, rel_area);
      return;
    }

    tree_.stats.sah_cost += params_.traversal_cost * rel_area;
    AABB below = cell, above = cell;
    below.hi[plane.axis] = plane.pos;
    above.lo[plane.axis] = plane.pos;
    Level& next = levels_[size_t(depth) + 1];
    uint32_t n_below = 0, n_above = 0;
    split_events(ev, plane, below, above, next.below, next.above, n_below, n_above);

    // The below child's lists live in levels_[depth + 1] until its subtree is done; only then
    // does the above child's subtree reuse the deeper levels.
    build(depth + 1, next.below, below, n_below);
    tree_.nodes[index] =
        KdNode::inner(plane.axis, plane.pos, static_cast<uint32_t>(tree_.nodes.size()));
    build(depth + 1, next.above, above, n_above);
  }

  // Planes just off p: at least one float, and at least min_offset_, away. A triangle ending
  // at p must be clearly apart from the cell beyond such a plane, more than the overlap test's
  // rounding can blur (one float next to 0 is a denormal).
  float offset_above(float p) const {
    const float q = p + min_offset_;
    return q > p ? q : float_above(p);
  }
  float offset_below(float p) const {
    const float q = p - min_offset_;
    return q < p ? q : float_below(p);
  }

  // One sweep per axis over the sorted events. At a candidate position p the below cell holds
  // every triangle starting at or before p (planar ones at p included) and the above cell every
  // triangle ending at or after p: both cells are closed.
  void find_plane(const EventLists& ev, const AABB& cell, uint32_t n, SplitPlane& best,
                  SplitPlane& forced, bool want_forced) const {
    const double kt = params_.traversal_cost, ki = params_.intersection_cost;
    const double bonus = 1.0 - double(params_.empty_bonus);
    const double ext[3] = {double(cell.hi.x) - cell.lo.x, double(cell.hi.y) - cell.lo.y,
                           double(cell.hi.z) - cell.lo.z};
    const double area = 2.0 * (ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0]);
    if (!(area > 0)) return;
    const double inv_area = 1.0 / area;

    for (int k = 0; k < 3; ++k) {
      const float lo = cell.lo[k], hi = cell.hi[k];
      if (!(lo < hi)) continue;
      const double eu = ext[(k + 1) % 3], ew = ext[(k + 2) % 3];
      const double cap = eu * ew, rim = eu + ew;  // child area = 2 * (cap + len * rim)
      auto consider = [&](float p, uint32_t nl, uint32_t nr) {
        if (!(p > lo && p < hi)) return;
        const double area_l = 2.0 * (cap + (double(p) - lo) * rim);
        const double area_r = 2.0 * (cap + (double(hi) - p) * rim);
        double cost = kt + ki * (area_l * nl + area_r * nr) * inv_area;
        if (nl == 0 || nr == 0) cost *= bonus;
        if (cost < best.cost) best = {k, p, cost};
        if (want_forced && nl < n && nr < n && cost < forced.cost) forced = {k, p, cost};
      };
      uint32_t before = 0, after = n;  // triangles starting before p; triangles not ended before p
      const EventList& list = ev[k];
      const size_t m = list.size();
      size_t i = 0;
      float prev = -std::numeric_limits<float>::infinity();
      while (i < m) {
        const uint32_t pk = list[i].pos_key();
        uint32_t count[3] = {0, 0, 0};
        do {
          ++count[list[i].type()];
          ++i;
        } while (i < m && list[i].pos_key() == pk);
        const float p = from_order_key(pk);
        // Triangles whose extent begins at p
        const uint32_t starting = count[kStart] + count[kPlanar];
        const uint32_t ending = count[kEnd] + count[kPlanar];  // ... ends at p
        // In the plane: everything touching p is on both sides.
        consider(p, before + starting, after);
        // Just below p, what begins at p (planar triangles included) is above only; just above
        // p, what ends at p is below only. This is the paper's choice of side for planar
        // triangles, made with closed cells. Skipped where other events lie between p and the
        // offset plane: their own planes cover that case.
        if (starting > 0) {
          const float q = offset_below(p);
          if (!(prev >= q)) consider(q, before, after);
        }
        if (ending > 0) {
          const float q = offset_above(p);
          if (!(i < m && list[i].pos() <= q)) consider(q, before + starting, after - ending);
        }
        before += starting;
        after -= ending;
        prev = p;
      }
    }
  }

  // Wald & Havran's classify-and-split: the children's lists come out sorted without sorting
  // more than the events of the clipped triangles.
  void split_events(const EventLists& ev, const SplitPlane& plane, const AABB& below,
                    const AABB& above, EventLists& out_below, EventLists& out_above,
                    uint32_t& n_below, uint32_t& n_above) {
    classify(ev, plane);
    n_below = n_above = 0;
    clip_straddling(below, above, n_below, n_above);
    for (int a = 0; a < 3; ++a) partition(ev[a], a, out_below[a], out_above[a]);
    // Triangles kept unclipped: one start or planar event each on any axis.
    for (const Event& e : ev[0]) {
      const uint8_t f = flags_[e.tri()];
      if (e.type() == kEnd) continue;
      n_below += (f & kKeepLeft) != 0;
      n_above += (f & kKeepRight) != 0;
    }
  }

  // Flags each triangle by where it goes, from the split axis' events. A triangle's start
  // precedes its end in the list, so a start below p leaves the decision to the end event.
  void classify(const EventLists& ev, const SplitPlane& plane) {
    const uint32_t p = order_key(plane.pos + 0.f);  // compared as order keys
    clip_list_.clear();
    for (const Event& e : ev[plane.axis]) {
      const uint32_t t = e.tri();
      const uint32_t pos = e.pos_key();
      switch (e.type()) {
        case kStart:
          if (pos > p) {
            flags_[t] = kKeepRight;
          } else if (pos == p) {
            flags_[t] = kKeepRight | kClipLeft;  // touches the below cell in the plane
            clip_list_.push_back(t);
          } else {
            flags_[t] = 0;
          }
          break;
        case kEnd:
          if (flags_[t] != 0) break;
          if (pos < p) {
            flags_[t] = kKeepLeft;
          } else if (pos == p) {
            flags_[t] = kKeepLeft | kClipRight;  // touches the above cell in the plane
            clip_list_.push_back(t);
          } else {
            flags_[t] = kClipLeft | kClipRight;  // straddles
            clip_list_.push_back(t);
          }
          break;
        default:  // planar: lying in the split plane it is in both closed cells, unchanged
          flags_[t] = pos < p ? kKeepLeft : pos > p ? kKeepRight : (kKeepLeft | kKeepRight);
          break;
      }
    }
  }

  // Perfect splits: clip the triangles that reach across to each child cell they touch.
  void clip_straddling(const AABB& below, const AABB& above, uint32_t& n_below, uint32_t& n_above) {
    for (auto& l : new_below_) l.clear();
    for (auto& l : new_above_) l.clear();
    for (uint32_t t : clip_list_) {
      const uint8_t f = flags_[t];
      AABB b;
      if ((f & kClipLeft) && clip_to_cell(t, below, b)) {
        add_events(new_below_, t, b);
        ++n_below;
      }
      if ((f & kClipRight) && clip_to_cell(t, above, b)) {
        add_events(new_above_, t, b);
        ++n_above;
      }
    }
  }

  // Partitions axis `a`'s list in order, merging the sorted new events in on the way.
  void partition(const EventList& ev, int a, EventList& l, EventList& r) {
    new_below_[a].sort();
    new_above_[a].sort();
    l.clear();
    r.clear();
    l.reserve(ev.size() + new_below_[a].size());
    r.reserve(ev.size() + new_above_[a].size());
    Event* wl = l.data();
    Event* wr = r.data();
    const Event *nl = new_below_[a].begin(), *nl_end = new_below_[a].end();
    const Event *nr = new_above_[a].begin(), *nr_end = new_above_[a].end();
    for (const Event& e : ev) {
      const uint8_t f = flags_[e.tri()];
      if (f & kKeepLeft) {
        while (nl != nl_end && *nl < e) *wl++ = *nl++;
        *wl++ = e;
      }
      if (f & kKeepRight) {
        while (nr != nr_end && *nr < e) *wr++ = *nr++;
        *wr++ = e;
      }
    }
    wl = std::copy(nl, nl_end, wl);
    wr = std::copy(nr, nr_end, wr);
    l.set_size(size_t(wl - l.data()));
    r.set_size(size_t(wr - r.data()));
  }

  // Extent of triangle t inside `cell`; false when it does not touch the cell.
  bool clip_to_cell(uint32_t t, const AABB& cell, AABB& out) const {
    const Triangle& tri = tris_[t];
    out = clip_triangle_bounds(tri, cell);
    if (!out.empty()) return true;
    // Clipping in double can lose a triangle that merely touches the cell along a computed
    // point; the overlap test has the last word, with a conservative extent.
    if (!triangle_overlaps_box(tri, cell)) return false;
    out = tri.bounds().intersect(cell);
    return !out.empty();
  }

  void make_leaf(uint32_t index, const EventLists& ev, const AABB& cell, uint32_t n, int depth,
                 double rel_area) {
    const uint32_t first = static_cast<uint32_t>(tree_.prims.size());
    for (const Event& e : ev[0])
      if (e.type() != kEnd) tree_.prims.push_back(e.tri());
    std::sort(tree_.prims.begin() + first, tree_.prims.end());
    const uint32_t leaf = static_cast<uint32_t>(tree_.leaves.size());
    tree_.leaves.push_back({first, n, cell});
    tree_.nodes[index] = KdNode::leaf(leaf, n);

    KdTreeStats& s = tree_.stats;
    if (n == 0) ++s.empty_leaves;
    s.max_prims_per_leaf = std::max(s.max_prims_per_leaf, n);
    s.max_depth = std::max(s.max_depth, depth);
    s.sah_cost += params_.intersection_cost * double(n) * rel_area;
  }

  struct Level {
    EventLists below, above;  // lists of the two children at this depth
  };

  const std::vector<Triangle>& tris_;
  const KdTreeParams params_;
  KdTree& tree_;
  int depth_limit_ = 0;
  double root_sa_ = 0;
  float min_offset_ = 0;             // see offset_above()
  std::vector<uint8_t> flags_;       // per triangle, valid while its node is being split
  std::vector<uint32_t> clip_list_;  // triangles of the current split that need clipping
  EventLists root_, new_below_, new_above_;
  std::vector<Level> levels_;  // reused from node to node: no allocation per node
};

}  // namespace

KdTree build_kdtree(const std::vector<Triangle>& triangles, const KdTreeParams& params) {
  const auto start = std::chrono::steady_clock::now();
  KdTree tree;
  Builder(triangles, params, tree).run();
  tree.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tree;
}

}  // namespace rtsim
