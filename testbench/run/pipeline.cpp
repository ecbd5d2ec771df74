#include "testbench/run/pipeline.h"

#include "common/error.h"
#include "common/host_clock.h"
#include "kernels/names.h"

#include <fmt/format.h>

#include <chrono>

namespace rtsim {

namespace {
nlohmann::json vec(const Vec3& v) { return {v.x, v.y, v.z}; }
}  // namespace

PreparedScene prepare_scene(const std::string& scene_file, const PrepareOptions& options) {
  PreparedScene p;
  p.file = scene_file;
  auto t0 = std::chrono::steady_clock::now();
  SceneSetup setup =
      load_scene_file(scene_file, SceneFileOptions{options.scene_root, options.overrides});
  p.scene = std::move(setup.scene);
  p.kdtree_params = setup.kdtree;
  p.bvh_config = setup.bvh;
  p.bvh_config.branching = accel_branching(options.accel);
  p.accel = options.accel;
  if (options.width > 0) p.scene.width = options.width;
  if (options.height > 0) p.scene.height = options.height;
  p.load_seconds = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  if (is_bvh(p.accel)) {
    p.bvh = build_bvh(p.scene.triangles, p.bvh_config);
    try {
      p.image = std::make_unique<MemoryImage>(p.scene, p.bvh, p.accel);
    } catch (const std::length_error& e) {  // the tree does not fit the format's index fields
      throw InputError(fmt::format("{}: {}", scene_file, e.what()));
    }
  } else {
    p.tree = build_kdtree(p.scene.triangles, p.kdtree_params);
    p.image = std::make_unique<MemoryImage>(p.scene, p.tree);
  }
  p.build_seconds = seconds_since(t0);
  return p;
}

LvbResult compute_scene_lvb(const PreparedScene& p, LvbParams& params) {
  if (is_bvh(p.accel)) {
    params.shadow_offset = lvb_shadow_offset(p.bvh);
    params.origin_margin = lvb_origin_margin(p.scene, p.bvh);
    return compute_lvb(p.scene, p.bvh, params);
  }
  params.shadow_offset = lvb_shadow_offset(p.tree);
  params.origin_margin = lvb_origin_margin(p.scene, p.tree);
  return compute_lvb(p.scene, p.tree, params);
}

nlohmann::json scene_json(const PreparedScene& p) {
  const Scene& s = p.scene;
  nlohmann::json lights = nlohmann::json::array();
  for (const Light& l : s.lights) {
    nlohmann::json j = {{"position", vec(l.position)}, {"color", vec(l.color)}};
    if (l.is_area())
      j["area"] = {{"edge1", vec(l.edge1)},
                   {"edge2", vec(l.edge2)},
                   {"two_sided", l.two_sided},
                   {"samples", l.samples}};
    lights.push_back(j);
  }
  const AABB b = s.bounds();
  return {{"name", s.name},
          {"file", p.file},
          {"time", s.time},
          {"triangles", s.triangles.size()},
          {"materials", s.materials.size()},
          {"lights", lights},
          {"camera",
           {{"eye", vec(s.camera.eye)},
            {"dir", vec(s.camera.dir)},
            {"up", vec(s.camera.up)},
            {"vfov_deg", s.camera.vfov_deg}}},
          {"resolution", {s.width, s.height}},
          {"bounds", {{"lo", vec(b.lo)}, {"hi", vec(b.hi)}}},
          {"image_bytes", p.image ? p.image->header().image_bytes : 0}};
}

nlohmann::json kdtree_json(const KdTreeParams& p, const KdTreeStats& s) {
  return {{"params",
           {{"traversal_cost", p.traversal_cost},
            {"intersection_cost", p.intersection_cost},
            {"empty_bonus", p.empty_bonus},
            {"max_depth", p.max_depth},
            {"max_prims_per_leaf", p.max_prims_per_leaf}}},
          {"nodes", s.nodes},
          {"inner_nodes", s.inner_nodes},
          {"leaves", s.leaves},
          {"empty_leaves", s.empty_leaves},
          {"nonempty_leaves", s.leaves - s.empty_leaves},
          {"prim_refs", s.prim_refs},
          {"mean_prims_per_leaf", s.mean_prims_per_leaf},
          {"max_prims_per_leaf", s.max_prims_per_leaf},
          {"max_depth", s.max_depth},
          {"depth_limit", s.depth_limit},
          {"sah_cost", s.sah_cost},
          {"build_seconds", s.build_seconds}};
}

nlohmann::json bvh_json(const BvhConfig& c, const BvhStats& s) {
  return {{"params",
           {{"branching", c.branching},
            {"min_leaf_size", c.min_leaf_size},
            {"max_leaf_size", c.max_leaf_size},
            {"traversal_cost", c.traversal_cost},
            {"intersection_cost", c.intersection_cost},
            {"max_depth", c.max_depth}}},
          {"nodes", s.nodes},
          {"leaves", s.leaves},
          {"nonempty_leaves", s.leaves},
          {"prims", s.prims},
          {"left_out", s.left_out},
          {"mean_prims_per_leaf", s.mean_leaf_size},
          {"max_prims_per_leaf", s.max_leaf_size},
          {"max_depth", s.max_depth},
          {"sah_cost", s.sah_cost},
          {"build_seconds", s.build_seconds}};
}

nlohmann::json structure_json(const PreparedScene& p) {
  if (is_bvh(p.accel))
    return {{"accel", to_string(p.accel)},
            {structure_family(true), bvh_json(p.bvh_config, p.bvh.stats)}};
  return {{structure_family(false), kdtree_json(p.kdtree_params, p.tree.stats)}};
}

}  // namespace rtsim
