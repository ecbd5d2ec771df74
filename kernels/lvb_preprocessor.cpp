// The search behind one LVB bit: may a triangle block a shadow ray from a hit in leaf b to light
// i? The paper's frusta or the exact hull of the shadow rays bound where a blocker can be; a scan
// of every leaf (the paper's method) or a walk of the kd-tree or BVH finds the leaves reaching
// into it, and the exact mode confirms with their triangles. Why it is never wrong: docs/lvb.md.
// The constructor converts, once, what every (leaf, light) query reads (triangles and their
// planes in double, each reference's box in its leaf and where its shadow rays start), so the
// queries, run concurrently, only read.
#include "kernels/lvb_preprocessor.h"

#include "kernels/clip.h"

#include <glm/geometric.hpp>
#include <glm/gtx/component_wise.hpp>

#include <algorithm>
#include <cmath>

namespace rtsim {
namespace lvb_detail {

namespace {

double max_abs_coordinate(const AABB& b) {
  const Vec3 m = glm::max(glm::abs(b.lo), glm::abs(b.hi));
  return std::max({double(m.x), double(m.y), double(m.z)});
}

// Grows a float box by g, rounding outward, so the grown box contains the exact one.
AABB grown_outward(const AABB& b, double g) {
  AABB r;
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = std::nextafter(float(double(b.lo[a]) - g), -INFINITY);
    r.hi[a] = std::nextafter(float(double(b.hi[a]) + g), INFINITY);
  }
  return r;
}

DBox empty_dbox() { return DBox(DVec3(INFINITY), DVec3(-INFINITY)); }
void extend(DBox& b, const DBox& o) {
  b.lo = glm::min(b.lo, o.lo);
  b.hi = glm::max(b.hi, o.hi);
}

// Squared distance from a point to a box (0 inside): the walk's nearer-to-the-light order.
double distance2(const AABB& b, const DVec3& p) {
  const DVec3 d = glm::max(glm::max(DVec3(b.lo) - p, p - DVec3(b.hi)), DVec3(0.0));
  return glm::dot(d, d);
}

// Which boxes may hold an occluder: the paper's frusta (open) or the exact hull (closed).
struct Region {
  bool exact = false;
  bool contained = false;  // the paper's test read literally (leaf boxes only)
  // BVH leaves, the paper's method: a box reaching into the leaf's own box counts too (another
  // leaf's triangles may lie between the leaf's triangles and the light inside it).
  bool own_counts = false;
  LightFrusta frusta;
  DBox enclosing, own;
  HullTest hull;

  bool may_hold(const DBox& b, Counters& c) const {
    ++c.region_tests;
    if (exact) return hull.intersects(b);
    if (!boxes_overlap_open(enclosing, b)) return false;
    if (own_counts && boxes_overlap_open(own, b)) return true;
    for (int i = 0; i < frusta.count; ++i)
      if (frustum_may_intersect_open(frusta.frusta[i], b)) return true;
    return false;
  }

