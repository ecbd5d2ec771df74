// BART AFF loader.
//
// Parsing is one pass over whole-file buffers. Geometry is emitted as soon as it is read, in
// the frame of the innermost enclosing animated transform (`x NAME`): static transforms
// (`xs`) are folded in at once. Animated transforms cannot be resolved while parsing because
// their keyframes (`k NAME`) may come later, even in another file, so each `x` records a node
// and the triangle ranges it owns; load_aff() then evaluates the keyframes at the requested
// time, moves each node's triangles to world space and drops those of invisible nodes.

#include "scene_loader/aff_loader.h"

#include "common/error.h"
#include "scene_loader/aff_geometry.h"
#include "scene_loader/aff_keyframes.h"
#include "scene_loader/aff_tokenizer.h"
#include "scene_loader/kb_spline.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rtsim {
namespace {

using glm::dmat4;
using glm::dquat;
using glm::dvec3;

using aff::Animation;
using aff::Tokenizer;

// Includes nest a few levels in practice; a deep chain is almost surely a cycle.
constexpr int kMaxIncludeDepth = 64;

// An `x NAME { ... }` block: its triangles and lights are stored in its own frame.
struct AnimNode {
  std::string name;
  int parent;   // enclosing animated node, -1 for none
  dmat4 local;  // static transforms between the parent's frame and this node
  std::vector<std::pair<std::size_t, std::size_t>> triangles;  // [begin, end) in scene
  std::vector<std::size_t> lights;
};

// An `la NAME` light: its position in the frame of the keyframes NAME, and where that frame sits.
struct AnimatedLight {
  std::size_t index;  // in scene.lights
  int node;           // enclosing animated node, -1 for none
  dmat4 matrix;       // static transforms between that node's frame and the light's
  dvec3 position;
  std::string name, file;
  long line;
};

// An open '{': what to restore at its '}'.
struct Frame {
  dmat4 matrix;
  int node;
  long line;
};

class AffLoader : public aff::GeometrySink {
 public:
  AffLoader(Scene& scene, double time, KbQuatSpline::Flip rotation_flip)
      : scene_(scene),
        time_(time),
        rotation_flip_(rotation_flip),
        first_triangle_(scene.triangles.size()),
        first_light_(scene.lights.size()) {}

  void load(const std::string& path) {
    std::string text;
    if (!aff::read_file(path, text)) throw_at_line(path, 0, "cannot open file");
    Tokenizer tk(path, std::move(text));
    parse(tk);
    resolve_animation();
    scene_.time = time_;
    if (scene_.name.empty()) scene_.name = std::filesystem::path(path).stem().string();
  }

 private:
  void parse(Tokenizer& tk) {
    const std::size_t depth_at_entry = frames_.size();
    for (;;) {
      std::string_view kw = tk.next();
      if (kw.empty()) break;
      if (kw == "m")
        aff::parse_mesh(tk, *this);
      else if (kw == "xs")
        parse_static_transform(tk);
      else if (kw == "x")
        parse_animated_transform(tk);
      else if (kw == "}")
        close_frame(tk, depth_at_entry);
      else if (kw == "i")
        parse_include(tk);
      else if (kw == "fm")
        parse_material_fm(tk);
      else if (kw == "f")
        parse_material_f(tk);
      else if (kw == "k")
        parse_keyframes(tk);
      else if (kw == "p")
        aff::parse_polygon(tk, false, *this);
      else if (kw == "pp")
        aff::parse_polygon(tk, true, *this);
      else if (kw == "tt")
        aff::parse_textured_triangle(tk, false, *this);
      else if (kw == "ttp")
        aff::parse_textured_triangle(tk, true, *this);
      else if (kw == "tpa")
        aff::parse_animated_triangle(tk, time_, *this);
      else if (kw == "s")
        aff::parse_sphere(tk, *this);
      else if (kw == "c")
        aff::parse_cone(tk, *this);
      else if (kw == "l")
        parse_light(tk);
      else if (kw == "la")
        parse_animated_light(tk);
      else if (kw == "v")
        parse_view(tk);
      else if (kw == "b")
        tk.vec3("background colour");  // no background in Scene
      else if (kw == "am")
        tk.vec3("ambient light colour");  // no ambient term in Scene
      else if (kw == "a")
        parse_animation_range(tk);
      else if (kw == "d")
        detail_level_ = tk.integer("detail level");
      else if (kw == "{")
        tk.fail(kw, "a keyword ('{' only follows 'xs ...' or 'x NAME')");
      else
        tk.error("found unknown keyword '" + std::string(kw) +
                 "', expected one of the AFF keywords v b l la f fm am a c s p pp tt ttp tpa m i d "
                 "xs x k }");
    }
    // Braces must balance within each file, so a truncated include cannot close its parent.
    if (frames_.size() > depth_at_entry)
      throw_at_line(tk.path(), frames_.back().line,
                    "found end of file, expected '}' closing the '{' opened on this line");
  }

