// The one scene type every loader produces: world-space triangles, materials, lights, camera.
// Data the loaders produce and the kernels consume: a folder of its own, so neither includes the
// other.
#pragma once

#include "common/geometry.h"

#include <string>
#include <vector>

namespace rtsim {

// NFF/BART material, kept as read so shading can use what the file says.
struct Material {
  Vec3 diffuse{0.8f};  // diffuse colour (colour * Kd for NFF 'f')
  Vec3 specular{0.f};  // specular colour (colour * Ks for NFF 'f')
  float shininess = 0.f;
  float reflectance = 0.f;    // mirror weight used by reflection rays (0 = no reflection ray)
  float transmittance = 0.f;  // kept for reference; geometry is opaque in rtsim
  float ior = 1.f;
};

// A point light, or a parallelogram area light: the points position + u edge1 + v edge2 for u, v
// in [0, 1], sampled by `samples` shadow rays per hit (kernels/light_samples.h). A one-sided area
// light emits towards edge1 x edge2 only. AFF and glTF lights are points.
struct Light {
  Vec3 position{0.f};  // the point, or the area light's corner
  Vec3 color{1.f};
  Vec3 edge1{0.f}, edge2{0.f};  // zero for a point light
  bool two_sided = true;
  uint32_t samples = 1;
  bool is_area() const { return edge1 != Vec3(0.f) || edge2 != Vec3(0.f); }
  Vec3 center() const { return position + 0.5f * (edge1 + edge2); }
};

// Pinhole camera. `up` is kept as given by the file (not orthogonalised against `dir`).
struct Camera {
  Vec3 eye{0.f, 0.f, 0.f};
  Vec3 dir{0.f, 0.f, -1.f};  // unit view direction
  Vec3 up{0.f, 1.f, 0.f};
  float vfov_deg = 45.f;  // vertical field of view
  float hither = 0.f;
};

struct Scene {
  std::string name;
  std::vector<Triangle> triangles;
  std::vector<Material> materials;  // Triangle::material indexes this
  std::vector<Light> lights;
  Camera camera;
  bool has_camera = false;
  int width = 0, height = 0;  // 0 = not given by the file
  double time = 0.0;          // animation time the scene was evaluated at

  AABB bounds() const {
    AABB b;
    for (const Triangle& t : triangles) b.extend(t.bounds());
    return b;
  }
  uint32_t add_material(const Material& m) {
    materials.push_back(m);
    return static_cast<uint32_t>(materials.size() - 1);
  }
};

// The mask format (uint16, bit 0 = hit, bit 1+i = light i) bounds the light count.
inline constexpr int kMaxLights = 15;
// Shadow rays per hit and area light (a scene file's `samples`), and the default.
inline constexpr int kMaxLightSamples = 256, kDefaultLightSamples = 16;

}  // namespace rtsim
