#include "config_loader/scene_file.h"

#include "common/yaml_reader.h"
#include "scene_loader/aff_loader.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
#include "scene_loader/procedural.h"
#include "scene_loader/simplify.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

Material read_material(YamlMap m) {
  Material mat;
  mat.diffuse = m.get_vec3("diffuse", mat.diffuse);
  mat.specular = m.get_vec3("specular", mat.specular);
  mat.shininess = m.get_in_range("shininess", mat.shininess, 0.f, 1e6f);
  mat.reflectance = m.get_in_range("reflectance", mat.reflectance, 0.f, 1.f);
  m.finish();
  return mat;
}

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

void load_geometry_file(YamlMap& g, const fs::path& root, double time, Scene& scene) {
  const fs::path rel = g.require<std::string>("file");
  const fs::path path = rel.is_absolute() ? rel : root / rel;
  if (!fs::exists(path))
    g.fail(
        "file",
        fmt::format(
            "geometry file '{}' not found (scene root '{}'; set --scene-root or RTSIM_SCENE_ROOT)",
            path.string(), root.string()));
  const std::string ext = lower_extension(path);
  const bool has_material = g.has("material");
  if (g.has("rotation_keys") && ext != ".aff" && ext != ".nff")
    g.fail("rotation_keys", "only AFF/NFF files have rotation keys");
  if (ext == ".aff" || ext == ".nff") {
    if (has_material) g.fail("material", "AFF/NFF files carry their own materials");
    const std::string flip = g.get<std::string>("rotation_keys", "bart");
    if (flip != "bart" && flip != "all")
      g.fail("rotation_keys",
             "expected 'bart' (flipped as BART's code does) or 'all' (every key the short way)");
    load_aff(path.string(), time, scene,
             flip == "bart" ? KbQuatSpline::Flip::kBart : KbQuatSpline::Flip::kAll);
  } else if (ext == ".ply") {
    const Material mat = has_material ? read_material(g.map("material")) : Material{};
    load_ply(path.string(), scene.add_material(mat), scene);
  } else if (ext == ".obj") {
    if (has_material) g.fail("material", "OBJ files carry their own materials (.mtl)");
    load_obj(path.string(), scene);
  } else if (ext == ".gltf" || ext == ".glb") {
    if (has_material) g.fail("material", "glTF files carry their own materials");
    load_gltf(path.string(), scene);
  } else {
    g.fail(
        "file",
        fmt::format("unknown geometry format '{}' (expected .aff, .nff, .ply, .obj, .gltf or .glb)",
                    ext));
  }
}

void load_triangles(YamlMap& g, Scene& scene) {
  YamlMap t = g.map("triangles");
  const YAML::Node verts = t.raw_sequence("vertices");
  const YAML::Node idx = t.raw_sequence("indices");
  if (verts.size() == 0) t.fail("vertices", "expected at least 3 vertices");
  std::vector<Vec3> v;
  for (size_t i = 0; i < verts.size(); ++i) {
    const YAML::Node n = verts[i];
    if (!n.IsSequence() || n.size() != 3)
      t.fail("vertices", fmt::format("entry {}: expected [x, y, z]", i), n);
    try {
      v.emplace_back(n[0].as<float>(), n[1].as<float>(), n[2].as<float>());
    } catch (const YAML::Exception&) {
      t.fail("vertices", fmt::format("entry {}: expected 3 numbers", i), n);
    }
    if (!std::isfinite(v.back().x) || !std::isfinite(v.back().y) || !std::isfinite(v.back().z))
      t.fail("vertices", fmt::format("entry {}: expected 3 finite numbers", i), n);
  }
  const uint32_t mat =
      scene.add_material(t.has("material") ? read_material(t.map("material")) : Material{});
  for (size_t i = 0; i < idx.size(); ++i) {
    const YAML::Node n = idx[i];
    if (!n.IsSequence() || n.size() != 3)
      t.fail("indices", fmt::format("entry {}: expected [a, b, c]", i), n);
    size_t k[3];
    for (int j = 0; j < 3; ++j) {
      long x = -1;
      try {
        x = n[j].as<long>();
      } catch (const YAML::Exception&) {
      }
      if (x < 0 || size_t(x) >= v.size())
        t.fail("indices",
               fmt::format("entry {}: expected vertex indices in [0, {}]", i, v.size() - 1), n);
      k[j] = size_t(x);
    }
    scene.triangles.push_back(Triangle{v[k[0]], v[k[1]], v[k[2]], mat});
  }
  t.finish();
}

