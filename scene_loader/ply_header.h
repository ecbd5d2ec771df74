// The PLY header (format, elements and their properties) as the PLY loader reads it, and the
// helpers its messages share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rtsim::ply {

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

struct TypeInfo {
  const char* name;   // PLY 1.0 name
  const char* alias;  // sized name most writers use today
  int size;           // bytes in binary data
  double lo, hi;      // value range (integers only)
};

// Indexed by Type.
inline constexpr TypeInfo kTypes[] = {
    {"char", "int8", 1, -128.0, 127.0},
    {"uchar", "uint8", 1, 0.0, 255.0},
    {"short", "int16", 2, -32768.0, 32767.0},
    {"ushort", "uint16", 2, 0.0, 65535.0},
    {"int", "int32", 4, -2147483648.0, 2147483647.0},
    {"uint", "uint32", 4, 0.0, 4294967295.0},
    {"float", "float32", 4, 0.0, 0.0},
    {"double", "float64", 8, 0.0, 0.0},
};

inline const TypeInfo& info(Type t) { return kTypes[static_cast<int>(t)]; }
inline bool is_float(Type t) { return t == Type::F32 || t == Type::F64; }

struct Property {
  std::string name;
  Type type = Type::F32;  // scalar type, or the item type of a list
  bool is_list = false;
  Type count_type = Type::U8;  // lists only
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
  long line = 0;  // header line declaring it
};

enum class Format { kAscii, kBinaryLittle, kBinaryBig };

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  size_t data_offset = 0;  // first byte after "end_header\n"
  long data_line = 0;      // line number of the first data line (ASCII)
};

// "vertices"/"faces" as the error messages in the interface promise, "'name' elements" otherwise.
std::string plural(const Element& e);
// A short, printable excerpt of untrusted text for an error message.
std::string quote(std::string_view s);
// The file's bytes; an input error naming it when it cannot be read.
std::string read_whole_file(const std::string& path);
// The header at the start of `data` (the file `path`); an input error naming the line otherwise.
Header parse_header(const std::string& path, const std::string& data);

}  // namespace rtsim::ply
