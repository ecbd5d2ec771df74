// Whether input text is UTF-8: text from a file or the command line reaches JSON writers (reports,
// sweep scripts) that refuse anything else, so readers check it where they read it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace rtsim {

// The length of the UTF-8 sequence at s[i], 0 if the bytes there are not one.
inline size_t utf8_sequence(std::string_view s, size_t i) {
  const auto c = static_cast<uint8_t>(s[i]);
  // The sequence's length and the smallest code point it may encode (no overlong forms).
  int n = 0;
  uint32_t cp = 0, min = 0;
  if (c < 0x80) return 1;
  if ((c & 0xe0) == 0xc0)
    n = 1, cp = c & 0x1f, min = 0x80;
  else if ((c & 0xf0) == 0xe0)
    n = 2, cp = c & 0x0f, min = 0x800;
  else if ((c & 0xf8) == 0xf0)
    n = 3, cp = c & 0x07, min = 0x10000;
  else
    return 0;
  if (s.size() - i <= size_t(n)) return 0;
  for (int k = 1; k <= n; ++k) {
    const auto d = static_cast<uint8_t>(s[i + k]);
    if ((d & 0xc0) != 0x80) return 0;
    cp = cp << 6 | (d & 0x3f);
  }
  if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return size_t(n) + 1;
}

inline bool is_utf8(std::string_view s) {
  for (size_t i = 0, n = 0; i < s.size(); i += n)
    if ((n = utf8_sequence(s, i)) == 0) return false;
  return true;
}

// `s` with every byte that starts no UTF-8 sequence replaced by '?': our own text that quotes
// input (a log, an error message) on its way into a JSON file.
inline std::string utf8_lossy(std::string_view s) {
  std::string out;
  for (size_t i = 0; i < s.size();) {
    const size_t n = utf8_sequence(s, i);
    out.append(n ? s.substr(i, n) : std::string_view("?"));
    i += n ? n : 1;
  }
  return out;
}

}  // namespace rtsim