void load_procedural(YamlMap& g, Scene& scene) {
  YamlMap p = g.map("procedural");
  const std::string kind = p.get<std::string>("kind", "city");
  if (kind != "city") p.fail("kind", "expected 'city'");
  CityParams c;
  c.blocks = p.get_in_range("blocks", c.blocks, 1, kMaxCityBlocks);
  c.seed = uint32_t(p.get_in_range<int64_t>("seed", c.seed, 0, 0xffffffffll));
  c.sphere_segments = p.get_in_range("sphere_segments", c.sphere_segments, 4, 256);
  c.lights = p.get_in_range("lights", c.lights, 1, kMaxLights);
  if (const uint64_t n = city_triangles(c); n > kMaxCityTriangles)
    p.fail("blocks", fmt::format("blocks {} with sphere_segments {} make {} triangles; expected "
                                 "at most {} (fewer blocks or segments)",
                                 c.blocks, c.sphere_segments, n, kMaxCityTriangles));
  p.finish();
  const std::string name = scene.name;  // the scene file's (or its stem), not the city's own
  make_city(c, scene);
  scene.name = name;
}

// `simplify: {triangles: N}`: the entry's triangles (one material) decimated to at most N.
void simplify_entry(YamlMap& g, size_t first, Scene& scene) {
  YamlMap m = g.map("simplify");
  const uint64_t target = m.get_in_range<uint64_t>("triangles", 0, 4, uint64_t(1) << 31);
  if (target == 0) m.fail("triangles", "expected the number of triangles to keep");
  m.finish();
  for (size_t i = first; i < scene.triangles.size(); ++i)
    if (scene.triangles[i].material != scene.triangles[first].material)
      g.fail("simplify", "expected an entry of one material (this one has several)");
  simplify_triangles(scene.triangles, first, size_t(target));
}

// Whatever its source (this file or a geometry file), the camera must make an image.
void check_camera(YamlMap& top, const Camera& cam) {
  const auto finite = [](const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(cam.eye) || !finite(cam.dir) || !finite(cam.up) || glm::length(cam.dir) == 0.f)
    top.fail("camera",
             "the camera's eye, direction and up must be finite, with a non-zero direction");
  const Vec3 d = glm::normalize(cam.dir);
  const float up_len = glm::length(cam.up);
  if (!(up_len > 0.f) || glm::length(glm::cross(d, cam.up / up_len)) < 1e-6f)
    top.fail("camera", "the camera's up vector is zero or parallel to the view direction");
  if (!(cam.vfov_deg >= 1e-3f && cam.vfov_deg <= 179.f))
    top.fail("camera",
             fmt::format("vertical field of view {} degrees; expected [0.001, 179]", cam.vfov_deg));
}

Camera read_camera(YamlMap c) {
  Camera cam;
  cam.eye = c.require_vec3("eye");
  if (c.has("dir") == c.has("at")) c.fail("dir", "give exactly one of 'dir' and 'at'");
  const Vec3 dir = c.has("dir") ? c.require_vec3("dir") : c.require_vec3("at") - cam.eye;
  if (glm::length(dir) == 0.f)
    c.fail(c.has("dir") ? "dir" : "at", "view direction has zero length");
  cam.dir = glm::normalize(dir);
  cam.up = c.get_vec3("up", Vec3(0, 1, 0));
  cam.vfov_deg = c.get_in_range("vfov_deg", 45.f, 1e-3f, 179.f);
  c.finish();
  return cam;
}

