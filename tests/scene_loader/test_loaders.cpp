// Tests of the PLY, OBJ and glTF loaders and the procedural city.
#include "common/error.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
#include "scene_loader/procedural.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <vector>

namespace rtsim {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// The message of the InputError that `f` throws; fails the test if it throws nothing.
std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

bool same_triangles(const std::vector<Triangle>& a, const std::vector<Triangle>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].v0 != b[i].v0 || a[i].v1 != b[i].v1 || a[i].v2 != b[i].v2 ||
        a[i].material != b[i].material)
      return false;
  return true;
}

void expect_near(const Vec3& got, const Vec3& want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// ---------------------------------------------------------------------------------------------
// PLY

// A polygon mesh written by the tests in any encoding, with extra elements and properties of
// assorted types that the loader must read past.
struct PlyMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::vector<int>> faces;
};

struct PlyTypes {
  std::string coord = "float";
  std::string count = "uchar";
  std::string index = "int";
};

enum class Encoding { kAscii, kLittle, kBig };

void put_binary(std::string& out, const std::string& type, double value, bool big) {
  unsigned char b[8];
  size_t n = 0;
  auto store = [&](auto v) {
    n = sizeof v;
    std::memcpy(b, &v, n);
  };
  if (type == "char" || type == "int8")
    store(static_cast<int8_t>(value));
  else if (type == "uchar" || type == "uint8")
    store(static_cast<uint8_t>(value));
  else if (type == "short" || type == "int16")
    store(static_cast<int16_t>(value));
  else if (type == "ushort" || type == "uint16")
    store(static_cast<uint16_t>(value));
  else if (type == "int" || type == "int32")
    store(static_cast<int32_t>(value));
  else if (type == "uint" || type == "uint32")
    store(static_cast<uint32_t>(value));
  else if (type == "float" || type == "float32")
    store(static_cast<float>(value));
  else
    store(value);
  if (big) std::reverse(b, b + n);  // the tests run on little-endian hosts
  out.append(reinterpret_cast<const char*>(b), n);
}

std::string ascii_value(const std::string& type, double value) {
  char buf[64];
  if (type == "float" || type == "float32")
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<float>(value));
  else if (type == "double" || type == "float64")
    std::snprintf(buf, sizeof buf, "%.17g", value);
  else
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(value));
  return buf;
}

void write_ply(const fs::path& path, const PlyMesh& mesh, Encoding enc, const PlyTypes& t = {}) {
  const char* format = enc == Encoding::kAscii    ? "ascii"
                       : enc == Encoding::kLittle ? "binary_little_endian"
                                                  : "binary_big_endian";
  std::string out =
      std::string("ply\nformat ") + format + " 1.0\ncomment written by test_loaders\n" +
      "element material 2\nproperty list uchar float values\n" + "element vertex " +
      std::to_string(mesh.vertices.size()) + "\n" + "property uint8 red\nproperty " + t.coord +
      " x\nproperty " + t.coord + " y\n" + "property float64 quality\nproperty " + t.coord +
      " z\n" + "element face " + std::to_string(mesh.faces.size()) + "\n" + "property list " +
      t.count + " " + t.index + " vertex_indices\nproperty int16 flags\n" +
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  // One row per element instance: (type, value) pairs.
  std::vector<std::vector<std::pair<std::string, double>>> rows;
  rows.push_back({{"uchar", 2}, {"float", 0.5}, {"float", 1.5}});
  rows.push_back({{"uchar", 0}});
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto& v = mesh.vertices[i];
    rows.push_back({{"uchar", double(i % 256)},
                    {t.coord, v[0]},
                    {t.coord, v[1]},
                    {"double", 0.25 * i},
                    {t.coord, v[2]}});
  }
  for (const auto& f : mesh.faces) {
    std::vector<std::pair<std::string, double>> row{{t.count, double(f.size())}};
    for (int i : f) row.push_back({t.index, double(i)});
    row.push_back({"short", -7});
    rows.push_back(row);
  }
  rows.push_back({{"int", 0}, {"int", 1}});
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) {
      if (enc == Encoding::kAscii)
        out += (i ? " " : "") + ascii_value(row[i].first, row[i].second);
      else
        put_binary(out, row[i].first, row[i].second, enc == Encoding::kBig);
    }
    if (enc == Encoding::kAscii) out += "\n";
  }
  write_text(path, out);
}