  // A leaf's box as a candidate occluder. Containment implies overlap, so a cell that fails
  // may_hold holds no leaf box that passes here: the walk prunes with may_hold.
  bool holds_candidate(const DBox& b, Counters& c) const {
    if (!may_hold(b, c)) return false;
    if (!contained || exact) return true;
    if (own_counts && boxes_overlap_open(own, b)) return true;
    for (int i = 0; i < frusta.count; ++i)
      if (frustum_contains(frusta.frusta[i], b)) return true;
    return false;
  }
};

}  // namespace

Preprocessor::Preprocessor(const Scene& scene, const LeafView& view, const LvbParams& p)
    : scene_(scene),
      view_(view),
      prims_(*view.prims),
      p_(p),
      exact_(p.self_occlusion == LvbSelfOcclusion::kTest) {
  const double scale = max_abs_coordinate(view.bounds) + view.bounds.diagonal();
  tolerance_ = 1e-9 * scale;
  // A hit point lies on its triangle's plane up to the rounding of o + t d (a few ulps of the
  // largest coordinate); the half-space filter below is only sound when the offset dwarfs that.
  const double point_error = 8.0 * std::ldexp(max_abs_coordinate(view.bounds), -23);
  halfspace_ok_ = p.shadow_offset > 4 * point_error;
  point_error_ = point_error;

  areas_.resize(scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    if (!l.is_area()) continue;
    AreaLight a;
    const DVec3 c(l.position), e1(l.edge1), e2(l.edge2);
    a.polygon.corners = {c, c + e1, c + e1 + e2, c + e2};
    a.polygon.edge1 = e1;
    a.polygon.edge2 = e2;
    // Each of the two products and sums rounds once: a few ulps of the largest magnitude.
    const double m = std::max(
        {glm::compMax(glm::abs(c)), glm::compMax(glm::abs(e1)), glm::compMax(glm::abs(e2))});
    a.error = 8.0 * std::ldexp(m, -23);
    areas_[i] = a;
  }
  tris_.resize(scene.triangles.size());
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    TriangleInfo& ti = tris_[i];
    ti.v[0] = DVec3(t.v0);
    ti.v[1] = DVec3(t.v1);
    ti.v[2] = DVec3(t.v2);
    const DVec3 n = glm::cross(ti.v[1] - ti.v[0], ti.v[2] - ti.v[0]);
    const double len = glm::length(n);
    ti.n = len > 0 ? n / len : DVec3(0.0);
    ti.c = glm::dot(ti.n, ti.v[0]);
  }
  const size_t leaves = view.leaves.size();
  cell_.resize(leaves);
  geom_.assign(leaves, empty_dbox());
  in_cell_.resize(prims_.size());
  origin_.resize(exact_ ? prims_.size() : 0);
  origin_region_.assign(exact_ ? leaves : 0, empty_dbox());
  // Cell-mode regions grow by the margin plus float rounding of the grown cell used for clipping.
  cell_growth_ =
      p.origin_margin + 4 * std::ldexp(max_abs_coordinate(view.bounds), -23) + 2 * tolerance_;
  const double slack = std::max(0.0, p.origin_margin - p.shadow_offset);
  for (size_t l = 0; l < leaves; ++l) add_leaf_references(l, slack);
}

// One leaf's references: each triangle's box in the leaf (in_cell_), where shadow rays from hits
// on it may start (origin_, exact mode), and their unions, the leaf's geometry and origin region.
void Preprocessor::add_leaf_references(size_t l, double slack) {
  const LeafView::Leaf& leaf = view_.leaves[l];
  cell_[l] = DBox(leaf.box);
  const AABB hit_region = grown_outward(leaf.box, slack);
  for (uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k) {
    const Triangle& t = scene_.triangles[prims_[k]];
    if (view_.bvh) {
      // A whole triangle: hits anywhere on it (up to the hit point's rounding, the margin's
      // part beyond the offset) are this leaf's.
      const AABB tb = t.bounds();
      in_cell_[k] = DBox(tb);
      if (exact_) {
        origin_[k] = DBox(grown_outward(tb, slack)).grown(p_.shadow_offset + tolerance_);
        extend(origin_region_[l], origin_[k]);
      }
    } else if (exact_) {
      // Shadow rays from hits on this triangle credited to this leaf start in here; one clip
      // serves both boxes (its part in the cell is contained in the clip to the grown cell).
      const AABB h = clip_triangle_bounds(t, hit_region);
      origin_[k] = h.empty() ? empty_dbox() : DBox(h).grown(p_.shadow_offset + tolerance_);
      extend(origin_region_[l], origin_[k]);
      const AABB c = h.intersect(leaf.box);
      in_cell_[k] = h.empty() || c.empty() ? empty_dbox() : DBox(c);
    } else {
      const AABB c = clip_triangle_bounds(t, leaf.box);
      in_cell_[k] = c.empty() ? empty_dbox() : DBox(c);
    }
    extend(geom_[l], in_cell_[k]);
  }
}

// What the exact mode knows about one of b's own triangles, for one light.
struct Preprocessor::Origin {
  uint32_t tri;
  bool use_halfspace;
  double side, need;  // a blocker must reach `need` into A's half-space on `side`
  const DBox* origin_box;
  mutable HullTest hull;  // the hull of A's shadow-ray origins and the light, built on first use
  mutable bool hull_ready = false;
};

// One (leaf, light) decision.
struct Preprocessor::Query {
  uint32_t b;
  DVec3 light;                      // a point light, or an area light's centre
  const AreaLight* area = nullptr;  // an area light's polygon
  Region region;
  std::vector<Origin> origins;  // built on the first candidate (exact mode)
  bool origins_ready = false;
  bool own_done = false;  // the leaf's own triangles were tested (exact mode)
};

