// What the tests of the BVH images and of their walk share: the node formats, a
// float's bits (results must be equal bit for bit) and the scenes they are built over.
#pragma once

#include "config_loader/scene_file.h"
#include "kernels/bvh_format.h"
#include "tests/test_util.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace rtsim::bvh_test {

// Every registered BVH node format, and those that decode to the tree's nodes exactly (cwbvh8's
// boxes are quantised outward and its nodes renumbered: tests/kernels/test_cwbvh8.cpp checks it).
inline std::vector<Accel> registered_bvh_accels() {
  std::vector<Accel> out;
  for (const RegisteredName& n : bvh_formats().names()) out.push_back(parse_accel(n.name));
  return out;
}
inline const std::vector<Accel> kBvhAccels = registered_bvh_accels();
inline const Accel kBvh2 = parse_accel("bvh2"), kBvh4 = parse_accel("bvh4"),
                   kBvh8 = parse_accel("bvh8"), kCwbvh8 = parse_accel("cwbvh8");
inline const std::vector<Accel> kUncompressedAccels = {kBvh2, kBvh4, kBvh8};

inline uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

inline SceneSetup load_city() {
  return load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string(),
                         SceneFileOptions{test::shared_scenes().string(), {}});
}

// One default material and one light around the triangles.
inline Scene scene_of(std::vector<Triangle> tris) {
  Scene s;
  s.add_material(Material{});
  s.triangles = std::move(tris);
  s.lights.push_back({});
  return s;
}

}  // namespace rtsim::bvh_test