// A bumpy grid of quads, with one triangle and one pentagon for good measure.
PlyMesh grid_mesh() {
  PlyMesh m;
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.vertices.push_back({0.1 * i - 0.3, 0.37 * j + 1e-3 * i * j, std::sin(0.5 * i + j)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i)
      m.faces.push_back({j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i});
  m.faces.push_back({0, 7, 14});
  m.faces.push_back({0, 1, 2, 8, 13});
  return m;
}

// What the loader must produce: coordinates rounded once to float (float32 data is written with
// enough digits to round-trip, float64 data exactly), polygons fan-triangulated.
std::vector<Triangle> fan(const PlyMesh& m, uint32_t material) {
  auto p = [&](int i) {
    const auto& v = m.vertices[static_cast<size_t>(i)];
    return Vec3(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  };
  std::vector<Triangle> tris;
  for (const auto& f : m.faces)
    for (size_t k = 2; k < f.size(); ++k)
      tris.push_back(Triangle{p(f[0]), p(f[k - 1]), p(f[k]), material});
  return tris;
}

std::vector<Triangle> load_ply_triangles(const fs::path& path, uint32_t material = 0) {
  Scene s;
  load_ply(path.string(), material, s);
  return s.triangles;
}

TEST(PlyLoader, BunnyHas69451Triangles) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const std::string path = (test::shared_scenes() / "bunny" / "bun_zipper.ply").string();
  Scene s;
  load_ply(path, 3, s);
  ASSERT_EQ(s.triangles.size(), 69451u);
  EXPECT_EQ(s.triangles[0].material, 3u);
  const AABB b = s.bounds();
  // The ground quad in the README sits at the bunny's min y
  EXPECT_NEAR(b.lo.y, 0.0329874f, 1e-6f);
}

TEST(PlyLoader, BunnyBinaryRewriteLoadsIdentically) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const auto ascii = load_ply_triangles(test::shared_scenes() / "bunny" / "bun_zipper.ply");
  PlyMesh m;  // three fresh vertices per triangle: exact floats survive the float32 rewrite
  for (const Triangle& t : ascii) {
    for (const Vec3& v : {t.v0, t.v1, t.v2}) m.vertices.push_back({v.x, v.y, v.z});
    const int i = static_cast<int>(m.vertices.size()) - 3;
    m.faces.push_back({i, i + 1, i + 2});
  }
  const fs::path dir = test::temp_dir("ply_bunny");
  write_ply(dir / "le.ply", m, Encoding::kLittle, {"float", "uchar", "uint"});
  write_ply(dir / "be.ply", m, Encoding::kBig, {"float", "uchar", "uint"});
  EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "le.ply"), ascii));
  EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "be.ply"), ascii));
  fs::remove_all(dir);
}

TEST(PlyLoader, AsciiAndBinaryEncodingsLoadIdentically) {
  const PlyMesh m = grid_mesh();
  const fs::path dir = test::temp_dir("ply_enc");
  const PlyTypes variants[] = {{"float", "uchar", "int"},
                               {"float32", "uint8", "uint32"},
                               {"double", "int16", "ushort"},
                               {"float64", "int", "int"}};
  for (const PlyTypes& t : variants) {
    SCOPED_TRACE(t.coord + " " + t.count + " " + t.index);
    write_ply(dir / "a.ply", m, Encoding::kAscii, t);
    write_ply(dir / "le.ply", m, Encoding::kLittle, t);
    write_ply(dir / "be.ply", m, Encoding::kBig, t);
    const auto want = fan(m, 5);
    EXPECT_EQ(want.size(), 25u * 2 + 1 + 3);
    EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "a.ply", 5), want));
    EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "le.ply", 5), want));
    EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "be.ply", 5), want));
  }
  fs::remove_all(dir);
}

TEST(PlyLoader, AppendsToTheScene) {
  const fs::path dir = test::temp_dir("ply_append");
  write_ply(dir / "a.ply", grid_mesh(), Encoding::kAscii);
  Scene s;
  s.triangles.push_back(Triangle{});
  load_ply((dir / "a.ply").string(), 0, s);
  EXPECT_EQ(s.triangles.size(), 1u + 54u);
  fs::remove_all(dir);
}

