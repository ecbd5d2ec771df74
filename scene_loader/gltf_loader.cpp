#include "scene_loader/gltf_loader.h"

#include "common/error.h"

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <cctype>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

namespace rtsim {
namespace {

using Mat4 = glm::dmat4;

// rtsim traces geometry only: textures are never decoded (nor is a missing one an error).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

bool ends_with_glb(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".glb";
}

void print_warnings(const std::string& path, const std::string& warn) {
  std::istringstream in(warn);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) std::cerr << "warning: " << path << ": " << line << "\n";
}

class GltfReader {
 public:
  GltfReader(const std::string& path, const tinygltf::Model& model, Scene& scene)
      : path_(path), m_(model), scene_(scene), on_path_(model.nodes.size(), 0) {}

  void run() {
    for (int root : roots()) visit(root, Mat4(1.0));
    if (skipped_lines_points_)
      print_warnings(
          path_, "skipped " + std::to_string(skipped_lines_points_) + " point/line primitive(s)");
    if (skipped_no_position_)
      print_warnings(path_, "skipped " + std::to_string(skipped_no_position_) +
                                " primitive(s) without POSITION or index data");
    if (skipped_lights_)
      print_warnings(path_, "skipped " + std::to_string(skipped_lights_) + " non-point light(s)");
  }

 private:
  [[noreturn]] void fail(const std::string& msg) const { throw_at_line(path_, 0, msg); }

  template <class T>
  const T& at(const std::vector<T>& v, int i, const char* what) const {
    if (i < 0 || static_cast<size_t>(i) >= v.size())
      fail(std::string(what) + " " + std::to_string(i) + " out of range (the file has " +
           std::to_string(v.size()) + ")");
    return v[static_cast<size_t>(i)];
  }

  std::vector<int> roots() const {
    int s = m_.defaultScene >= 0 ? m_.defaultScene : (m_.scenes.empty() ? -1 : 0);
    if (s >= 0) return at(m_.scenes, s, "scene").nodes;
    // No scene: every node that is nobody's child.
    std::vector<char> is_child(m_.nodes.size(), 0);
    for (const tinygltf::Node& n : m_.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<size_t>(c) < is_child.size()) is_child[c] = 1;
    std::vector<int> r;
    for (size_t i = 0; i < m_.nodes.size(); ++i)
      if (!is_child[i]) r.push_back(static_cast<int>(i));
    return r;
  }

