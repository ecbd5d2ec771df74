#include "scene_loader/procedural.h"

#include "common/error.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace rtsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kPitch = 10.0;  // block pitch
constexpr double kStreet = 3.0;  // street width
constexpr double kLot = kPitch - kStreet;

// splitmix64 (Steele, Lea, Flood 2014): tiny, fast and fully specified, unlike the standard
// library's distributions.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1): 53 random bits scaled exactly.
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }
  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }

 private:
  uint64_t state_;
};

// sin and cos of x in [-pi, pi] from their Taylor series: only +, * and /, so every IEEE
// machine computes the same bits.
void sincos_exact(double x, double& s, double& c) {
  const double x2 = x * x;
  double ts = x, tc = 1.0;
  s = 0.0;
  c = 0.0;
  for (int k = 0; k < 30; ++k) {  // the terms are below 1e-17 long before k = 30
    s += ts;
    c += tc;
    ts *= -x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    tc *= -x2 / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
  }
}

Vec3 to_vec3(double x, double y, double z) {
  return Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
}

void check_range(const char* name, long value, long lo, long hi) {
  if (value < lo || value > hi)
    throw InputError("procedural city: '" + std::string(name) + "' must be in " +
                     std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                     std::to_string(value));
}

// Unit sphere as triangles (3 points each), computed once and scaled per sphere.
std::vector<glm::dvec3> unit_sphere(int segments) {
  const int stacks = segments / 2;
  // ring[k][m]: stack k = 1..stacks-1 from the north pole, segment m.
  std::vector<glm::dvec3> ring;
  for (int k = 1; k < stacks; ++k) {
    double sp, cp;
    sincos_exact(kPi * k / stacks - kPi / 2, sp, cp);  // latitude in (-pi/2, pi/2)
    for (int m = 0; m < segments; ++m) {
      double st, ct;
      sincos_exact(2.0 * kPi * m / segments - kPi, st, ct);
      ring.push_back(glm::dvec3(cp * ct, -sp, cp * st));
    }
  }
  auto at = [&](int k, int m) {
    return ring[static_cast<size_t>((k - 1) * segments + m % segments)];
  };
  const glm::dvec3 north(0, 1, 0), south(0, -1, 0);
  std::vector<glm::dvec3> tris;
  for (int m = 0; m < segments; ++m) {
    tris.insert(tris.end(), {north, at(1, m + 1), at(1, m)});
    for (int k = 1; k + 1 < stacks; ++k) {
      tris.insert(tris.end(), {at(k, m), at(k, m + 1), at(k + 1, m + 1)});
      tris.insert(tris.end(), {at(k, m), at(k + 1, m + 1), at(k + 1, m)});
    }
    tris.insert(tris.end(), {south, at(stacks - 1, m), at(stacks - 1, m + 1)});
  }
  return tris;
}

void add_sphere(Scene& scene, const std::vector<glm::dvec3>& unit, const glm::dvec3& center,
                double radius, uint32_t material) {
  for (size_t i = 0; i < unit.size(); i += 3) {
    Triangle t;
    const glm::dvec3 a = center + radius * unit[i], b = center + radius * unit[i + 1],
                     c = center + radius * unit[i + 2];
    t.v0 = to_vec3(a.x, a.y, a.z);
    t.v1 = to_vec3(b.x, b.y, b.z);
    t.v2 = to_vec3(c.x, c.y, c.z);
    t.material = material;
    scene.triangles.push_back(t);
  }
}

void add_quad(Scene& scene, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
              const glm::dvec3& d, uint32_t material) {
  scene.triangles.push_back(
      Triangle{to_vec3(a.x, a.y, a.z), to_vec3(b.x, b.y, b.z), to_vec3(c.x, c.y, c.z), material});
  scene.triangles.push_back(
      Triangle{to_vec3(a.x, a.y, a.z), to_vec3(c.x, c.y, c.z), to_vec3(d.x, d.y, d.z), material});
}

// Walls and roof of the box [x0,x1] x [0,h] x [z0,z1]; the floor would only duplicate the ground.
void add_building(Scene& scene, double x0, double z0, double x1, double z1, double h,
                  uint32_t material) {
  const glm::dvec3 b00(x0, 0, z0), b10(x1, 0, z0), b11(x1, 0, z1), b01(x0, 0, z1);
  const glm::dvec3 t00(x0, h, z0), t10(x1, h, z0), t11(x1, h, z1), t01(x0, h, z1);
  add_quad(scene, b00, b10, t10, t00, material);
  add_quad(scene, b10, b11, t11, t10, material);
  add_quad(scene, b11, b01, t01, t11, material);
  add_quad(scene, b01, b00, t00, t01, material);
  add_quad(scene, t00, t10, t11, t01, material);
}

// The city's materials: the ground, three kinds of wall, a mirror, a glossy paint.
struct CityMaterials {
  uint32_t ground, walls[3], mirror, paint;
};