// A 4-vertex ASCII PLY: header lines 1-9, vertices on lines 10-13, faces from line 14.
const char* kSmallPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n";
const char* kSmallPlyData = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";

std::string small_ply(int faces, const std::string& data = kSmallPlyData) {
  char header[512];
  std::snprintf(header, sizeof header, kSmallPlyHeader, faces);
  return header + data;
}

TEST(PlyLoader, SmallAsciiFile) {
  const fs::path dir = test::temp_dir("ply_small");
  write_text(dir / "s.ply", small_ply(2));
  const auto tris = load_ply_triangles(dir / "s.ply");
  ASSERT_EQ(tris.size(), 2u);
  EXPECT_EQ(tris[1].v2, Vec3(0, 1, 0));
  // Windows line ends and trailing blank lines are fine.
  write_text(dir / "crlf.ply",
             std::regex_replace(small_ply(2), std::regex("\n"), "\r\n") + "\r\n\n");
  EXPECT_TRUE(same_triangles(load_ply_triangles(dir / "crlf.ply"), tris));
  fs::remove_all(dir);
}

TEST(PlyLoader, ElementCountWrongNamesFileAndLine) {
  const fs::path dir = test::temp_dir("ply_count");
  const std::string file = (dir / "count.ply").string();

  // Declares 3 faces, has 2: the file ends after line 15 (the last face).
  write_text(file, small_ply(3));
  std::string msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ":15: expected 3 faces, file ends after 2"), std::string::npos) << msg;

  // Declares 1 face, has 2: the second face (line 15) is data after the last element.
  write_text(file, small_ply(1));
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ":15:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("element counts are wrong"), std::string::npos) << msg;

  // Too many vertices declared: the first face line (14) does not fit the vertex properties.
  std::string text = small_ply(2);
  text.replace(text.find("vertex 4"), 8, "vertex 5");
  write_text(file, text);
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ":14:"), std::string::npos) << msg;

  // Truncated binary: names the element and byte offset.
  PlyMesh m = grid_mesh();
  write_ply(file, m, Encoding::kLittle);
  {
    std::ifstream in(file, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), {});
    // 2 materials, then 100 bytes
    write_text(file, data.substr(0, data.find("end_header\n") + 11 + 10 + 100));
  }
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ": vertex 4 at byte "), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 36 vertices, file ends after 4"), std::string::npos) << msg;

  // Binary with bytes left over.
  write_ply(file, m, Encoding::kBig);
  {
    std::ofstream out(file, std::ios::binary | std::ios::app);
    out << "xx";
  }
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ": 2 bytes of data after the last element"), std::string::npos) << msg;
  fs::remove_all(dir);
}

TEST(PlyLoader, BadHeaderNamesFileAndLine) {
  const fs::path dir = test::temp_dir("ply_header");
  const std::string file = (dir / "h.ply").string();
  struct Case {
    std::string from, to;  // edit of a good file
    int line;
  };
  const Case cases[] = {
      {"ply\n", "plx\n", 1},
      {"format ascii 1.0", "format ascii 2.0", 2},
      {"format ascii 1.0", "format text 1.0", 2},
      {"property float y", "property real y", 5},
      {"property list uchar int", "property list float int", 8},
      {"element face 2", "element face many", 7},
      {"property float z\n", "property float z\nbogus line\n", 7},
      {"element vertex 4\n", "property float w\nelement vertex 4\n", 3},
      {"end_header\n", "", 9},        // data read as header: '0' is no keyword
      {"format ascii 1.0\n", "", 8},  // reported at end_header
  };
  for (const Case& c : cases) {
    std::string text = small_ply(2);
    text.replace(text.find(c.from), c.from.size(), c.to);
    write_text(file, text);
    const std::string msg = input_error([&] {
      Scene s;
      load_ply(file, 0, s);
    });
    EXPECT_NE(msg.find(file + ":" + std::to_string(c.line) + ":"), std::string::npos)
        << c.to << " -> " << msg;
  }
  write_text(file, "ply\nformat ascii 1.0\nelement vertex 1\n");
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file, 0, s);
            }).find(file + ":3: the header has no 'end_header'"),
            std::string::npos);
  // Missing x/y/z or vertex_indices: named at the element's header line.
  std::string text = small_ply(2);
  text.replace(text.find("property float z"), 16, "property float w");
  write_text(file, text);
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file, 0, s);
            }).find(file + ":3: element 'vertex' needs"),
            std::string::npos);
  // Not there at all.
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file + ".missing", 0, s);
            }).find(file + ".missing"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(PlyLoader, IndexOutOfRangeNamesFileAndLine) {
  const fs::path dir = test::temp_dir("ply_index");
  const std::string file = (dir / "i.ply").string();
  write_text(file, small_ply(2, "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 4\n"));
  std::string msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ":15: face 1: vertex index 4 out of range (4 vertices)"),
            std::string::npos)
      << msg;
  write_text(file, small_ply(2, "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 -1\n3 0 2 3\n"));
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ":14: face 0: vertex index -1 out of range"), std::string::npos) << msg;

  PlyMesh m = grid_mesh();
  m.faces[3][1] = 36;
  write_ply(file, m, Encoding::kBig);
  msg = input_error([&] {
    Scene s;
    load_ply(file, 0, s);
  });
  EXPECT_NE(msg.find(file + ": face 3 at byte "), std::string::npos) << msg;
  EXPECT_NE(msg.find("vertex index 36 out of range (36 vertices)"), std::string::npos) << msg;
  fs::remove_all(dir);
}