  // ---- transforms --------------------------------------------------------------------------

  void open_brace(Tokenizer& tk, const char* after) {
    tk.expect("{", after);
    frames_.push_back(Frame{matrix_, node_, tk.line()});
  }

  void close_frame(Tokenizer& tk, std::size_t depth_at_entry) {
    if (frames_.size() <= depth_at_entry)
      tk.fail("}", "a keyword ('}' closes no '{' opened in this file)");
    matrix_ = frames_.back().matrix;
    node_ = frames_.back().node;
    frames_.pop_back();
  }

  void parse_static_transform(Tokenizer& tk) {
    dvec3 s = tk.vec3("xs scale");
    dvec3 axis = tk.vec3("xs rotation axis");
    double degrees = tk.number("xs rotation angle");
    dvec3 t = tk.vec3("xs translation");
    open_brace(tk, "after 'xs' and its 10 numbers");
    matrix_ = matrix_ * aff::trs(t, quat_from_axis_angle(axis, degrees), s);
  }

  void parse_animated_transform(Tokenizer& tk) {
    std::string name(tk.word("a transform name after 'x'"));
    open_brace(tk, "after 'x NAME'");
    nodes_.push_back(AnimNode{std::move(name), node_, matrix_, {}, {}});
    node_ = static_cast<int>(nodes_.size()) - 1;
    matrix_ = dmat4(1.0);
  }

  void parse_keyframes(Tokenizer& tk) {
    std::string name;
    const Animation anim = aff::parse_keyframes(tk, time_, rotation_flip_, name);
    animations_[name] = anim;  // a later block for the same name replaces an earlier one
  }

  void parse_animation_range(Tokenizer& tk) {
    tk.number("animation start time");
    tk.number("animation end time");
    tk.count("animation frame count");
  }

  // ---- includes ----------------------------------------------------------------------------

  void parse_include(Tokenizer& tk) {
    long level = tk.integer("include detail level");
    std::string name(tk.word("a file name after 'i LEVEL'"));
    // BART skips includes more detailed than the current detail level ('d', default 0).
    if (level > detail_level_) return;
    std::filesystem::path p(name);
    if (p.is_relative()) p = std::filesystem::path(tk.path()).parent_path() / p;
    std::string resolved = p.string();
    if (include_depth_ >= kMaxIncludeDepth)
      tk.error("found include of '" + name + "' nested " + std::to_string(include_depth_) +
               " deep, expected an include chain without cycles");
    std::string text;
    if (!aff::read_file(resolved, text))
      tk.error("found include of '" + name + "', expected a readable file at '" + resolved + "'");
    Tokenizer inner(resolved, std::move(text));
    ++include_depth_;
    parse(inner);
    --include_depth_;
  }

  // ---- materials and lights ---------------------------------------------------------------

  // NFF: f r g b Kd Ks Shine T ior. Reflectance = Ks: NFF uses Ks as the mirror weight too.
  void parse_material_f(Tokenizer& tk) {
    dvec3 rgb = tk.vec3("f colour");
    double kd = tk.number("f Kd");
    double ks = tk.number("f Ks");
    Material m;
    m.diffuse = Vec3(rgb * kd);
    m.specular = Vec3(rgb * ks);
    m.shininess = static_cast<float>(tk.number("f shine"));
    m.reflectance = static_cast<float>(ks);
    m.transmittance = static_cast<float>(tk.number("f transmittance"));
    m.ior = static_cast<float>(tk.number("f index of refraction"));
    material_ = static_cast<int>(scene_.add_material(m));
  }