CityMaterials add_city_materials(Scene& scene) {
  Material ground;
  ground.diffuse = Vec3(0.35f, 0.35f, 0.33f);
  Material concrete;
  concrete.diffuse = Vec3(0.7f, 0.68f, 0.62f);
  Material brick;
  brick.diffuse = Vec3(0.6f, 0.3f, 0.22f);
  Material glass;  // glossy blue facades
  glass.diffuse = Vec3(0.35f, 0.45f, 0.6f);
  glass.specular = Vec3(0.4f);
  glass.shininess = 40.f;
  Material mirror;
  mirror.diffuse = Vec3(0.2f);
  mirror.specular = Vec3(0.8f);
  mirror.shininess = 100.f;
  mirror.reflectance = 0.5f;
  Material paint;
  paint.diffuse = Vec3(0.8f, 0.2f, 0.15f);
  paint.specular = Vec3(0.3f);
  paint.shininess = 20.f;
  CityMaterials m;
  m.ground = scene.add_material(ground);
  m.walls[0] = scene.add_material(concrete);
  m.walls[1] = scene.add_material(brick);
  m.walls[2] = scene.add_material(glass);
  m.mirror = scene.add_material(mirror);
  m.paint = scene.add_material(paint);
  return m;
}

// `lights` point lights on a ring above a city of extent w, and the camera looking down at it.
void add_city_lights_and_camera(int lights, double w, Rng& rng, Scene& scene) {
  const float intensity = static_cast<float>(1.0 / std::sqrt(static_cast<double>(lights)));
  for (int i = 0; i < lights; ++i) {
    double s, c;
    sincos_exact(2.0 * kPi * i / lights - kPi, s, c);
    const double radius = 0.35 * w * rng.range(0.8, 1.0);
    Light light;
    light.position = to_vec3(0.5 * w + radius * c, 30.0 + 0.2 * w, 0.5 * w + radius * s);
    light.color = Vec3(intensity);
    scene.lights.push_back(light);
  }
  const glm::dvec3 eye(-0.2 * w, 0.45 * w + 25.0, -0.2 * w), target(0.5 * w, 0.0, 0.5 * w);
  const glm::dvec3 dir = glm::normalize(target - eye);
  scene.camera = Camera{};
  scene.camera.eye = to_vec3(eye.x, eye.y, eye.z);
  scene.camera.dir = to_vec3(dir.x, dir.y, dir.z);
  scene.camera.up = Vec3(0.f, 1.f, 0.f);
  scene.camera.vfov_deg = 45.f;
  scene.has_camera = true;
}

}  // namespace

uint64_t city_triangles(const CityParams& params) {
  const uint64_t b = uint64_t(std::max(params.blocks, 0));
  const uint64_t s = uint64_t(std::max(params.sphere_segments, 0));
  const uint64_t spheres = (b * b + 1) / 2 + b;  // on every other roof, and one per street
  return 2 + 10 * b * b + spheres * 2 * s * (s / 2 > 0 ? s / 2 - 1 : 0);
}

void make_city(const CityParams& params, Scene& scene) {
  check_range("blocks", params.blocks, 1, kMaxCityBlocks);
  check_range("sphere_segments", params.sphere_segments, 4, 256);
  check_range("lights", params.lights, 1, kMaxLights);
  if (const uint64_t n = city_triangles(params); n > kMaxCityTriangles)
    throw InputError("procedural city: 'blocks' " + std::to_string(params.blocks) +
                     " with 'sphere_segments' " + std::to_string(params.sphere_segments) +
                     " make " + std::to_string(n) + " triangles; expected at most " +
                     std::to_string(kMaxCityTriangles));
  scene.triangles.reserve(scene.triangles.size() + size_t(city_triangles(params)));

  Rng rng(params.seed);
  const int n = params.blocks;
  const double w = kPitch * n + kStreet;  // city extent on x and z
  const CityMaterials m = add_city_materials(scene);
  const std::vector<glm::dvec3> sphere = unit_sphere(params.sphere_segments);

  add_quad(scene, {0, 0, 0}, {0, 0, w}, {w, 0, w}, {w, 0, 0}, m.ground);
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const double lot_x = kStreet + kPitch * col, lot_z = kStreet + kPitch * row;
      const double x0 = lot_x + rng.range(0.0, 1.0), x1 = lot_x + kLot - rng.range(0.0, 1.0);
      const double z0 = lot_z + rng.range(0.0, 1.0), z1 = lot_z + kLot - rng.range(0.0, 1.0);
      const double u = rng.unit();
      const double h = 3.0 + 22.0 * u * u;  // mostly low, a few towers
      add_building(scene, x0, z0, x1, z1, h, m.walls[rng.next() % 3]);
      if ((row + col) % 2 == 0) {
        const double r = 0.25 * std::min(x1 - x0, z1 - z0) * rng.range(0.6, 1.0);
        add_sphere(scene, sphere, {0.5 * (x0 + x1), h + r, 0.5 * (z0 + z1)}, r, m.mirror);
      }
    }
    // The street before this row runs along x at z in [pitch*row, pitch*row + street].
    const double r = 0.4 * kStreet * rng.range(0.7, 1.0);
    const double x = rng.range(0.5 * kStreet, w - 0.5 * kStreet);
    add_sphere(scene, sphere, {x, r, kPitch * row + 0.5 * kStreet}, r,
               rng.next() % 2 ? m.mirror : m.paint);
  }
  add_city_lights_and_camera(params.lights, w, rng, scene);
  scene.width = 640;
  scene.height = 360;
  scene.name = "city";
}

}  // namespace rtsim