TEST(PlyLoader, BadValuesNameTheLine) {
  const fs::path dir = test::temp_dir("ply_values");
  const std::string file = (dir / "v.ply").string();
  write_text(file, small_ply(2, "0 0 0\n1 0 0\n1 x 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"));
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file, 0, s);
            }).find(file + ":12: vertex 2: property 'y'"),
            std::string::npos);
  write_text(file, small_ply(2, "0 0 0\n1 0 0\n1 1 0\n0 1 0 7\n3 0 1 2\n3 0 2 3\n"));
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file, 0, s);
            }).find(file + ":13: vertex 3: unexpected value"),
            std::string::npos);
  write_text(file, small_ply(2, "0 0 0\n1 0 0\n1 1 0\n0 1 0\n300 0 1 2\n3 0 2 3\n"));
  EXPECT_NE(input_error([&] {
              Scene s;
              load_ply(file, 0, s);
            }).find(file + ":14: face 0: property 'vertex_indices'"),
            std::string::npos);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST(ObjLoader, LoadsFacesAndMtlMaterials) {
  const fs::path dir = test::temp_dir("obj");
  write_text(dir / "m.mtl",
             "newmtl red\nKd 1 0 0\nKs 0.5 0.25 0.125\nNs 32\nnewmtl blue\nKd 0 0 1\n");
  write_text(
      dir / "m.obj",
      "# test\nmtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nusemtl red\nf "
      "1//1 2//1 3//1 4//1\nusemtl blue\nf 1 2 5\ng other\nusemtl none\nf -3 -2 -1\n");
  Scene s;
  s.add_material(Material{});  // loaders append after what is there
  load_obj((dir / "m.obj").string(), s);
  ASSERT_EQ(s.triangles.size(), 4u);
  ASSERT_EQ(s.materials.size(), 4u);  // existing, red, blue, default
  const Material& red = s.materials[s.triangles[0].material];
  EXPECT_EQ(red.diffuse, Vec3(1, 0, 0));
  EXPECT_EQ(red.specular, Vec3(0.5f, 0.25f, 0.125f));
  EXPECT_EQ(red.shininess, 32.f);
  EXPECT_EQ(s.triangles[0].material, 1u);
  EXPECT_EQ(s.triangles[1].material, 1u);
  EXPECT_EQ(s.triangles[2].material, 2u);
  EXPECT_EQ(s.materials[2].diffuse, Vec3(0, 0, 1));
  EXPECT_EQ(s.triangles[3].material, 3u);  // unknown material -> default
  // The quad is fan-triangulated: (1 2 3) (1 3 4).
  EXPECT_EQ(s.triangles[0].v0, Vec3(0, 0, 0));
  EXPECT_EQ(s.triangles[0].v1, Vec3(1, 0, 0));
  EXPECT_EQ(s.triangles[0].v2, Vec3(1, 1, 0));
  EXPECT_EQ(s.triangles[1].v2, Vec3(0, 1, 0));
  EXPECT_EQ(s.triangles[2].v2, Vec3(0, 0, 1));
  // Negative indices count back from the last vertex.
  EXPECT_EQ(s.triangles[3].v0, Vec3(1, 1, 0));
  EXPECT_EQ(s.triangles[3].v2, Vec3(0, 0, 1));
  fs::remove_all(dir);
}

