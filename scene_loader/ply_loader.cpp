#include "scene_loader/ply_loader.h"

#include "common/error.h"
#include "scene_loader/ply_header.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

namespace rtsim {
namespace {

using namespace ply;

// ---------------------------------------------------------------------------------------------
// Data readers. Both offer begin/read/finish per element instance and fail() for errors, so one
// templated loop reads either encoding.

// ASCII: one element instance per line, values separated by blanks; blank lines are skipped.
class AsciiReader {
 public:
  AsciiReader(const std::string& path, const char* p, const char* end, long line)
      : path_(path), p_(p), end_(end), line_(line), last_line_(line - 1) {}

  // Moves to the next non-blank line; false at end of file.
  bool begin(const Element& e, uint64_t index) {
    elem_ = &e;
    index_ = index;
    skip_blank_lines();
    if (p_ == end_) return false;
    last_line_ = line_;
    return true;
  }

  double read(Type t, const Property& prop) {
    while (p_ != end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r')) ++p_;
    const char* start = p_;
    while (p_ != end_ && *p_ != ' ' && *p_ != '\t' && *p_ != '\r' && *p_ != '\n') ++p_;
    if (p_ == start)
      fail("the line ends before property '" + prop.name +
           "' is complete (wrong element count or property list?)");
    return parse(t, start, p_, prop);
  }

  // The instance must end its line.
  void finish() {
    while (p_ != end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r')) ++p_;
    if (p_ == end_) return;
    if (*p_ != '\n')
      fail("unexpected value " + quote(std::string_view(p_, std::min<size_t>(20, end_ - p_))) +
           " after the last property (wrong element count or property list?)");
    ++p_;
    ++line_;
  }

  void at_end(const Header& h) {
    skip_blank_lines();
    if (p_ != end_) {
      const Element& last = h.elements.back();
      throw_at_line(path_, line_,
                    "data after the last element (the header declares " +
                        std::to_string(last.count) + " " + plural(last) +
                        "): the element counts are wrong");
    }
  }

  [[noreturn]] void fail(const std::string& msg) const {
    throw_at_line(path_, line_, elem_->name + " " + std::to_string(index_) + ": " + msg);
  }
  // Names the last line holding data: that is where the count stops matching.
  [[noreturn]] void fail_eof() const {
    throw_at_line(path_, last_line_,
                  "expected " + std::to_string(elem_->count) + " " + plural(*elem_) +
                      ", file ends after " + std::to_string(index_));
  }

 private:
  void skip_blank_lines() {
    for (;;) {
      const char* q = p_;
      while (q != end_ && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
      if (q == end_) {
        p_ = q;
        return;
      }
      if (*q != '\n') return;
      p_ = q + 1;
      ++line_;
    }
  }

  double parse(Type t, const char* b, const char* e, const Property& prop) const {
    std::from_chars_result r{};
    double value = 0;
    if (t == Type::F32) {
      float f = 0;
      r = std::from_chars(b, e, f);
      value = f;
    } else if (t == Type::F64) {
      r = std::from_chars(b, e, value);
    } else {
      long long i = 0;
      r = std::from_chars(b, e, i);
      value = static_cast<double>(i);
    }
    if (r.ec != std::errc() || r.ptr != e)
      fail("property '" + prop.name + "': " + quote(std::string_view(b, e - b)) +
           " is not a valid " + info(t).alias);
    if (!is_float(t) && (value < info(t).lo || value > info(t).hi))
      fail("property '" + prop.name + "': " + quote(std::string_view(b, e - b)) +
           " does not fit in " + info(t).alias);
    return value;
  }

  const std::string& path_;
  const char* p_;
  const char* const end_;
  long line_;
  long last_line_;  // line of the last element instance begun
  const Element* elem_ = nullptr;
  uint64_t index_ = 0;
};

// Binary: packed values in the file's byte order.
class BinaryReader {
 public:
  BinaryReader(const std::string& path, const char* begin, const char* p, const char* end,
               bool big_endian)
      : path_(path), begin_(begin), p_(p), end_(end) {
    const bool host_big = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;
    swap_ = host_big != big_endian;
  }

  bool begin(const Element& e, uint64_t index) {
    elem_ = &e;
    index_ = index;
    instance_ = p_;
    return p_ != end_;
  }

  double read(Type t, const Property&) {
    const int size = info(t).size;
    if (end_ - p_ < size) fail_eof();
    unsigned char b[8];
    std::memcpy(b, p_, size);
    p_ += size;
    if (swap_) std::reverse(b, b + size);
    switch (t) {
      case Type::I8: return as<int8_t>(b);
      case Type::U8: return as<uint8_t>(b);
      case Type::I16: return as<int16_t>(b);
      case Type::U16: return as<uint16_t>(b);
      case Type::I32: return as<int32_t>(b);
      case Type::U32: return as<uint32_t>(b);
      case Type::F32: return as<float>(b);
      case Type::F64: return as<double>(b);
    }
    return 0;
  }

  void finish() {}

  void at_end(const Header& h) {
    if (p_ != end_) {
      const Element& last = h.elements.back();
      throw_at_line(path_, 0,
                    std::to_string(end_ - p_) + " bytes of data after the last element at byte " +
                        std::to_string(p_ - begin_) + " (the header declares " +
                        std::to_string(last.count) + " " + plural(last) +
                        "): the element counts are wrong");
    }
  }

  [[noreturn]] void fail(const std::string& msg) const { throw_at_line(path_, 0, where() + msg); }
  [[noreturn]] void fail_eof() const {
    throw_at_line(path_, 0,
                  where() + "expected " + std::to_string(elem_->count) + " " + plural(*elem_) +
                      ", file ends after " + std::to_string(index_));
  }

 private:
  template <class T>
  static double as(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }
  std::string where() const {
    return elem_->name + " " + std::to_string(index_) + " at byte " +
           std::to_string(instance_ - begin_) + ": ";
  }

  const std::string& path_;
  const char* const begin_;
  const char* p_;
  const char* const end_;
  bool swap_ = false;
  const Element* elem_ = nullptr;
  uint64_t index_ = 0;
  const char* instance_ = nullptr;
};

// ---------------------------------------------------------------------------------------------
// What the loader takes from the elements.

struct Layout {
  const Element* vertex = nullptr;
  int x = -1, y = -1, z = -1;  // property indices in the vertex element
  const Element* face = nullptr;
  int indices = -1;  // list property index in the face element
};

Layout find_layout(const std::string& path, const Header& h) {
  Layout l;
  for (const Element& e : h.elements) {
    if (e.name == "vertex" && !l.vertex) {
      l.vertex = &e;
      for (size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        int* slot = p.name == "x" ? &l.x : p.name == "y" ? &l.y : p.name == "z" ? &l.z : nullptr;
        if (!slot) continue;
        if (p.is_list)
          throw_at_line(path, e.line,
                        "vertex property '" + p.name + "' must be a scalar, not a list");
        *slot = static_cast<int>(i);
      }
      if (l.x < 0 || l.y < 0 || l.z < 0)
        throw_at_line(path, e.line, "element 'vertex' needs properties x, y and z");
      if (e.count > 0xffffffffull) throw_at_line(path, e.line, "more than 2^32-1 vertices");
    } else if (e.name == "face" && !l.face) {
      l.face = &e;
      for (size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
        if (!p.is_list || is_float(p.type))
          throw_at_line(path, e.line,
                        "face property '" + p.name + "' must be a list of an integer type");
        l.indices = static_cast<int>(i);
        break;
      }
      if (l.indices < 0)
        throw_at_line(path, e.line,
                      "element 'face' needs a list property vertex_indices (or vertex_index)");
    }
  }
  if (!l.vertex) throw_at_line(path, 0, "no 'vertex' element in the header");
  if (!l.face)
    throw_at_line(path, 0,
                  "no 'face' element in the header (a point cloud has no triangles to trace)");
  return l;
}

struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> triangles;  // 3 vertex indices each
};

template <class Reader>
void read_data(Reader& r, const Header& h, const Layout& l, size_t data_bytes, Mesh& mesh) {
  const double nverts = static_cast<double>(l.vertex->count);
  // Grown as read: a huge count in a corrupt header must end in an error, not in an allocation.
  mesh.vertices.reserve(std::min<uint64_t>(l.vertex->count, data_bytes / 3));
  std::vector<uint32_t> polygon;
  for (const Element& e : h.elements) {
    const bool is_vertex = &e == l.vertex, is_face = &e == l.face;
    for (uint64_t i = 0; i < e.count; ++i) {
      if (!r.begin(e, i)) r.fail_eof();
      if (is_vertex) mesh.vertices.emplace_back(0.f);
      for (size_t k = 0; k < e.props.size(); ++k) {
        const Property& p = e.props[k];
        const int slot = static_cast<int>(k);
        if (!p.is_list) {
          const double v = r.read(p.type, p);
          if (is_vertex) {
            if (slot == l.x)
              mesh.vertices.back().x = static_cast<float>(v);
            else if (slot == l.y)
              mesh.vertices.back().y = static_cast<float>(v);
            else if (slot == l.z)
              mesh.vertices.back().z = static_cast<float>(v);
          }
          continue;
        }
        const double n = r.read(p.count_type, p);
        if (n < 0) r.fail("list '" + p.name + "' has a negative length");
        const uint64_t count = static_cast<uint64_t>(n);
        if (!is_face || slot != l.indices) {
          for (uint64_t j = 0; j < count; ++j) r.read(p.type, p);
          continue;
        }
        polygon.clear();
        for (uint64_t j = 0; j < count; ++j) {
          const double v = r.read(p.type, p);
          if (v < 0 || v >= nverts)
            r.fail("vertex index " + std::to_string(static_cast<long long>(v)) + " out of range (" +
                   std::to_string(l.vertex->count) + " vertices)");
          polygon.push_back(static_cast<uint32_t>(v));
        }
        // Fan triangulation: exact for the convex polygons scanners and modellers write.
        for (size_t j = 2; j < polygon.size(); ++j) {
          mesh.triangles.push_back(polygon[0]);
          mesh.triangles.push_back(polygon[j - 1]);
          mesh.triangles.push_back(polygon[j]);
        }
      }
      r.finish();
    }
  }
  r.at_end(h);
}

}  // namespace

void load_ply(const std::string& path, uint32_t material, Scene& scene) {
  const std::string data = read_whole_file(path);
  const Header h = parse_header(path, data);
  const Layout layout = find_layout(path, h);

  Mesh mesh;
  const char* begin = data.data();
  const char* end = data.data() + data.size();
  if (h.format == Format::kAscii) {
    AsciiReader r(path, begin + h.data_offset, end, h.data_line);
    read_data(r, h, layout, data.size(), mesh);
  } else {
    BinaryReader r(path, begin, begin + h.data_offset, end, h.format == Format::kBinaryBig);
    read_data(r, h, layout, data.size(), mesh);
  }

  scene.triangles.reserve(scene.triangles.size() + mesh.triangles.size() / 3);
  for (size_t i = 0; i < mesh.triangles.size(); i += 3) {
    scene.triangles.push_back(Triangle{mesh.vertices[mesh.triangles[i]],
                                       mesh.vertices[mesh.triangles[i + 1]],
                                       mesh.vertices[mesh.triangles[i + 2]], material});
  }
}

}  // namespace rtsim