bool Preprocessor::bit(uint32_t b, size_t light_index, Counters& c, bool* dirty,
                       LazyCounters* lazy) const {
  const AreaLight* area = areas_[light_index].has_value() ? &*areas_[light_index] : nullptr;
  const DVec3 light = area ? DVec3(scene_.lights[light_index].center())
                           : DVec3(scene_.lights[light_index].position);
  if (dirty) *dirty = change_->light_moved[light_index] != 0;
  Query q;
  q.b = b;
  q.light = light;
  q.area = area;
  Region& r = q.region;
  // Exact mode: every shadow ray credited to b starts in this box (origins of all of b's
  // triangles).
  const DBox origins =
      exact_ ? (p_.bounds == LvbBounds::kCell ? cell_[b].grown(cell_growth_) : origin_region_[b])
             : DBox();
  // An area light's region is always the hull (the paper's frusta are for a point).
  r.exact = exact_ || area;
  if (area) {
    r.hull = HullTest(exact_ ? origins : box(b), area->polygon, tolerance_ + area->error);
  } else if (exact_) {
    r.hull = HullTest(origins, light, tolerance_);
  } else {
    r.frusta = build_light_frusta(box(b), light);
    if (r.frusta.slabs_containing_light == 3) return true;  // internal light (Table 1)
    r.enclosing = enclosing_box(box(b), light);
    r.contained = p_.frustum_test == LvbFrustumTest::kContained;
    r.own_counts = view_.bvh != nullptr;
    r.own = box(b);
  }
  if (dirty && !*dirty) {
    // Moved geometry in the leaf's own cell, or somewhere the region reaches.
    Counters scratch;
    *dirty = moved_->any([&](const DBox& m) {
      ++lazy->dirty_tests;
      return cell_[b].overlaps(m) || r.may_hold(m, scratch);
    });
  }
  // The leaf's own triangles are the likeliest blockers and need no search (exact mode).
  if (exact_ && candidate_blocks(q, b, c)) return true;
  if (p_.method == LvbMethod::kPaper) {
    for (uint32_t l = 0; l < view_.leaves.size(); ++l) {
      ++c.nodes_visited;
      if (candidate_blocks(q, l, c)) return true;
    }
    return false;
  }
  return view_.kd ? walk_kdtree(q, c) : walk_bvh(q, c);
}

// Is leaf l a candidate occluder of leaf b, and (exact mode) does one of its triangles confirm?
bool Preprocessor::candidate_blocks(Query& q, uint32_t l, Counters& c) const {
  if (view_.leaves[l].count == 0 || (l == q.b && (!exact_ || q.own_done))) return false;
  if (l == q.b) q.own_done = true;
  if (!q.region.holds_candidate(box(l), c)) return false;
  return !exact_ || pair_blocks(q, l, c);
}

// The paper's future work: visit only the kd-tree cells that reach the region.
bool Preprocessor::walk_kdtree(Query& q, Counters& c) const {
  const KdTree& tree = *view_.kd;
  struct Entry {
    uint32_t node;
    DBox cell;
  };
  Entry stack[128];
  int sp = 0;
  stack[sp++] = {0, DBox(tree.bounds)};
  while (sp > 0) {
    const Entry e = stack[--sp];
    ++c.nodes_visited;
    const KdNode& n = tree.nodes[e.node];
    if (n.is_leaf()) {
      if (candidate_blocks(q, n.leaf_index(), c)) return true;
      continue;
    }
    if (!q.region.may_hold(e.cell, c)) continue;
    const int a = n.axis();
    DBox below = e.cell, above = e.cell;
    below.hi[a] = above.lo[a] = n.split();
    // The side towards the light first: occluders usually lie between the leaf and the light.
    if (q.light[a] >= n.split()) {
      stack[sp++] = {e.node + 1, below};
      stack[sp++] = {n.above_child(), above};
    } else {
      stack[sp++] = {n.above_child(), above};
      stack[sp++] = {e.node + 1, below};
    }
  }
  return false;
}

// The same walk on a BVH: a child whose box fails the region test holds no leaf box that passes
// (its box holds theirs, and the test is monotone), so it is pruned; a leaf is tested as the
// scan tests it. Every node read counts, leaves included; children nearer the light go first.
bool Preprocessor::walk_bvh(Query& q, Counters& c) const {
  const Bvh& bvh = *view_.bvh;
  if (bvh.nodes.empty()) return false;
  constexpr uint32_t kLeafBit = 1u << 31;  // a stack entry that is a leaf number
  std::vector<uint32_t> stack{0};
  stack.reserve(kBvhMaxBranching * 16);
  while (!stack.empty()) {
    const uint32_t e = stack.back();
    stack.pop_back();
    ++c.nodes_visited;
    if (e & kLeafBit) {
      if (candidate_blocks(q, e & ~kLeafBit, c)) return true;
      continue;
    }
    const BvhNode& n = bvh.nodes[e];
    // The children to visit, farthest from the light first (so the nearest is popped first).
    uint32_t next[kBvhMaxBranching];
    double key[kBvhMaxBranching];
    int m = 0;
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const BvhChild& ch = n.children[i];
      if (!ch.is_leaf() && !q.region.may_hold(DBox(ch.box), c)) continue;
      const double d = distance2(ch.box, q.light);
      int j = m++;
      for (; j > 0 && key[j - 1] < d; --j) {
        key[j] = key[j - 1];
        next[j] = next[j - 1];
      }
      key[j] = d;
      next[j] = ch.is_leaf() ? ch.index | kLeafBit : ch.index;
    }
    stack.insert(stack.end(), next, next + m);
  }
  return false;
}