TEST(ObjLoader, MissingMtlIsOnlyAWarning) {
  const fs::path dir = test::temp_dir("obj_nomtl");
  write_text(dir / "m.obj", "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
  Scene s;
  load_obj((dir / "m.obj").string(), s);
  ASSERT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].diffuse, Material{}.diffuse);
  fs::remove_all(dir);
}

TEST(ObjLoader, IndexOutOfRangeNamesFileAndLine) {
  const fs::path dir = test::temp_dir("obj_bad");
  const std::string file = (dir / "bad.obj").string();
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\nf 1 2 9\nf 1 2 3\n");
  std::string msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":6: face vertex index 9 is out of range (the file has 3 vertices)"),
            std::string::npos)
      << msg;
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":4: face vertex index -4"), std::string::npos) << msg;
  write_text(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");  // tinyobjloader's own error
  msg = input_error([&] {
    Scene s;
    load_obj(file, s);
  });
  EXPECT_NE(msg.find(file + ":4:"), std::string::npos) << msg;
  msg = input_error([&] {
    Scene s;
    load_obj(file + ".missing", s);
  });
  EXPECT_NE(msg.find(file + ".missing: cannot open"), std::string::npos) << msg;
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// glTF

// Hand-rolled transforms for the expected values (independent of the loader's glm code).
struct Trs {
  std::array<double, 3> t{0, 0, 0};
  std::array<double, 4> r{0, 0, 0, 1};  // x y z w
  std::array<double, 3> s{1, 1, 1};
  Vec3 apply(const Vec3& p) const {
    const double v[3] = {p.x * s[0], p.y * s[1], p.z * s[2]};
    // v' = v + 2w (q x v) + 2 q x (q x v)
    const double q[3] = {r[0], r[1], r[2]}, w = r[3];
    const double c1[3] = {q[1] * v[2] - q[2] * v[1], q[2] * v[0] - q[0] * v[2],
                          q[0] * v[1] - q[1] * v[0]};
    const double c2[3] = {q[1] * c1[2] - q[2] * c1[1], q[2] * c1[0] - q[0] * c1[2],
                          q[0] * c1[1] - q[1] * c1[0]};
    return Vec3(static_cast<float>(v[0] + 2 * w * c1[0] + 2 * c2[0] + t[0]),
                static_cast<float>(v[1] + 2 * w * c1[1] + 2 * c2[1] + t[1]),
                static_cast<float>(v[2] + 2 * w * c1[2] + 2 * c2[2] + t[2]));
  }
};

Vec3 apply_matrix(const std::vector<double>& m, const Vec3& p) {  // column-major 4x4
  return Vec3(static_cast<float>(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12]),
              static_cast<float>(m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13]),
              static_cast<float>(m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]));
}

// The test scene: root node 0 (TRS) with children 1 (mesh 0 = indexed quad with strided
// positions, translated) and 2 (matrix; mesh 1 = a plain triangle, a u8-indexed strip and a
// skipped POINTS primitive) whose child 3 carries a point light; root node 4 holds the camera.
struct GltfFixture {
  tinygltf::Model model;
  Trs root, quad_node, light_node, camera_node;
  std::vector<double> matrix;
  std::vector<Vec3> quad, tri, strip;  // local positions

