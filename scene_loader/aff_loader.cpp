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

constexpr double kPi = 3.14159265358979323846;

// Tessellation of the NFF quadrics. 12 x 24 keeps a sphere at 528 triangles (silhouette
// error under 1% of the radius); cones and cylinders get 24 sides and, as NFF specifies, no
// end caps.
constexpr int kSphereStacks = 12;
constexpr int kSphereSlices = 24;
constexpr int kConeSides = 24;

// Includes nest a few levels in practice; a deep chain is almost surely a cycle.
constexpr int kMaxIncludeDepth = 64;

bool read_file(const std::string& path, std::string& out) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!f) return false;
  out.clear();
  char buf[1 << 16];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) out.append(buf, n);
  return !std::ferror(f.get());
}

// Whitespace tokenizer over a whole file. '{' and '}' are tokens of their own; '#' or '%'
// at the start of a token comments out the rest of the line.
class Tokenizer {
 public:
  Tokenizer(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  const std::string& path() const { return path_; }
  // Line of the last token returned (at end of file: of the last token in the file).
  long line() const { return tok_line_; }

  // The next token; empty at end of file.
  std::string_view next() {
    const char* s = text_.data();
    const std::size_t n = text_.size();
    for (;;) {
      while (pos_ < n && is_space(s[pos_])) {
        if (s[pos_] == '\n') ++line_;
        ++pos_;
      }
      if (pos_ >= n) return {};
      if (s[pos_] == '#' || s[pos_] == '%') {
        while (pos_ < n && s[pos_] != '\n') ++pos_;
        continue;
      }
      tok_line_ = line_;
      std::size_t begin = pos_++;
      if (s[begin] != '{' && s[begin] != '}')
        while (pos_ < n && !is_space(s[pos_]) && s[pos_] != '{' && s[pos_] != '}') ++pos_;
      return std::string_view(s + begin, pos_ - begin);
    }
  }

  std::string_view peek() {
    std::size_t pos = pos_;
    long line = line_, tok_line = tok_line_;
    std::string_view t = next();
    pos_ = pos;
    line_ = line;
    tok_line_ = tok_line;
    return t;
  }

  // "FILE:LINE: found F, expected E".
  [[noreturn]] void fail(std::string_view found, const std::string& expected) const {
    std::string what = found.empty() ? "end of file" : "'" + std::string(found) + "'";
    error("found " + what + ", expected " + expected);
  }
  // "FILE:LINE: MESSAGE" at the last token.
  [[noreturn]] void error(const std::string& message) const {
    throw_at_line(path_, tok_line_, message);
  }

  double number(const char* what) {
    std::string_view t = next();
    double v;
    if (!parse_number(t, v)) fail(t, std::string("a number (") + what + ")");
    return v;
  }
  dvec3 vec3(const char* what) {
    double x = number(what);
    double y = number(what);
    return dvec3(x, y, number(what));
  }
  long integer(const char* what) {
    std::string_view t = next();
    long v = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size())
      fail(t, std::string("an integer (") + what + ")");
    return v;
  }
  long count(const char* what) {
    long n = integer(what);
    if (n < 0) fail(std::to_string(n), std::string("a count >= 0 (") + what + ")");
    return n;
  }
  // An index into a list of `size` items.
  long index(const char* what, long size) {
    long i = integer(what);
    if (i < 0 || i >= size)
      fail(std::to_string(i), std::string(what) + " in [0, " + std::to_string(size) + ")");
    return i;
  }
  std::string_view word(const char* what) {
    std::string_view t = next();
    if (t.empty() || t == "{" || t == "}") fail(t, what);
    return t;
  }
  void expect(std::string_view keyword, const char* context) {
    std::string_view t = next();
    if (t != keyword) fail(t, "'" + std::string(keyword) + "' " + context);
  }
  bool next_is_number() {
    double v;
    return parse_number(peek(), v);
  }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
  }
  static bool parse_number(std::string_view t, double& v) {
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);  // from_chars rejects a leading '+'
    if (t.empty()) return false;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size();
  }

  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  long line_ = 1;
  long tok_line_ = 1;
};

dvec3 transform_point(const dmat4& m, const dvec3& p) { return dvec3(m * glm::dvec4(p, 1.0)); }

