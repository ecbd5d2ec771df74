// rtsim info: what a scene file loads to, and the kd-tree built over it.
#include "testbench/commands.h"

#include <fmt/format.h>

namespace rtsim {

int run_info(const InfoArgs& args) {
  const PreparedScene p = prepare_scene(args.scene, args.prepare);
  if (args.json) {
    nlohmann::json j = {{"scene", scene_json(p)},
                        {"host_seconds", {{"load", p.load_seconds}, {"build", p.build_seconds}}}};
    j.update(structure_json(p));
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  const Scene& s = p.scene;
  const Camera& c = s.camera;
  const KdTreeStats& k = p.tree.stats;
  fmt::print("scene        {} ({})\n", s.name, p.file);
  fmt::print("triangles    {}\nmaterials    {}\nresolution   {}x{}\ntime         {}\n",
             s.triangles.size(), s.materials.size(), s.width, s.height, s.time);
  fmt::print(
      "camera       eye ({:.7g}, {:.7g}, {:.7g})  dir ({:.7g}, {:.7g}, {:.7g})  up ({:.7g}, "
      "{:.7g}, {:.7g})  vfov {:.6g} deg\n",
      c.eye.x, c.eye.y, c.eye.z, c.dir.x, c.dir.y, c.dir.z, c.up.x, c.up.y, c.up.z, c.vfov_deg);
  for (size_t i = 0; i < s.lights.size(); ++i) {
    const Light& l = s.lights[i];
    fmt::print("light {:<6} ({:.7g}, {:.7g}, {:.7g})", i, l.position.x, l.position.y, l.position.z);
    if (l.is_area())
      fmt::print(" + u ({:.7g}, {:.7g}, {:.7g}) + v ({:.7g}, {:.7g}, {:.7g}), {}-sided, {} samples",
                 l.edge1.x, l.edge1.y, l.edge1.z, l.edge2.x, l.edge2.y, l.edge2.z,
                 l.two_sided ? "two" : "one", l.samples);
    fmt::print("\n");
  }
  if (is_bvh(p.accel)) {
    const BvhStats& b = p.bvh.stats;
    fmt::print(
        "{:<12} {} nodes, {} leaves, {} triangles ({} degenerate left out), {:.2f} mean / "
        "{} max per leaf\n",
        to_string(p.accel), b.nodes, b.leaves, b.prims, b.left_out, b.mean_leaf_size,
        b.max_leaf_size);
    fmt::print("             depth {} (limit {}), SAH cost {:.2f}, built in {:.3f} s\n",
               b.max_depth, p.bvh_config.max_depth, b.sah_cost, b.build_seconds);
  } else {
    fmt::print(
        "kd-tree      {} nodes, {} leaves ({} empty), {} references, {:.2f} mean / {} max per "
        "non-empty leaf\n",
        k.nodes, k.leaves, k.empty_leaves, k.prim_refs, k.mean_prims_per_leaf,
        k.max_prims_per_leaf);
    fmt::print("             depth {} (limit {}), SAH cost {:.2f}, built in {:.3f} s\n",
               k.max_depth, k.depth_limit, k.sah_cost, k.build_seconds);
  }
  fmt::print("image        {} bytes\nload         {:.3f} s\n", p.image->header().image_bytes,
             p.load_seconds);
  return 0;
}

}  // namespace rtsim