  GltfFixture() {
    root.t = {1, 2, 3};
    root.r = {0, std::sin(M_PI / 4), 0, std::cos(M_PI / 4)};  // 90 degrees about +Y
    root.s = {2, 2, 2};
    quad_node.t = {0, 0, -1};
    light_node.t = {0, 5, 0};
    camera_node.t = {0, 1, 10};
    camera_node.r = {std::sin(-M_PI / 36), 0, 0, std::cos(-M_PI / 36)};  // -10 degrees about +X
    // 90 degrees about +Z, then x += 5
    matrix = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1};
    quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    tri = {{0, 0, 0}, {0, 2, 0}, {0, 0, 2}};
    strip = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 2}};

    std::vector<unsigned char> data;
    auto add_view = [&](const void* p, size_t n, size_t stride, int target) {
      while (data.size() % 4) data.push_back(0);
      tinygltf::BufferView v;
      v.buffer = 0;
      v.byteOffset = data.size();
      v.byteLength = n;
      v.byteStride = stride;
      v.target = target;
      data.insert(data.end(), static_cast<const unsigned char*>(p),
                  static_cast<const unsigned char*>(p) + n);
      model.bufferViews.push_back(v);
      return static_cast<int>(model.bufferViews.size() - 1);
    };
    auto add_accessor = [&](int view, int component, int type, size_t count) {
      tinygltf::Accessor a;
      a.bufferView = view;
      a.componentType = component;
      a.type = type;
      a.count = count;
      model.accessors.push_back(a);
      return static_cast<int>(model.accessors.size() - 1);
    };
    auto positions = [&](const std::vector<Vec3>& pts, size_t stride) {
      std::vector<float> f(pts.size() * stride / 4, -99.f);  // padding that must not be read
      for (size_t i = 0; i < pts.size(); ++i) std::memcpy(&f[i * stride / 4], &pts[i], 12);
      return add_accessor(
          add_view(f.data(), f.size() * 4, stride == 12 ? 0 : stride, TINYGLTF_TARGET_ARRAY_BUFFER),
          TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, pts.size());
    };

    const uint16_t quad_idx[6] = {0, 1, 2, 0, 2, 3};
    const uint8_t strip_idx[4] = {0, 1, 2, 3};
    tinygltf::Primitive pq;
    pq.attributes["POSITION"] = positions(quad, 16);
    pq.indices =
        add_accessor(add_view(quad_idx, sizeof quad_idx, 0, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, 6);
    pq.material = 0;
    pq.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Primitive pt;
    pt.attributes["POSITION"] = positions(tri, 12);
    pt.material = 1;
    pt.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Primitive ps;
    ps.attributes["POSITION"] = positions(strip, 12);
    ps.indices =
        add_accessor(add_view(strip_idx, sizeof strip_idx, 0, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, 4);
    ps.material = 1;
    ps.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
    tinygltf::Primitive pp = pt;
    pp.mode = TINYGLTF_MODE_POINTS;
    tinygltf::Buffer buffer;
    buffer.data = data;
    model.buffers.push_back(buffer);

    tinygltf::Mesh m0, m1;
    m0.primitives = {pq};
    m1.primitives = {pt, ps, pp};
    model.meshes = {m0, m1};
    tinygltf::Material red, green;
    red.pbrMetallicRoughness.baseColorFactor = {1, 0, 0, 1};
    green.pbrMetallicRoughness.baseColorFactor = {0, 1, 0, 0.5};
    model.materials = {red, green};

    auto trs_node = [](const Trs& t) {
      tinygltf::Node n;
      n.translation = {t.t[0], t.t[1], t.t[2]};
      n.rotation = {t.r[0], t.r[1], t.r[2], t.r[3]};
      n.scale = {t.s[0], t.s[1], t.s[2]};
      return n;
    };
    tinygltf::Node n0 = trs_node(root), n1 = trs_node(quad_node), n2, n3,
                   n4 = trs_node(camera_node);
    n0.children = {1, 2};
    n1.mesh = 0;
    n2.matrix = matrix;
    n2.mesh = 1;
    n2.children = {3};
    n3.translation = {light_node.t[0], light_node.t[1], light_node.t[2]};
    n3.extensions["KHR_lights_punctual"] =
        tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(0)}});
    n4.camera = 0;
    model.nodes = {n0, n1, n2, n3, n4};

    tinygltf::Light light;
    light.type = "point";
    light.color = {1, 0.5, 0.25};
    light.intensity = 3;
    model.lights = {light};
    tinygltf::Camera cam;
    cam.type = "perspective";
    cam.perspective.yfov = 0.8;
    cam.perspective.znear = 0.1;
    cam.perspective.aspectRatio = 1.5;
    model.cameras = {cam};
    tinygltf::Scene scene;
    scene.nodes = {0, 4};
    model.scenes = {scene};
    model.defaultScene = 0;
    model.asset.version = "2.0";
  }

  std::vector<Triangle> expected() const {
    std::vector<Triangle> out;
    auto quad_world = [&](const Vec3& p) { return root.apply(quad_node.apply(p)); };
    auto mesh1_world = [&](const Vec3& p) { return root.apply(apply_matrix(matrix, p)); };
    out.push_back({quad_world(quad[0]), quad_world(quad[1]), quad_world(quad[2]), 0});
    out.push_back({quad_world(quad[0]), quad_world(quad[2]), quad_world(quad[3]), 0});
    out.push_back({mesh1_world(tri[0]), mesh1_world(tri[1]), mesh1_world(tri[2]), 1});
    out.push_back({mesh1_world(strip[0]), mesh1_world(strip[1]), mesh1_world(strip[2]), 1});
    out.push_back({mesh1_world(strip[1]), mesh1_world(strip[3]), mesh1_world(strip[2]), 1});
    return out;
  }
  Vec3 light_position() const {
    return root.apply(apply_matrix(matrix, light_node.apply(Vec3(0.f))));
  }
};

