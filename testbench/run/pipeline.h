// The host-side preparation every command shares: scene file -> Scene -> kd-tree -> memory image.
#pragma once

#include "config_loader/scene_file.h"
#include "kernels/bvh.h"
#include "kernels/kdtree.h"
#include "kernels/lvb.h"
#include "kernels/memory_image.h"
#include "kernels/ray.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace rtsim {

struct PrepareOptions {
  std::string scene_root;                 // empty = default
  std::vector<ConfigOverride> overrides;  // of the scene file's keys
  int width = 0, height = 0;              // 0 = from the scene file
  Accel accel = Accel::kKdTree;           // the structure in the memory image
};

// The scene, its acceleration structure (the kd-tree, or a BVH) and the memory image.
struct PreparedScene {
  std::string file;
  Scene scene;
  Accel accel = Accel::kKdTree;
  KdTreeParams kdtree_params;
  KdTree tree;  // empty for a BVH
  BvhConfig bvh_config;
  Bvh bvh;  // empty for the kd-tree
  std::unique_ptr<MemoryImage> image;
  double load_seconds = 0, build_seconds = 0;
  double structure_seconds() const {
    return is_bvh(accel) ? bvh.stats.build_seconds : tree.stats.build_seconds;
  }
};

PreparedScene prepare_scene(const std::string& scene_file, const PrepareOptions& options);

// The LVB words of the prepared structure's leaves (kernels/lvb.h); fills in `params`' shadow
// offset and origin margin (the tracer's, from the scene) first.
LvbResult compute_scene_lvb(const PreparedScene& p, LvbParams& params);

// One pixel of mask.npy: bit 0 = the primary ray hit, bit 1+i = its shadow ray to light i is
// occluded.
inline uint16_t mask_value(uint32_t hit_tri, uint16_t occluded) {
  return uint16_t((hit_tri != kNoHit ? 1u : 0u) | (uint32_t(occluded) << 1));
}

// The scene and kd-tree statistics, as written into every report.
nlohmann::json scene_json(const PreparedScene& p);
nlohmann::json kdtree_json(const KdTreeParams& p, const KdTreeStats& s);
nlohmann::json bvh_json(const BvhConfig& c, const BvhStats& s);
// The structure's section of a report, named by its family (kernels/names.h); a BVH's with
// "accel", its format.
nlohmann::json structure_json(const PreparedScene& p);

}  // namespace rtsim