  Mat4 local_transform(const tinygltf::Node& n, int index) const {
    const std::string where = "node " + std::to_string(index) + ": ";
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) fail(where + "matrix must have 16 numbers");
      return glm::make_mat4(n.matrix.data());  // both column-major
    }
    Mat4 t(1.0), r(1.0), s(1.0);
    if (!n.translation.empty()) {
      if (n.translation.size() != 3) fail(where + "translation must have 3 numbers");
      t = glm::translate(Mat4(1.0),
                         glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    }
    if (!n.rotation.empty()) {
      if (n.rotation.size() != 4) fail(where + "rotation must have 4 numbers");
      // glTF stores x, y, z, w; glm's constructor takes w first.
      glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      if (glm::length(q) > 0.0) q = glm::normalize(q);
      r = glm::mat4_cast(q);
    }
    if (!n.scale.empty()) {
      if (n.scale.size() != 3) fail(where + "scale must have 3 numbers");
      s = glm::scale(Mat4(1.0), glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    }
    return t * r * s;
  }

  void visit(int index, const Mat4& parent) {
    const tinygltf::Node& n = at(m_.nodes, index, "node");
    if (on_path_[index])
      fail("node " + std::to_string(index) + " is its own ancestor (cycle in the node tree)");
    on_path_[index] = 1;
    const Mat4 world = parent * local_transform(n, index);

    if (n.mesh != -1) add_mesh(n.mesh, world);
    if (n.camera != -1) add_camera(n.camera, world);
    if (auto ext = n.extensions.find("KHR_lights_punctual"); ext != n.extensions.end()) {
      if (!ext->second.Has("light") || !ext->second.Get("light").IsNumber())
        fail("node " + std::to_string(index) + ": KHR_lights_punctual without a light index");
      add_light(ext->second.Get("light").GetNumberAsInt(), world);
    }
    for (int child : n.children) visit(child, world);
    on_path_[index] = 0;
  }

  static Vec3 transform_point(const Mat4& m, const Vec3& p) {
    const glm::dvec4 w = m * glm::dvec4(p.x, p.y, p.z, 1.0);
    return Vec3(w);
  }
  static Vec3 transform_dir(const Mat4& m, double x, double y, double z) {
    return Vec3(glm::normalize(glm::dvec3(m * glm::dvec4(x, y, z, 0.0))));
  }

  void add_camera(int index, const Mat4& world) {
    const tinygltf::Camera& c = at(m_.cameras, index, "camera");
    if (scene_.has_camera || c.type != "perspective") return;  // the first perspective camera wins
    if (!(c.perspective.yfov > 0.0)) fail("camera " + std::to_string(index) + ": yfov must be > 0");
    Camera cam;
    cam.eye = transform_point(world, Vec3(0.f));
    cam.dir = transform_dir(world, 0, 0, -1);
    cam.up = transform_dir(world, 0, 1, 0);
    cam.vfov_deg = static_cast<float>(glm::degrees(c.perspective.yfov));
    scene_.camera = cam;
    scene_.has_camera = true;
  }

  void add_light(int index, const Mat4& world) {
    const tinygltf::Light& l = at(m_.lights, index, "light");
    if (l.type != "point") {
      ++skipped_lights_;
      return;
    }
    Light p;
    p.position = transform_point(world, Vec3(0.f));
    if (l.color.size() == 3) p.color = Vec3(l.color[0], l.color[1], l.color[2]);
    scene_.lights.push_back(p);
  }

  uint32_t material(int index) {
    if (auto it = materials_.find(index); it != materials_.end()) return it->second;
    Material mat;
    mat.diffuse = Vec3(1.f);  // glTF's default baseColorFactor
    if (index != -1) {
      const std::vector<double>& c =
          at(m_.materials, index, "material").pbrMetallicRoughness.baseColorFactor;
      if (c.size() >= 3) mat.diffuse = Vec3(c[0], c[1], c[2]);
    }
    const uint32_t id = scene_.add_material(mat);
    materials_[index] = id;
    return id;
  }

  // The bytes of `count` elements of `elem_size` bytes from an accessor, checked against its
  // buffer view and buffer. Returns the first element and sets `stride`.
  const unsigned char* accessor_data(const tinygltf::Accessor& a, size_t elem_size, size_t& stride,
                                     const std::string& where) const {
    if (a.sparse.isSparse) fail(where + "sparse accessors are not supported");
    const tinygltf::BufferView& v = at(m_.bufferViews, a.bufferView, "bufferView");
    const tinygltf::Buffer& b = at(m_.buffers, v.buffer, "buffer");
    stride = v.byteStride ? v.byteStride : elem_size;
    if (v.byteOffset > b.data.size() || v.byteLength > b.data.size() - v.byteOffset)
      fail(where + "bufferView " + std::to_string(a.bufferView) + " lies outside its buffer");
    if (stride < elem_size)
      fail(where + "byteStride " + std::to_string(stride) + " is smaller than an element");
    // Need byteOffset + (count - 1) * stride + elem_size <= byteLength, without overflow.
    const bool fits =
        a.count == 0 || (a.byteOffset <= v.byteLength && v.byteLength - a.byteOffset >= elem_size &&
                         a.count - 1 <= (v.byteLength - a.byteOffset - elem_size) / stride);
    if (!fits)
      fail(where + "accessor data lies outside bufferView " + std::to_string(a.bufferView));
    return b.data.data() + v.byteOffset + a.byteOffset;
  }

  std::vector<Vec3> positions(int index, const Mat4& world, const std::string& where) const {
    const tinygltf::Accessor& a = at(m_.accessors, index, "accessor");
    if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(where + "POSITION accessor " + std::to_string(index) + " must be float VEC3");
    size_t stride = 0;
    const unsigned char* p = accessor_data(a, 12, stride, where);
    std::vector<Vec3> out(a.count);
    for (size_t i = 0; i < a.count; ++i, p += stride) {
      float xyz[3];
      std::memcpy(xyz, p, sizeof xyz);
      out[i] = transform_point(world, Vec3(xyz[0], xyz[1], xyz[2]));
    }
    return out;
  }

  std::vector<uint32_t> indices(int index, size_t nverts, const std::string& where) const {
    const tinygltf::Accessor& a = at(m_.accessors, index, "accessor");
    size_t size = 0;
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: size = 1; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: size = 2; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: size = 4; break;
      default:
        fail(where + "index accessor " + std::to_string(index) +
             " must be unsigned byte/short/int");
    }
    if (a.type != TINYGLTF_TYPE_SCALAR)
      fail(where + "index accessor " + std::to_string(index) + " must be SCALAR");
    size_t stride = 0;
    const unsigned char* p = accessor_data(a, size, stride, where);
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i, p += stride) {
      uint8_t u8;
      uint16_t u16;
      uint32_t u32 = 0;
      if (size == 1)
        std::memcpy(&u8, p, 1), u32 = u8;
      else if (size == 2)
        std::memcpy(&u16, p, 2), u32 = u16;
      else
        std::memcpy(&u32, p, 4);
      if (u32 >= nverts)
        fail(where + "index " + std::to_string(u32) + " at position " + std::to_string(i) +
             " out of range (" + std::to_string(nverts) + " vertices)");
      out[i] = u32;
    }
    return out;
  }

  bool has_data(int accessor) const {
    const tinygltf::Accessor& a = at(m_.accessors, accessor, "accessor");
    return a.bufferView >= 0 || a.sparse.isSparse;  // sparse: accessor_data reports it
  }

  void add_mesh(int index, const Mat4& world) {
    const tinygltf::Mesh& mesh = at(m_.meshes, index, "mesh");
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = mesh.primitives[pi];
      const std::string where =
          "mesh " + std::to_string(index) + " primitive " + std::to_string(pi) + ": ";
      const int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        ++skipped_lines_points_;
        continue;
      }
      // Accessors without a bufferView are all zeros (only sparse data, unsupported, would fill
      // them): such primitives would be degenerate, so they are skipped like ones without POSITION.
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end() || !has_data(pos->second) ||
          (prim.indices >= 0 && !has_data(prim.indices))) {
        ++skipped_no_position_;
        continue;
      }
      const std::vector<Vec3> v = positions(pos->second, world, where);
      std::vector<uint32_t> idx;
      if (prim.indices >= 0) {
        idx = indices(prim.indices, v.size(), where);
      } else {
        idx.resize(v.size());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<uint32_t>(i);
      }
      const uint32_t mat = material(prim.material);
      auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
        scene_.triangles.push_back(Triangle{v[a], v[b], v[c], mat});
      };
      const size_t n = idx.size();
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < n; i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
      } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // Odd triangles swap their last two vertices to keep a consistent winding.
        for (size_t i = 0; i + 2 < n; ++i) emit(idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]);
      } else {
        for (size_t i = 1; i + 1 < n; ++i) emit(idx[i], idx[i + 1], idx[0]);
      }
    }
  }

  const std::string& path_;
  const tinygltf::Model& m_;
  Scene& scene_;
  std::vector<char> on_path_;          // nodes on the current root-to-node path
  std::map<int, uint32_t> materials_;  // glTF material (-1 = none) -> scene material
  size_t skipped_lines_points_ = 0, skipped_no_position_ = 0, skipped_lights_ = 0;
};

}  // namespace

void load_gltf(const std::string& path, Scene& scene) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw_at_line(path, 0, "cannot open file");

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&skip_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = ends_with_glb(path) ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                      : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw_at_line(path, 0,
                  "tinygltf: " + (err.empty() ? std::string("cannot parse the file") : err));
  }
  print_warnings(path, warn + err);
  GltfReader(path, model, scene).run();
}

}  // namespace rtsim