void expect_fixture_scene(const GltfFixture& f, const Scene& s) {
  const auto want = f.expected();
  ASSERT_EQ(s.triangles.size(), want.size());
  ASSERT_EQ(s.materials.size(), 2u);
  for (size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("triangle " + std::to_string(i));
    expect_near(s.triangles[i].v0, want[i].v0);
    expect_near(s.triangles[i].v1, want[i].v1);
    expect_near(s.triangles[i].v2, want[i].v2);
    EXPECT_EQ(s.materials[s.triangles[i].material].diffuse,
              want[i].material ? Vec3(0, 1, 0) : Vec3(1, 0, 0));
  }
  ASSERT_EQ(s.lights.size(), 1u);
  expect_near(s.lights[0].position, f.light_position());
  EXPECT_EQ(s.lights[0].color, Vec3(1, 0.5f, 0.25f));
  ASSERT_TRUE(s.has_camera);
  expect_near(s.camera.eye, Vec3(0, 1, 10));
  const float a = static_cast<float>(M_PI / 18);  // the camera is pitched 10 degrees down
  expect_near(s.camera.dir, Vec3(0, -std::sin(a), -std::cos(a)));
  expect_near(s.camera.up, Vec3(0, std::cos(a), -std::sin(a)));
  EXPECT_NEAR(s.camera.vfov_deg, 0.8 * 180 / M_PI, 1e-4);
}

TEST(GltfLoader, GltfAndGlbLoadTheSameWorldSpaceScene) {
  GltfFixture f;
  const fs::path dir = test::temp_dir("gltf");
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.gltf").string(), true, true, true, false));
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.glb").string(), true, true, false, true));
  Scene a, b;
  load_gltf((dir / "s.gltf").string(), a);
  load_gltf((dir / "s.glb").string(), b);
  {
    SCOPED_TRACE(".gltf");
    expect_fixture_scene(f, a);
  }
  {
    SCOPED_TRACE(".glb");
    expect_fixture_scene(f, b);
  }
  EXPECT_TRUE(same_triangles(a.triangles, b.triangles));
  fs::remove_all(dir);
}

TEST(GltfLoader, NoSceneMeansAllRootNodes) {
  GltfFixture f;
  f.model.scenes.clear();
  f.model.defaultScene = -1;
  const fs::path dir = test::temp_dir("gltf_noscene");
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(
      writer.WriteGltfSceneToFile(&f.model, (dir / "s.gltf").string(), true, true, true, false));
  Scene s;
  load_gltf((dir / "s.gltf").string(), s);
  expect_fixture_scene(f, s);
  fs::remove_all(dir);
}

