// BVH builder: Embree 3's rtcBuildBVH (MEDIUM quality = binned SAH, no spatial splits) builds a
// tree of temporary nodes through callbacks; we then copy it into our own arrays in a fixed order.
//
// Why the copy and not Embree's nodes directly: the callbacks run on several threads in no fixed
// order, so addresses and any counter handed out in them differ between runs. What Embree decides
// (the splits, each node's children and their order, each leaf's triangles) depends only on the
// input (docs/bvh.md); numbering nodes depth-first from the root, recomputing every box from the
// triangles and sorting each leaf's triangles by index removes everything else.
#include "kernels/bvh.h"

#include "kernels/clip.h"

#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace rtsim {

void BvhConfig::validate(const std::string& prefix) const {
  auto fail = [&](const char* key, const std::string& allowed, const std::string& got) {
    throw std::invalid_argument(prefix + key + ": expected " + allowed + ", got " + got);
  };
  if (branching != 2 && branching != 4 && branching != 8)
    fail("branching", "2, 4 or 8", std::to_string(branching));
  if (max_leaf_size < 1 || max_leaf_size > kBvhMaxLeafSize)
    fail("max_leaf_size", "1.." + std::to_string(kBvhMaxLeafSize), std::to_string(max_leaf_size));
  if (min_leaf_size < 1 || min_leaf_size > max_leaf_size)
    fail("min_leaf_size", "1..max_leaf_size (" + std::to_string(max_leaf_size) + ")",
         std::to_string(min_leaf_size));
  if (!(std::isfinite(traversal_cost) && traversal_cost > 0.f))
    fail("traversal_cost", "a finite number > 0", std::to_string(traversal_cost));
  if (!(std::isfinite(intersection_cost) && intersection_cost > 0.f))
    fail("intersection_cost", "a finite number > 0", std::to_string(intersection_cost));
  if (max_depth < 1 || max_depth > kBvhMaxDepth)
    fail("max_depth", "1.." + std::to_string(kBvhMaxDepth), std::to_string(max_depth));
  if (build_threads > 1024) fail("build_threads", "0 (all) .. 1024", std::to_string(build_threads));
}

namespace {

// Embree's tree as the callbacks build it, in memory of the RTCBVH's allocator (freed with it).
struct TmpNode {
  uint32_t is_leaf;
  uint32_t count;  // children or triangles
  union {
    void* children[kBvhMaxBranching];
    uint32_t ids[kBvhMaxLeafSize];
  };
};

// The callbacks touch only the node they are given: safe on any thread, in any order.
void* create_node(RTCThreadLocalAllocator alloc, unsigned int child_count, void*) {
  auto* n = static_cast<TmpNode*>(rtcThreadLocalAlloc(alloc, sizeof(TmpNode), alignof(TmpNode)));
  if (n == nullptr) return nullptr;
  n->is_leaf = 0;
  n->count = child_count;  // > kBvhMaxBranching: refused when copied
  std::fill(n->children, n->children + kBvhMaxBranching, nullptr);
  return n;
}

void set_node_children(void* node, void** children, unsigned int count, void*) {
  auto* n = static_cast<TmpNode*>(node);
  for (unsigned int i = 0; i < count && i < kBvhMaxBranching; ++i) n->children[i] = children[i];
}

// Mandatory for Embree; the boxes are recomputed from the triangles when the tree is copied.
void set_node_bounds(void*, const RTCBounds**, unsigned int, void*) {}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                  void*) {
  auto* n = static_cast<TmpNode*>(rtcThreadLocalAlloc(alloc, sizeof(TmpNode), alignof(TmpNode)));
  if (n == nullptr) return nullptr;
  n->is_leaf = 1;
  n->count = static_cast<uint32_t>(count);  // > kBvhMaxLeafSize: refused when copied
  for (size_t i = 0; i < count && i < kBvhMaxLeafSize; ++i) n->ids[i] = prims[i].primID;
  return n;
}

struct DeviceRelease {
  void operator()(RTCDeviceTy* d) const { rtcReleaseDevice(d); }
};
struct BvhRelease {
  void operator()(RTCBVHTy* b) const { rtcReleaseBVH(b); }
};