  // BART: fm amb(rgb) diff(rgb) spec(rgb) shine T ior. Reflectance = mean of the specular
  // colour, the scalar closest to NFF's Ks.
  void parse_material_fm(Tokenizer& tk) {
    tk.vec3("fm ambient colour");  // no ambient term in Material
    Material m;
    m.diffuse = Vec3(tk.vec3("fm diffuse colour"));
    dvec3 spec = tk.vec3("fm specular colour");
    m.specular = Vec3(spec);
    m.reflectance = static_cast<float>((spec.x + spec.y + spec.z) / 3.0);
    m.shininess = static_cast<float>(tk.number("fm shine"));
    m.transmittance = static_cast<float>(tk.number("fm transmittance"));
    m.ior = static_cast<float>(tk.number("fm index of refraction"));
    material_ = static_cast<int>(scene_.add_material(m));
  }

  uint32_t material() {
    if (material_ < 0) material_ = static_cast<int>(scene_.add_material(Material{}));
    return static_cast<uint32_t>(material_);
  }

  // l x y z [r g b]. Lights move with their enclosing transforms, like geometry.
  void parse_light(Tokenizer& tk) {
    Light l;
    l.position = Vec3(aff::transform_point(matrix_, tk.vec3("light position")));
    if (tk.next_is_number()) l.color = Vec3(tk.vec3("light colour"));
    if (node_ >= 0) nodes_[node_].lights.push_back(scene_.lights.size());
    scene_.lights.push_back(l);
  }

  // la NAME x y z [r g b]: a light placed by the keyframes `k NAME` (which may come later), as
  // `x NAME { l x y z }` would be; resolved with the animated transforms.
  void parse_animated_light(Tokenizer& tk) {
    AnimatedLight a;
    a.name = std::string(tk.word("an animated light's name after 'la'"));
    a.position = tk.vec3("light position");
    Light l;
    if (tk.next_is_number()) l.color = Vec3(tk.vec3("light colour"));
    a.index = scene_.lights.size();
    a.node = node_;
    a.matrix = matrix_;
    a.file = tk.path();
    a.line = tk.line();
    animated_lights_.push_back(std::move(a));
    scene_.lights.push_back(l);
  }

  void parse_view(Tokenizer& tk) {
    Camera c;
    tk.expect("from", "in 'v' block");
    dvec3 from = tk.vec3("v from");
    tk.expect("at", "in 'v' block");
    dvec3 at = tk.vec3("v at");
    tk.expect("up", "in 'v' block");
    dvec3 up = tk.vec3("v up");
    tk.expect("angle", "in 'v' block");
    double angle = tk.number("v angle");
    tk.expect("hither", "in 'v' block");
    double hither = tk.number("v hither");
    tk.expect("resolution", "in 'v' block");
    long w = tk.integer("v resolution width");
    long h = tk.integer("v resolution height");
    if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
      tk.error("found resolution " + std::to_string(w) + " x " + std::to_string(h) +
               ", expected a width and height in [1, 16384]");
    if (glm::length(at - from) == 0.0)
      tk.error("found 'at' equal to 'from' in 'v', expected distinct points");
    c.eye = Vec3(from);
    c.dir = Vec3(glm::normalize(at - from));
    c.up = Vec3(up);  // kept as given, not orthogonalised (see Camera)
    c.vfov_deg = static_cast<float>(angle);
    c.hither = static_cast<float>(hither);
    scene_.camera = c;
    scene_.has_camera = true;
    scene_.width = static_cast<int>(w);
    scene_.height = static_cast<int>(h);
  }

  // ---- geometry ----------------------------------------------------------------------------

  // GeometrySink: the current node's frame.
  Vec3 to_frame(const dvec3& p) const override { return Vec3(aff::transform_point(matrix_, p)); }
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) override {
    std::size_t i = scene_.triangles.size();
    scene_.triangles.push_back(Triangle{a, b, c, material()});
    if (node_ < 0) return;
    auto& ranges = nodes_[node_].triangles;
    if (!ranges.empty() && ranges.back().second == i)
      ranges.back().second = i + 1;
    else
      ranges.emplace_back(i, i + 1);
  }

  // ---- animation ---------------------------------------------------------------------------