TEST(GltfLoader, ErrorsNameTheFile) {
  const fs::path dir = test::temp_dir("gltf_bad");
  const std::string file = (dir / "bad.gltf").string();
  write_text(file, "{ \"asset\": {\"version\": \"2.0\"}, \"nodes\": [ ");
  std::string msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_EQ(msg.rfind(file + ": tinygltf: ", 0), 0u) << msg;

  GltfFixture f;
  f.model.nodes[1].mesh = 7;
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&f.model, file, true, true, true, false));
  msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_EQ(msg.rfind(file + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find("mesh 7 out of range"), std::string::npos) << msg;

  GltfFixture g;
  g.model.nodes[2].children = {3, 0};  // a cycle
  ASSERT_TRUE(writer.WriteGltfSceneToFile(&g.model, file, true, true, true, false));
  msg = input_error([&] {
    Scene s;
    load_gltf(file, s);
  });
  EXPECT_NE(msg.find("cycle"), std::string::npos) << msg;

  msg = input_error([&] {
    Scene s;
    load_gltf(file + ".missing.glb", s);
  });
  EXPECT_NE(msg.find(file + ".missing.glb"), std::string::npos) << msg;
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// Procedural city

size_t city_triangles(const CityParams& p) {
  const size_t b = static_cast<size_t>(p.blocks), s = static_cast<size_t>(p.sphere_segments);
  return 2 + 10 * b * b + ((b * b + 1) / 2 + b) * 2 * s * (s / 2 - 1);
}

TEST(Procedural, SameSeedSameTrianglesDifferentSeedDifferent) {
  Scene a, b, c;
  make_city(CityParams{}, a);
  make_city(CityParams{}, b);
  CityParams other;
  other.seed = 2;
  make_city(other, c);
  EXPECT_TRUE(same_triangles(a.triangles, b.triangles));
  EXPECT_EQ(a.triangles.size(), c.triangles.size());
  EXPECT_FALSE(same_triangles(a.triangles, c.triangles));
}

// Bit-identical everywhere: a hash of the default city's bits, fixed when the generator was
// written. Changing the city on purpose means updating it.
TEST(Procedural, DefaultCityHashIsStable) {
  Scene s;
  make_city(CityParams{}, s);
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  auto mix = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i)
      h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  for (const Triangle& t : s.triangles) {
    mix(&t.v0, 12);
    mix(&t.v1, 12);
    mix(&t.v2, 12);
    mix(&t.material, 4);
  }
  for (const Light& l : s.lights) mix(&l.position, 12);
  mix(&s.camera.eye, 12);
  mix(&s.camera.dir, 12);
  std::printf("default city hash: 0x%016llx\n", static_cast<unsigned long long>(h));
  EXPECT_EQ(h, 0xfaceea412c9c2552ull);
}

TEST(Procedural, TriangleCountFollowsParams) {
  for (int blocks : {1, 2, 5, 8})
    for (int seg : {4, 5, 16, 33}) {
      CityParams p;
      p.blocks = blocks;
      p.sphere_segments = seg;
      p.lights = 1 + blocks % 15;
      Scene s;
      make_city(p, s);
      SCOPED_TRACE("blocks " + std::to_string(blocks) + " segments " + std::to_string(seg));
      EXPECT_EQ(s.triangles.size(), city_triangles(p));
      EXPECT_EQ(s.lights.size(), static_cast<size_t>(p.lights));
      // Everything inside the city's footprint, on or above the ground.
      const float w = 10.f * blocks + 3.f;
      const AABB b = s.bounds();
      EXPECT_GE(b.lo.x, 0.f);
      EXPECT_GE(b.lo.y, 0.f);
      EXPECT_GE(b.lo.z, 0.f);
      EXPECT_LE(b.hi.x, w);
      EXPECT_LE(b.hi.z, w);
      for (const Light& l : s.lights) EXPECT_GT(l.position.y, b.hi.y);
    }
}

TEST(Procedural, SceneSetup) {
  Scene s;
  make_city(CityParams{}, s);
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 360);
  EXPECT_TRUE(s.has_camera);
  EXPECT_NEAR(glm::length(s.camera.dir), 1.f, 1e-6f);
  EXPECT_LT(s.camera.dir.y, 0.f);  // looking down at the city
  bool mirror = false;
  for (const Material& m : s.materials) mirror |= m.reflectance == 0.5f;
  EXPECT_TRUE(mirror);
  for (const Triangle& t : s.triangles) ASSERT_LT(t.material, s.materials.size());
}

TEST(Procedural, ParamsAreValidated) {
  auto bad = [](std::function<void(CityParams&)> edit) {
    CityParams p;
    edit(p);
    Scene s;
    return input_error([&] { make_city(p, s); });
  };
  EXPECT_NE(bad([](CityParams& p) { p.blocks = 0; }).find("blocks"), std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.blocks = 65; }).find("blocks"), std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.sphere_segments = 3; }).find("sphere_segments"),
            std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.sphere_segments = 257; }).find("sphere_segments"),
            std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.lights = 0; }).find("lights"), std::string::npos);
  EXPECT_NE(bad([](CityParams& p) { p.lights = 16; }).find("lights"), std::string::npos);
}

}  // namespace
}  // namespace rtsim