void on_embree_error(void* user, RTCError, const char* message) {
  auto* out = static_cast<std::string*>(user);
  if (out->empty()) *out = message ? message : "unknown error";
}

// Copies Embree's tree into `out` depth-first in pre-order (see the header).
class Flattener {
 public:
  Flattener(const std::vector<AABB>& boxes, const BvhConfig& config, Bvh& out)
      : boxes_(boxes), config_(config), out_(out) {}

  void root(const TmpNode* t) {
    if (t != nullptr && t->is_leaf) {  // the whole scene is one leaf: below a root of its own
      out_.nodes.emplace_back();
      const BvhChild c = emit(t, 1);
      out_.nodes[0].child_count = 1;
      out_.nodes[0].children[0] = c;
      out_.bounds = c.box;
    } else {
      out_.bounds = emit(t, 0).box;
    }
  }

 private:
  // `depth`: inner nodes above `t`.
  BvhChild emit(const TmpNode* t, uint32_t depth) {
    if (t == nullptr) throw std::runtime_error("bvh: Embree returned a null node (out of memory?)");
    // Embree keeps to the limits it was given; a node that does not is refused, never cut.
    if (t->count == 0 || t->count > (t->is_leaf ? config_.max_leaf_size : config_.branching))
      throw std::logic_error("bvh: Embree made a node of " + std::to_string(t->count) +
                             (t->is_leaf ? " triangles" : " children"));
    BvhChild c;
    if (t->is_leaf) {
      BvhLeaf leaf;
      leaf.first = static_cast<uint32_t>(out_.prims.size());
      leaf.count = t->count;
      out_.prims.insert(out_.prims.end(), t->ids, t->ids + t->count);
      std::sort(out_.prims.begin() + leaf.first, out_.prims.end());
      for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
        leaf.box.extend(boxes_[out_.prims[i]]);
      c.index = static_cast<uint32_t>(out_.leaves.size());
      c.count = leaf.count;
      c.box = leaf.box;
      out_.leaves.push_back(leaf);
      out_.stats.max_depth = std::max(out_.stats.max_depth, depth);
      return c;
    }
    c.index = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.emplace_back();
    out_.nodes[c.index].child_count = t->count;
    for (uint32_t i = 0; i < t->count; ++i) {
      const BvhChild child = emit(static_cast<const TmpNode*>(t->children[i]), depth + 1);
      out_.nodes[c.index].children[i] = child;  // by index: emit() may grow the vector
      c.box.extend(child.box);
    }
    return c;
  }

  const std::vector<AABB>& boxes_;
  const BvhConfig& config_;
  Bvh& out_;
};

// Runs rtcBuildBVH over `prims` (reordered by Embree) and copies the result into `out`.
void embree_build(std::vector<RTCBuildPrimitive>& prims, const std::vector<AABB>& boxes,
                  const BvhConfig& config, Bvh& out) {
  std::string error;  // before the device: it must outlive the device's error callback
  const std::string device_config = "threads=" + std::to_string(config.build_threads);
  std::unique_ptr<RTCDeviceTy, DeviceRelease> device(rtcNewDevice(device_config.c_str()));
  if (!device) throw std::runtime_error("bvh: Embree could not create a device");
  rtcSetDeviceErrorFunction(device.get(), on_embree_error, &error);
  std::unique_ptr<RTCBVHTy, BvhRelease> handle(rtcNewBVH(device.get()));
  if (!handle) throw std::runtime_error("bvh: Embree could not create a BVH: " + error);

  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH; no spatial splits
  args.maxBranchingFactor = config.branching;
  args.maxDepth = config.max_depth;
  args.minLeafSize = config.min_leaf_size;
  args.maxLeafSize = config.max_leaf_size;
  args.traversalCost = config.traversal_cost;
  args.intersectionCost = config.intersection_cost;
  args.bvh = handle.get();
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = create_node;
  args.setNodeChildren = set_node_children;
  args.setNodeBounds = set_node_bounds;
  args.createLeaf = create_leaf;

  const auto* root = static_cast<const TmpNode*>(rtcBuildBVH(&args));
  if (root == nullptr || !error.empty()) {
    if (error.find("depth limit") != std::string::npos)
      throw std::invalid_argument("bvh.max_depth: " + std::to_string(config.max_depth) +
                                  " is too small for " + std::to_string(prims.size()) +
                                  " triangles (Embree: " + error + ")");
    throw std::runtime_error("bvh: Embree's build failed: " + (error.empty() ? "no root" : error));
  }
  Flattener(boxes, config, out).root(root);
}

