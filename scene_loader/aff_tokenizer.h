// The AFF tokenizer: whitespace-separated tokens over a whole file, '{' and '}' tokens of their
// own, '#' or '%' comments; typed reads that fail with "FILE:LINE: found F, expected E".
#pragma once

#include "common/error.h"

#include <glm/vec3.hpp>

#include <charconv>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>

namespace rtsim::aff {

using glm::dvec3;

// The whole file at `path` into `out`; false if it cannot be read.
inline bool read_file(const std::string& path, std::string& out) {
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

}  // namespace rtsim::aff
