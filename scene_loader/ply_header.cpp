#include "scene_loader/ply_header.h"

#include "common/error.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>

namespace rtsim::ply {

namespace {

bool parse_type(std::string_view s, Type& out) {
  for (int i = 0; i < 8; ++i) {
    if (s == kTypes[i].name || s == kTypes[i].alias) {
      out = static_cast<Type>(i);
      return true;
    }
  }
  return false;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}

}  // namespace

// "vertices"/"faces" as the error messages in the interface promise, "'name' elements" otherwise.
std::string plural(const Element& e) {
  if (e.name == "vertex") return "vertices";
  if (e.name == "face") return "faces";
  return "'" + e.name + "' elements";
}

// A short, printable excerpt of untrusted text for an error message.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (char c : s.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
  if (s.size() > 40) out += "...";
  return out + "'";
}

std::string read_whole_file(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw_at_line(path, 0, std::string("cannot open file: ") + std::strerror(errno));
  std::string data;
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) data.append(buf, n);
  if (std::ferror(f.get())) throw_at_line(path, 0, "read error");
  return data;
}

namespace {

using Words = std::vector<std::string_view>;
using Fail = std::function<void(const std::string&)>;  // throws, naming the header line

void parse_format(const Words& w, Header& h, const Fail& fail) {
  if (w.size() != 3) fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
  if (w[1] == "ascii")
    h.format = Format::kAscii;
  else if (w[1] == "binary_little_endian")
    h.format = Format::kBinaryLittle;
  else if (w[1] == "binary_big_endian")
    h.format = Format::kBinaryBig;
  else
    fail("unknown format " + quote(w[1]) +
         ", expected ascii, binary_little_endian or binary_big_endian");
  if (w[2] != "1.0") fail("unsupported PLY version " + quote(w[2]) + ", expected 1.0");
}

Element parse_element(const Words& w, long line_no, const Fail& fail) {
  Element e;
  if (w.size() != 3) fail("expected 'element NAME COUNT'");
  const auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
  if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size())
    fail("element count " + quote(w[2]) + " is not a non-negative integer");
  e.name = std::string(w[1]);
  e.line = line_no;
  return e;
}

Property parse_property(const Words& w, const Fail& fail) {
  Property prop;
  if (w.size() >= 2 && w[1] == "list") {
    if (w.size() != 5) fail("expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
    if (!parse_type(w[2], prop.count_type)) fail("unknown list count type " + quote(w[2]));
    if (!parse_type(w[3], prop.type)) fail("unknown list item type " + quote(w[3]));
    if (is_float(prop.count_type))
      fail("list count type " + quote(w[2]) + " must be an integer type");
    prop.is_list = true;
    prop.name = std::string(w[4]);
  } else {
    if (w.size() != 3)
      fail("expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
    if (!parse_type(w[1], prop.type)) fail("unknown property type " + quote(w[1]));
    prop.name = std::string(w[2]);
  }
  return prop;
}

}  // namespace

Header parse_header(const std::string& path, const std::string& data) {
  const char* p = data.data();
  const char* const end = data.data() + data.size();
  long line_no = 0;
  // Next header line without its "\n" or "\r\n"; false at end of file.
  auto next_line = [&](std::string_view& line) {
    if (p == end) return false;
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    const char* e = nl ? nl : end;
    line = std::string_view(p, static_cast<size_t>(e - p));
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    p = nl ? nl + 1 : end;
    ++line_no;
    return true;
  };
  const Fail fail = [&](const std::string& msg) { throw_at_line(path, line_no, msg); };

  std::string_view line;
  if (!next_line(line) || line != "ply")
    throw_at_line(path, 1,
                  "expected 'ply' as the first line, found " + quote(line) + " (not a PLY file?)");
  Header h;
  bool have_format = false;
  for (;;) {
    if (!next_line(line)) fail("the header has no 'end_header' line");
    const Words w = split_words(line);
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      parse_format(w, h, fail);
      have_format = true;
    } else if (w[0] == "element") {
      h.elements.push_back(parse_element(w, line_no, fail));
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail("'property' before any 'element'");
      h.elements.back().props.push_back(parse_property(w, fail));
    } else if (w[0] == "end_header") {
      if (w.size() != 1) fail("expected 'end_header' alone on its line");
      break;
    } else {
      fail("unknown header keyword " + quote(w[0]) +
           ", expected format, element, property, comment, obj_info or end_header");
    }
  }
  if (!have_format) fail("the header has no 'format' line");
  h.data_offset = static_cast<size_t>(p - data.data());
  h.data_line = line_no + 1;
  return h;
}

}  // namespace rtsim::ply