KdTreeParams read_kdtree(YamlMap k) {
  KdTreeParams p;
  p.traversal_cost = k.get_in_range("traversal_cost", p.traversal_cost, 1e-6f, 1e6f);
  p.intersection_cost = k.get_in_range("intersection_cost", p.intersection_cost, 1e-6f, 1e6f);
  p.empty_bonus = k.get_in_range("empty_bonus", p.empty_bonus, 0.f, 0.99f);
  // The traversal stacks hold 64 entries.
  p.max_depth = k.get_in_range("max_depth", p.max_depth, 0, 63);
  p.max_prims_per_leaf = k.get_in_range("max_prims_per_leaf", p.max_prims_per_leaf, 0, 1 << 20);
  k.finish();
  return p;
}

// The BVH builder's knobs but the branching factor (kernels/bvh.h; Embree's limits).
BvhConfig read_bvh(YamlMap k) {
  BvhConfig p;
  p.max_leaf_size = k.get_in_range("max_leaf_size", p.max_leaf_size, 1u, kBvhMaxLeafSize);
  p.min_leaf_size = k.get_in_range("min_leaf_size", p.min_leaf_size, 1u, p.max_leaf_size);
  p.traversal_cost = k.get_in_range("traversal_cost", p.traversal_cost, 1e-6f, 1e6f);
  p.intersection_cost = k.get_in_range("intersection_cost", p.intersection_cost, 1e-6f, 1e6f);
  p.max_depth = k.get_in_range("max_depth", p.max_depth, 1u, kBvhMaxDepth);
  k.finish();
  return p;
}

// A light of `lights.add`: a point (`position`) or a parallelogram (`area: {corner, edge1, edge2,
// two_sided}` with `samples`).
Light read_light(YamlMap& a) {
  Light light;
  light.color = a.get_vec3("color", light.color);
  if (a.has("position") == a.has("area"))
    a.fail("position", "expected either 'position' (a point light) or 'area'");
  if (a.has("position")) {
    light.position = a.require_vec3("position");
    if (a.has("samples"))
      a.fail("samples", "a point light has one sample; 'samples' needs an 'area' light");
  } else {
    YamlMap area = a.map("area");
    light.position = area.require_vec3("corner");
    light.edge1 = area.require_vec3("edge1");
    light.edge2 = area.require_vec3("edge2");
    light.two_sided = area.get<bool>("two_sided", false);
    const float span = glm::length(glm::cross(light.edge1, light.edge2));
    if (!(span > 0.f) || !std::isfinite(span))
      area.fail("edge2", "expected edges that span an area (edge1 x edge2 is zero)");
    area.finish();
    light.samples = uint32_t(a.get_in_range("samples", kDefaultLightSamples, 1, kMaxLightSamples));
  }
  a.finish();
  return light;
}

// `lights.area_from_points`: every point light becomes a horizontal square area light centred on
// it, of side `side_fraction` of the scene's diagonal, two-sided unless stated
// (docs/area-lights.md).
void area_from_points(YamlMap m, Scene& scene) {
  const double fraction = m.get_in_range("side_fraction", 0.02, 1e-6, 1.0);
  const int samples = m.get_in_range("samples", kDefaultLightSamples, 1, kMaxLightSamples);
  const bool two_sided = m.get<bool>("two_sided", true);
  m.finish();
  const float side = float(fraction * scene.bounds().diagonal());
  if (!(side > 0.f)) m.fail("side_fraction", "the scene has no extent to take a fraction of");
  for (Light& l : scene.lights) {
    if (l.is_area()) continue;
    l.edge1 = Vec3(side, 0.f, 0.f);
    l.edge2 = Vec3(0.f, 0.f, side);
    l.position -= 0.5f * (l.edge1 + l.edge2);
    l.two_sided = two_sided;
    l.samples = uint32_t(samples);
  }
}

