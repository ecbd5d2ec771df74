// The PLY loader: the bunny (ASCII, and rewritten binary), every encoding and type loading the
// same triangles, appending to a scene, and bad files named by file and line.
#include "common/error.h"
#include "scene_loader/gltf_loader.h"
#include "scene_loader/obj_loader.h"
#include "scene_loader/ply_loader.h"
#include "scene_loader/procedural.h"
#include "tests/scene_loader/loader_test_util.h"
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

using namespace loader_test;

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

}  // namespace
}  // namespace rtsim