void Preprocessor::prepare_origins(Query& q) const {
  const LeafView::Leaf& lb = view_.leaves[q.b];
  for (uint32_t ka = lb.first; ka < lb.first + lb.count; ++ka) {
    if (origin_[ka].lo.x > origin_[ka].hi.x) continue;  // no hit on A can be credited to b
    const TriangleInfo& ta = tris_[prims_[ka]];
    // The shadow ray starts `offset` off A's plane on the light's side and ends at the light, so
    // every point of it is at least min(offset, light distance) into that side: a blocker
    // must reach that far.
    // An area light: its samples lie between its corners, so the nearest corner bounds them,
    // when all four are on one side (up to the samples' rounding).
    double dl = glm::dot(ta.n, q.light) - ta.c, slack = 0;
    if (q.area) {
      double lo = INFINITY, hi = -INFINITY;
      for (const DVec3& corner : q.area->polygon.corners) {
        lo = std::min(lo, glm::dot(ta.n, corner) - ta.c);
        hi = std::max(hi, glm::dot(ta.n, corner) - ta.c);
      }
      dl = lo > 0 ? lo : (hi < 0 ? hi : 0.0);
      slack = q.area->error;
    }
    Origin o;
    o.tri = prims_[ka];
    o.use_halfspace = halfspace_ok_ && std::abs(dl) > 4 * point_error_ + slack;
    o.side = dl > 0 ? 1.0 : -1.0;
    o.need = 0.5 *
             std::min(p_.shadow_offset - 2 * point_error_, std::abs(dl) - 2 * point_error_ - slack);
    o.origin_box = &origin_[ka];
    q.origins.push_back(o);
  }
  q.origins_ready = true;
}

// Exact mode: can a triangle T of leaf l block a shadow ray from a hit on a triangle A of leaf b?
bool Preprocessor::pair_blocks(Query& q, uint32_t l, Counters& c) const {
  if (!q.origins_ready) prepare_origins(q);
  const LeafView::Leaf& ll = view_.leaves[l];
  for (uint32_t kt = ll.first; kt < ll.first + ll.count; ++kt) {
    // A triangle outside the whole region can block nothing.
    if (ll.count > 1 && !q.region.may_hold(in_cell_[kt], c)) continue;
    const uint32_t t = prims_[kt];
    const TriangleInfo& tt = tris_[t];
    for (const Origin& o : q.origins) {
      if (t == o.tri) continue;
      ++c.pair_tests;
      if (o.use_halfspace) {
        const TriangleInfo& ta = tris_[o.tri];
        double reach = -INFINITY;
        for (const DVec3& v : tt.v) reach = std::max(reach, o.side * (glm::dot(ta.n, v) - ta.c));
        if (reach <= o.need) continue;
      }
      if (!o.hull_ready) {
        o.hull = q.area ? HullTest(*o.origin_box, q.area->polygon, tolerance_ + q.area->error)
                        : HullTest(*o.origin_box, q.light, tolerance_);
        o.hull_ready = true;
      }
      if (o.hull.intersects(in_cell_[kt])) return true;
    }
  }
  return false;
}

}  // namespace lvb_detail

uint64_t lvb_working_bytes(size_t triangles, size_t leaves, size_t refs, bool exact) {
  const uint64_t per_leaf = sizeof(lvb_detail::LeafView::Leaf) + (exact ? 3 : 2) * sizeof(DBox) +
                            sizeof(uint32_t);  // view, cell and geometry (+ origin region), word
  const uint64_t per_ref = (exact ? 2 : 1) * sizeof(DBox);  // in_cell_ (+ origin_)
  return triangles * sizeof(lvb_detail::TriangleInfo) + leaves * per_leaf + refs * per_ref;
}

}  // namespace rtsim