  void resolve_animation() {
    std::vector<dmat4> world(nodes_.size());
    std::vector<char> visible(nodes_.size());
    std::vector<char> keep_tri, keep_light;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const AnimNode& n = nodes_[i];
      dmat4 m = n.parent < 0 ? dmat4(1.0) : world[n.parent];
      bool vis = n.parent < 0 ? true : visible[n.parent] != 0;
      m = m * n.local;
      auto it = animations_.find(n.name);
      if (it != animations_.end()) {  // an `x` without keyframes stays static
        m = m * it->second.matrix();
        vis = vis && it->second.visible;
      }
      world[i] = m;
      visible[i] = vis;

      if (!vis) {
        if (keep_tri.empty()) keep_tri.assign(scene_.triangles.size() - first_triangle_, 1);
        if (keep_light.empty()) keep_light.assign(scene_.lights.size() - first_light_, 1);
        for (auto [b, e] : n.triangles)
          for (std::size_t t = b; t < e; ++t) keep_tri[t - first_triangle_] = 0;
        for (std::size_t l : n.lights) keep_light[l - first_light_] = 0;
        continue;
      }
      if (m == dmat4(1.0)) continue;
      for (auto [b, e] : n.triangles) {
        for (std::size_t t = b; t < e; ++t) {
          Triangle& tri = scene_.triangles[t];
          tri.v0 = Vec3(aff::transform_point(m, dvec3(tri.v0)));
          tri.v1 = Vec3(aff::transform_point(m, dvec3(tri.v1)));
          tri.v2 = Vec3(aff::transform_point(m, dvec3(tri.v2)));
        }
      }
      for (std::size_t l : n.lights)
        scene_.lights[l].position = Vec3(aff::transform_point(m, dvec3(scene_.lights[l].position)));
    }
    for (const AnimatedLight& a : animated_lights_) {
      auto it = animations_.find(a.name);
      if (it == animations_.end())
        throw_at_line(
            a.file, a.line,
            "found 'la " + a.name + "', expected keyframes 'k " + a.name + "' in the scene");
      const dmat4 m = (a.node < 0 ? dmat4(1.0) : world[a.node]) * a.matrix * it->second.matrix();
      scene_.lights[a.index].position = Vec3(aff::transform_point(m, a.position));
      if (a.node >= 0 && !visible[a.node]) {
        if (keep_light.empty()) keep_light.assign(scene_.lights.size() - first_light_, 1);
        keep_light[a.index - first_light_] = 0;
      }
    }
    compact(scene_.triangles, first_triangle_, keep_tri);
    compact(scene_.lights, first_light_, keep_light);

    // `k camera` overrides `v`: eye = translation, view = -Z and up = +Y of the rotation.
    // A missing channel keeps what `v` gave (or the default camera).
    auto cam = animations_.find("camera");
    if (cam != animations_.end()) {
      const Animation& a = cam->second;
      Camera& c = scene_.camera;
      if (a.has_translation) c.eye = Vec3(a.translation);
      if (a.has_rotation) {
        c.dir = Vec3(glm::normalize(a.rotation * dvec3(0.0, 0.0, -1.0)));
        c.up = Vec3(glm::normalize(a.rotation * dvec3(0.0, 1.0, 0.0)));
      }
      scene_.has_camera = true;
    }
  }

  // Removes items [first + i] with keep[i] == 0, keeping order. Empty keep = keep all.
  template <typename T>
  static void compact(std::vector<T>& items, std::size_t first, const std::vector<char>& keep) {
    if (keep.empty()) return;
    std::size_t out = first;
    for (std::size_t i = first; i < items.size(); ++i)
      if (keep[i - first]) items[out++] = items[i];
    items.resize(out);
  }

  Scene& scene_;
  double time_;
  KbQuatSpline::Flip rotation_flip_;
  std::size_t first_triangle_, first_light_;  // where this load started appending

  dmat4 matrix_{1.0};  // static transforms from the current node's frame to here
  int node_ = -1;      // innermost enclosing animated node
  std::vector<Frame> frames_;
  std::vector<AnimNode> nodes_;
  std::unordered_map<std::string, Animation> animations_;
  std::vector<AnimatedLight> animated_lights_;

  int material_ = -1;  // current material (global, in parse order), -1 until set or needed
  long detail_level_ = 0;
  int include_depth_ = 0;
};

}  // namespace

void load_aff(const std::string& path, double time, Scene& scene,
              KbQuatSpline::Flip rotation_flip) {
  AffLoader(scene, time, rotation_flip).load(path);
}

}  // namespace rtsim