// M = T * R * S: scale first, then rotate, then translate (BART's order for xs and x).
dmat4 trs(const dvec3& t, const dquat& r, const dvec3& s) {
  return glm::translate(dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(dmat4(1.0), s);
}

// A `k NAME` block evaluated at the load time.
struct Animation {
  bool has_translation = false, has_rotation = false;
  dvec3 translation{0.0};
  dquat rotation{1.0, 0.0, 0.0, 0.0};
  dvec3 scale{1.0};
  bool visible = true;

  dmat4 matrix() const { return trs(translation, rotation, scale); }
};

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

class AffLoader {
 public:
  AffLoader(Scene& scene, double time, KbQuatSpline::Flip rotation_flip)
      : scene_(scene),
        time_(time),
        rotation_flip_(rotation_flip),
        first_triangle_(scene.triangles.size()),
        first_light_(scene.lights.size()) {}

  void load(const std::string& path) {
    std::string text;
    if (!read_file(path, text)) throw_at_line(path, 0, "cannot open file");
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
        parse_mesh(tk);
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
        parse_polygon(tk, false);
      else if (kw == "pp")
        parse_polygon(tk, true);
      else if (kw == "tt")
        parse_textured_triangle(tk, false);
      else if (kw == "ttp")
        parse_textured_triangle(tk, true);
      else if (kw == "tpa")
        parse_animated_triangle(tk);
      else if (kw == "s")
        parse_sphere(tk);
      else if (kw == "c")
        parse_cone(tk);
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
    matrix_ = matrix_ * trs(t, quat_from_axis_angle(axis, degrees), s);
  }

  void parse_animated_transform(Tokenizer& tk) {
    std::string name(tk.word("a transform name after 'x'"));
    open_brace(tk, "after 'x NAME'");
    nodes_.push_back(AnimNode{std::move(name), node_, matrix_, {}, {}});
    node_ = static_cast<int>(nodes_.size()) - 1;
    matrix_ = dmat4(1.0);
  }

  // `k NAME { transl N ... rot N ... scale N ... visibility N ... }`, evaluated right away:
  // the load time is fixed, so only the resulting transform needs keeping.
  void parse_keyframes(Tokenizer& tk) {
    std::string name(tk.word("an animation name after 'k'"));
    tk.expect("{", "after 'k NAME'");
    Animation anim;
    for (;;) {
      std::string_view kind = tk.next();
      if (kind == "}") break;
      if (kind == "transl" || kind == "scale") {
        bool is_transl = kind == "transl";
        KbSpline<dvec3> spline(read_vector_keys(tk, is_transl ? "transl" : "scale"));
        (is_transl ? anim.translation : anim.scale) = spline.evaluate(time_);
        if (is_transl) anim.has_translation = true;
      } else if (kind == "rot") {
        anim.rotation = KbQuatSpline(read_rotation_keys(tk), rotation_flip_).evaluate(time_);
        anim.has_rotation = true;
      } else if (kind == "visibility") {
        // Visible until the first key; from each key's time on, that key's flag holds.
        long n = tk.count("number of visibility keys");
        if (n < 1) tk.fail(std::to_string(n), "at least 1 visibility key");
        for (long i = 0; i < n; ++i) {
          double t = tk.number("visibility key time");
          long flag = tk.integer("visibility flag 0 or 1");
          if (flag != 0 && flag != 1) tk.fail(std::to_string(flag), "visibility flag 0 or 1");
          if (t <= time_) anim.visible = flag == 1;
        }
      } else {
        tk.fail(kind, "'transl', 'rot', 'scale', 'visibility' or '}' in 'k " + name + "'");
      }
    }
    animations_[name] = anim;  // a later block for the same name replaces an earlier one
  }

  long key_count(Tokenizer& tk, const char* kind) {
    long n = tk.count("number of keys");
    // The first and last keys only shape tangents, so 4 is the minimum (as in BART).
    if (n < 4) tk.fail(std::to_string(n), std::string("at least 4 '") + kind + "' keys");
    return n;
  }

  Tcb read_tcb(Tokenizer& tk) {
    Tcb c;
    c.tension = tk.number("key tension");
    c.continuity = tk.number("key continuity");
    c.bias = tk.number("key bias");
    return c;
  }

  std::vector<KbKey<dvec3>> read_vector_keys(Tokenizer& tk, const char* kind) {
    std::vector<KbKey<dvec3>> keys(static_cast<std::size_t>(key_count(tk, kind)));
    for (KbKey<dvec3>& k : keys) {
      k.time = tk.number("key time");
      k.value = tk.vec3("key x y z");
      k.tcb = read_tcb(tk);
    }
    return keys;
  }

  std::vector<KbKey<dquat>> read_rotation_keys(Tokenizer& tk) {
    std::vector<KbKey<dquat>> keys(static_cast<std::size_t>(key_count(tk, "rot")));
    for (KbKey<dquat>& k : keys) {
      k.time = tk.number("key time");
      dvec3 axis = tk.vec3("rotation key axis");
      // Each key is an absolute orientation; angles beyond 360 only matter modulo 720 here.
      k.value = quat_from_axis_angle(axis, tk.number("rotation key angle in degrees"));
      k.tcb = read_tcb(tk);
    }
    return keys;
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
    if (!read_file(resolved, text))
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
    l.position = Vec3(transform_point(matrix_, tk.vec3("light position")));
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

  Vec3 to_frame(const dvec3& p) const { return Vec3(transform_point(matrix_, p)); }

  // Adds a triangle already in the current node's frame.
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    std::size_t i = scene_.triangles.size();
    scene_.triangles.push_back(Triangle{a, b, c, material()});
    if (node_ < 0) return;
    auto& ranges = nodes_[node_].triangles;
    if (!ranges.empty() && ranges.back().second == i)
      ranges.back().second = i + 1;
    else
      ranges.emplace_back(i, i + 1);
  }

  // m / vertices N xyz... / [normals N xyz...] / [texturecoords N file uv...] /
  // triangles N, each "v0 v1 v2 [n0 n1 n2] [t0 t1 t2]".
  void parse_mesh(Tokenizer& tk) {
    tk.expect("vertices", "after 'm'");
    long nv = tk.count("number of mesh vertices");
    std::vector<Vec3> verts(static_cast<std::size_t>(nv));
    for (Vec3& v : verts) v = to_frame(tk.vec3("mesh vertex x y z"));

    long nn = 0, nt = 0;
    std::string_view section = tk.next();
    if (section == "normals") {
      nn = tk.count("number of mesh normals");
      for (long i = 0; i < 3 * nn; ++i) tk.number("mesh normal x y z");  // normals unused
      section = tk.next();
    }
    if (section == "texturecoords") {
      nt = tk.count("number of mesh texture coordinates");
      tk.word("a texture file name after 'texturecoords N'");  // textures ignored, never opened
      for (long i = 0; i < 2 * nt; ++i) tk.number("mesh texture coordinate u v");
      section = tk.next();
    }
    if (section != "triangles")
      tk.fail(section, nn || nt ? "'triangles' in mesh"
                                : "'normals', 'texturecoords' or 'triangles' in mesh");

    long ntri = tk.count("number of mesh triangles");
    for (long i = 0; i < ntri; ++i) {
      long a = tk.index("a mesh vertex index", nv);
      long b = tk.index("a mesh vertex index", nv);
      long c = tk.index("a mesh vertex index", nv);
      for (int k = 0; k < 3 && nn; ++k) tk.index("a mesh normal index", nn);
      for (int k = 0; k < 3 && nt; ++k) tk.index("a mesh texture coordinate index", nt);
      add_triangle(verts[a], verts[b], verts[c]);
    }
  }

  // p N xyz... / pp N (xyz nxnynz)...: planar convex polygons, fan-triangulated.
  void parse_polygon(Tokenizer& tk, bool patch) {
    long n = tk.count("number of polygon vertices");
    if (n < 3) tk.fail(std::to_string(n), "at least 3 polygon vertices");
    std::vector<Vec3> v(static_cast<std::size_t>(n));
    for (Vec3& p : v) {
      p = to_frame(tk.vec3("polygon vertex x y z"));
      if (patch) tk.vec3("polygon patch normal");
    }
    for (long i = 1; i + 1 < n; ++i) add_triangle(v[0], v[i], v[i + 1]);
  }

  // tt TEXTURE (xyz uv) x3 / ttp TEXTURE (xyz n uv) x3.
  void parse_textured_triangle(Tokenizer& tk, bool patch) {
    tk.word("a texture file name");
    Vec3 v[3];
    for (Vec3& p : v) {
      p = to_frame(tk.vec3("textured triangle vertex x y z"));
      if (patch) tk.vec3("textured triangle normal");
      tk.number("texture coordinate u");
      tk.number("texture coordinate v");
    }
    add_triangle(v[0], v[1], v[2]);
  }

  // tpa N, then N samples "time (x y z nx ny nz) x3" in increasing time: the triangle at the load
  // time is the linear interpolation of the two samples around it, clamped to the first and the
  // last sample (BART's format description).
  void parse_animated_triangle(Tokenizer& tk) {
    const long n = tk.count("number of tpa time samples");
    if (n < 1) tk.fail(std::to_string(n), "at least 1 tpa time sample");
    std::vector<double> times(static_cast<std::size_t>(n));
    std::vector<std::array<dvec3, 3>> verts(times.size());
    for (std::size_t k = 0; k < times.size(); ++k) {
      times[k] = tk.number("tpa sample time");
      if (k > 0 && !(times[k] > times[k - 1]))
        tk.error("found tpa sample time " + std::to_string(times[k]) + " after " +
                 std::to_string(times[k - 1]) + ", expected increasing times");
      for (dvec3& v : verts[k]) {
        v = tk.vec3("tpa vertex x y z");
        tk.vec3("tpa normal");
      }
    }
    std::size_t k = 0;
    while (k + 1 < times.size() && times[k + 1] <= time_) ++k;
    std::array<dvec3, 3> v = verts[k];
    if (k + 1 < times.size() && time_ > times[k]) {
      const double s = (time_ - times[k]) / (times[k + 1] - times[k]);
      for (int j = 0; j < 3; ++j) v[j] = (1.0 - s) * verts[k][j] + s * verts[k + 1][j];
    }
    add_triangle(to_frame(v[0]), to_frame(v[1]), to_frame(v[2]));
  }

  // s x y z r. A negative radius (inside visible) gives the same surface.
  void parse_sphere(Tokenizer& tk) {
    dvec3 center = tk.vec3("sphere centre");
    double r = std::abs(tk.number("sphere radius"));
    if (r == 0.0) tk.error("found sphere radius 0, expected a non-zero radius");
    auto point = [&](int stack, int slice) {
      double theta = kPi * stack / kSphereStacks;
      double phi = 2.0 * kPi * slice / kSphereSlices;
      dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      return to_frame(center + r * d);
    };
    // Quads between latitude rings, counter-clockwise seen from outside; the pole rows
    // collapse to one triangle each.
    for (int i = 0; i < kSphereStacks; ++i) {
      for (int j = 0; j < kSphereSlices; ++j) {
        Vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
        if (i + 1 < kSphereStacks) add_triangle(a, c, b);
        if (i > 0) add_triangle(a, d, c);
      }
    }
  }

  // c / base.xyz base_r / apex.xyz apex_r: an open cone or cylinder.
  void parse_cone(Tokenizer& tk) {
    dvec3 base = tk.vec3("cone base centre");
    double r0 = std::abs(tk.number("cone base radius"));
    dvec3 apex = tk.vec3("cone apex centre");
    double r1 = std::abs(tk.number("cone apex radius"));
    dvec3 axis = apex - base;
    if (glm::length(axis) == 0.0)
      tk.error("found cone apex equal to base, expected distinct points");
    if (r0 == 0.0 && r1 == 0.0) tk.error("found cone radii 0 and 0, expected a non-zero radius");
    dvec3 w = glm::normalize(axis);
    // Any unit vector not parallel to w completes the frame.
    dvec3 helper = std::abs(w.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    dvec3 u = glm::normalize(glm::cross(helper, w));
    dvec3 v = glm::cross(w, u);
    auto ring = [&](const dvec3& c, double r, int j) {
      double phi = 2.0 * kPi * j / kConeSides;
      return to_frame(c + r * (std::cos(phi) * u + std::sin(phi) * v));
    };
    for (int j = 0; j < kConeSides; ++j) {
      Vec3 a = ring(base, r0, j), b = ring(base, r0, j + 1);
      Vec3 c = ring(apex, r1, j + 1), d = ring(apex, r1, j);
      if (r0 > 0.0) add_triangle(a, b, c);
      if (r1 > 0.0) add_triangle(a, c, d);
    }
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
          tri.v0 = Vec3(transform_point(m, dvec3(tri.v0)));
          tri.v1 = Vec3(transform_point(m, dvec3(tri.v1)));
          tri.v2 = Vec3(transform_point(m, dvec3(tri.v2)));
        }
      }
      for (std::size_t l : n.lights)
        scene_.lights[l].position = Vec3(transform_point(m, dvec3(scene_.lights[l].position)));
    }
    for (const AnimatedLight& a : animated_lights_) {
      auto it = animations_.find(a.name);
      if (it == animations_.end())
        throw_at_line(
            a.file, a.line,
            "found 'la " + a.name + "', expected keyframes 'k " + a.name + "' in the scene");
      const dmat4 m = (a.node < 0 ? dmat4(1.0) : world[a.node]) * a.matrix * it->second.matrix();
      scene_.lights[a.index].position = Vec3(transform_point(m, a.position));
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
