#include "scene_loader/obj_loader.h"

#include "common/error.h"

#include <tiny_obj_loader.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

namespace rtsim {
namespace {

// tinyobjloader puts "(line N.)" or "line N" in its messages; lift N out for "FILE:N:".
void throw_tinyobj_error(const std::string& path, const std::string& err) {
  std::string msg = err;
  while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ' || msg.back() == '.'))
    msg.pop_back();
  // First message only
  if (const size_t nl = msg.find('\n'); nl != std::string::npos) msg.resize(nl);
  if (msg.empty()) msg = "tinyobjloader could not parse the file";
  std::smatch m;
  long line = 0;
  if (std::regex_search(msg, m, std::regex(R"(line (\d+))"))) line = std::stol(m[1].str());
  throw_at_line(path, line, msg);
}

struct BadIndex {
  long line = 0;
  long index = 0;  // as written in the file (1-based, or negative = relative)
};

// tinyobjloader checks vertex indices only against the final vertex count and then names the
// file's last line, so on that error path a second, cheap pass finds the offending face line.
BadIndex find_bad_face(const std::string& path, long nverts) {
  std::ifstream in(path, std::ios::binary);
  std::string text;
  long line_no = 0, seen = 0;
  while (std::getline(in, text)) {
    ++line_no;
    const char* s = text.c_str();
    while (*s == ' ' || *s == '\t') ++s;
    if (s[0] == 'v' && (s[1] == ' ' || s[1] == '\t')) {
      ++seen;
      continue;
    }
    if (s[0] != 'f' || (s[1] != ' ' && s[1] != '\t')) continue;
    for (s += 2;;) {
      while (*s == ' ' || *s == '\t' || *s == '\r') ++s;
      if (*s == '\0') break;
      const long raw = std::strtol(s, nullptr, 10);  // "v", "v/t", "v//n", "v/t/n": v comes first
      const long idx = raw > 0 ? raw - 1 : seen + raw;  // negative indices count back from here
      if (raw == 0 || idx < 0 || idx >= nverts) return {line_no, raw};
      while (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\r') ++s;
    }
  }
  return {};
}

void print_warnings(const std::string& path, const std::string& warn) {
  std::istringstream in(warn);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line != ".") std::cerr << "warning: " << path << ": " << line << "\n";
}

}  // namespace

void load_obj(const std::string& path, Scene& scene) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw_at_line(path, 0, "cannot open file");

  // tinyobjloader's own triangulation reads vertex positions before indices are validated, so
  // faces come back as polygons and are fan-triangulated below once every index has been checked.
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) throw_tinyobj_error(path, reader.Error());

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const long nverts = static_cast<long>(attrib.vertices.size() / 3);
  size_t ntris = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t used = 0;
    for (unsigned char n : mesh.num_face_vertices) {
      used += n;
      if (n >= 3) ntris += n - 2u;
    }
    // num_face_vertices is 8 bits wide in this tinyobjloader: a larger polygon breaks the count.
    if (used != mesh.indices.size())
      throw_at_line(path, 0, "a face in shape '" + shape.name + "' has more than 255 vertices");
    for (const tinyobj::index_t& i : mesh.indices) {
      if (i.vertex_index >= 0 && i.vertex_index < nverts) continue;
      const BadIndex bad = find_bad_face(path, nverts);
      throw_at_line(path, bad.line,
                    "face vertex index " + std::to_string(bad.index) +
                        " is out of range (the file has " + std::to_string(nverts) + " vertices)");
    }
  }
  print_warnings(path, reader.Warning());
  print_warnings(path, reader.Error());  // non-fatal .mtl problems

  const std::vector<tinyobj::material_t>& mtls = reader.GetMaterials();
  const uint32_t first = static_cast<uint32_t>(scene.materials.size());
  for (const tinyobj::material_t& m : mtls) {
    Material mat;
    mat.diffuse = Vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    mat.specular = Vec3(m.specular[0], m.specular[1], m.specular[2]);
    mat.shininess = m.shininess;
    mat.ior = m.ior;
    scene.add_material(mat);
  }
  bool have_default = false;
  uint32_t default_material = 0;
  auto material_of = [&](int id) {
    if (id >= 0 && static_cast<size_t>(id) < mtls.size()) return first + static_cast<uint32_t>(id);
    if (!have_default) {
      default_material = scene.add_material(Material{});
      have_default = true;
    }
    return default_material;
  };

  auto position = [&](const tinyobj::index_t& i) {
    const tinyobj::real_t* v = &attrib.vertices[3 * static_cast<size_t>(i.vertex_index)];
    return Vec3(v[0], v[1], v[2]);
  };
  scene.triangles.reserve(scene.triangles.size() + ntris);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const size_t n = mesh.num_face_vertices[f];
      if (n >= 3) {
        const uint32_t material = material_of(mesh.material_ids[f]);
        const Vec3 v0 = position(mesh.indices[offset]);
        for (size_t k = 2; k < n; ++k)
          scene.triangles.push_back(Triangle{v0, position(mesh.indices[offset + k - 1]),
                                             position(mesh.indices[offset + k]), material});
      }
      offset += n;
    }
  }
}

}  // namespace rtsim