// Numbers the leaves node by node, each node's leaf children in slot order (see the header).
void number_leaves(Bvh& bvh) {
  std::vector<BvhLeaf> leaves;
  leaves.reserve(bvh.leaves.size());
  for (BvhNode& n : bvh.nodes)
    for (uint32_t i = 0; i < n.child_count; ++i) {
      BvhChild& c = n.children[i];
      if (!c.is_leaf()) continue;
      leaves.push_back(bvh.leaves[c.index]);
      c.index = static_cast<uint32_t>(leaves.size() - 1);
    }
  bvh.leaves = std::move(leaves);
}

void compute_stats(const Bvh& bvh, BvhStats& s) {
  s.nodes = bvh.nodes.size();
  s.prims = bvh.prims.size();
  const double root_area = bvh.bounds.surface_area();
  double inner = 0, leaf = 0;
  for (const BvhNode& n : bvh.nodes) {
    AABB box;
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const BvhChild& c = n.children[i];
      box.extend(c.box);
      if (!c.is_leaf()) continue;
      ++s.leaves;
      s.max_leaf_size = std::max(s.max_leaf_size, c.count);
      leaf += double(c.count) * c.box.surface_area();
    }
    inner += box.surface_area();
  }
  s.mean_leaf_size = s.leaves ? double(s.prims) / double(s.leaves) : 0.0;
  s.sah_cost = root_area > 0 ? (inner + leaf) / root_area : 0.0;
}

}  // namespace

Bvh build_bvh(const std::vector<Triangle>& triangles, const BvhConfig& config) {
  config.validate();
  if (triangles.size() > UINT32_MAX)  // triangle indices are 32-bit here and in the hardware
    throw std::length_error("bvh: " + std::to_string(triangles.size()) + " triangles, at most " +
                            std::to_string(UINT32_MAX));
  const auto start = std::chrono::steady_clock::now();
  Bvh out;
  out.branching = config.branching;

  std::vector<AABB> boxes(triangles.size());
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    if (triangle_is_degenerate(triangles[i])) {
      ++out.stats.left_out;
      continue;
    }
    const AABB b = boxes[i] = triangles[i].bounds();
    prims.push_back(RTCBuildPrimitive{b.lo.x, b.lo.y, b.lo.z, 0u, b.hi.x, b.hi.y, b.hi.z,
                                      static_cast<uint32_t>(i)});
  }
  if (prims.empty()) {
    out.nodes.emplace_back();  // a root without children
  } else {
    embree_build(prims, boxes, config, out);
    number_leaves(out);
  }
  compute_stats(out, out.stats);
  out.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::vector<uint8_t> serialize_bvh(const Bvh& bvh) {
  std::vector<uint8_t> bytes;
  auto put = [&](uint32_t w) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<uint8_t>(w >> (8 * i)));
  };
  auto put_vec = [&](const Vec3& v) {
    for (int a = 0; a < 3; ++a) {
      uint32_t w;
      std::memcpy(&w, &v[a], 4);
      put(w);
    }
  };
  put(bvh.branching);
  put_vec(bvh.bounds.lo);
  put_vec(bvh.bounds.hi);
  put(static_cast<uint32_t>(bvh.nodes.size()));
  for (const BvhNode& n : bvh.nodes) {
    put(n.child_count);
    for (uint32_t i = 0; i < n.child_count; ++i) {
      put_vec(n.children[i].box.lo);
      put_vec(n.children[i].box.hi);
      put(n.children[i].index);
      put(n.children[i].count);
    }
  }
  put(static_cast<uint32_t>(bvh.prims.size()));
  for (uint32_t p : bvh.prims) put(p);
  return bytes;
}

uint64_t bvh_hash(const Bvh& bvh) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (uint8_t b : serialize_bvh(bvh)) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace rtsim