// `base: FILE` (relative to this file): the base file, with this file's top-level keys in place of
// its own (whole values), so a variant of a setup states only what differs. One level deep.
YamlMap load_with_base(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  YamlMap derived = YamlMap::load_file(path, overrides);
  if (!derived.has("base")) return derived;
  const fs::path base = fs::path(path).parent_path() / derived.require<std::string>("base");
  if (!fs::exists(base)) derived.fail("base", fmt::format("{}: file not found", base.string()));
  std::vector<ConfigOverride> own;
  for (const std::string& key : derived.keys())
    if (key != "base") own.push_back({{key}, derived.raw(key), fmt::format("{}: {}", path, key)});
  own.insert(own.end(), overrides.begin(), overrides.end());
  YamlMap top = YamlMap::load_file(base.string(), own);
  if (top.has("base")) top.fail("base", "a base file has no base of its own (one level only)");
  return top;
}

}  // namespace

std::string default_scene_root() {
  if (const char* env = std::getenv("RTSIM_SCENE_ROOT"); env && *env) return env;
  for (const fs::path& p :
       {fs::path("../shared/scenes"), fs::path(RTSIM_DEFAULT_SOURCE_DIR) / "../shared/scenes"})
    if (fs::is_directory(p)) return fs::weakly_canonical(p).string();
  return ".";
}

SceneSetup load_scene_file(const std::string& path, const SceneFileOptions& options) {
  YamlMap top = load_with_base(path, options.overrides);
  const fs::path root = options.scene_root.empty() ? default_scene_root() : options.scene_root;
  SceneSetup setup;
  Scene& scene = setup.scene;
  scene.name = top.get<std::string>("name", fs::path(path).stem().string());
  scene.time = top.get<double>("time", 0.0);
  for (YamlMap& g : top.list_of_maps("geometry")) {
    const int kinds = g.has("file") + g.has("triangles") + g.has("procedural");
    if (kinds != 1) g.fail("file", "expected exactly one of 'file', 'triangles', 'procedural'");
    const size_t first = scene.triangles.size();
    if (g.has("file"))
      load_geometry_file(g, root, scene.time, scene);
    else if (g.has("triangles"))
      load_triangles(g, scene);
    else
      load_procedural(g, scene);
    if (g.has("simplify")) simplify_entry(g, first, scene);
    g.finish();
  }
  if (top.has("camera")) {
    scene.camera = read_camera(top.map("camera"));
    scene.has_camera = true;
  } else {
    top.get<int>("camera", 0);  // an explicit 'camera: ~' means "from the file"
  }
  if (!scene.has_camera)
    top.fail("camera", "no camera: the geometry files define none, so give one here");
  check_camera(top, scene.camera);

  if (top.has("lights")) {
    YamlMap l = top.map("lights");
    if (!l.get<bool>("from_files", true)) scene.lights.clear();
    if (l.has("add"))
      for (YamlMap& a : l.list_of_maps("add")) scene.lights.push_back(read_light(a));
    if (l.has("area_from_points")) area_from_points(l.map("area_from_points"), scene);
    l.finish();
  }
  if (scene.lights.empty()) top.fail("lights", "the scene has no light");
  if (scene.lights.size() > size_t(kMaxLights))
    top.fail("lights", fmt::format("{} lights; at most {} are supported (one mask bit each)",
                                   scene.lights.size(), kMaxLights));

  if (top.has("resolution")) {
    const YAML::Node r = top.raw("resolution");
    int w = 0, h = 0;
    try {
      if (r.IsSequence() && r.size() == 2) w = r[0].as<int>(), h = r[1].as<int>();
    } catch (const YAML::Exception&) {
    }
    if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
      top.fail("resolution", "expected [width, height], each in [1, 16384]");
    scene.width = w;
    scene.height = h;
  }
  if (scene.width == 0 && scene.height == 0) {
    scene.width = 640;
    scene.height = 360;
  }
  if (scene.width < 1 || scene.height < 1 || scene.width > 16384 || scene.height > 16384)
    top.fail("resolution", fmt::format("the geometry files give {}x{}; expected each side in [1, "
                                       "16384] (set 'resolution' here to override)",
                                       scene.width, scene.height));
  if (scene.triangles.empty()) top.fail("geometry", "the scene has no triangles");
  if (top.has("kdtree")) setup.kdtree = read_kdtree(top.map("kdtree"));
  if (top.has("bvh")) setup.bvh = read_bvh(top.map("bvh"));
  top.finish();
  return setup;
}

}  // namespace rtsim
