// A record read through a level of the memory hierarchy (a unit's L1): the lines covering it are
// fetched (a record may straddle two), and its bytes are assembled from that level's copies of
// those lines.
#pragma once

#include "model/memory/line_source.h"

#include <algorithm>
#include <cstring>

namespace rtsim::model {

struct RecordFetch {
  Tick ready = 0;        // delivery of the last line; kUnknown if some line is still to come
  uint32_t pending = 0;  // lines still to come (each will be told through on_fill)
};

// `Source` is a LineSource, or a Cache (whose final methods are then called directly: this runs on
// every record a unit reads).
template <class Source>
RecordFetch fetch_record(Source& source, uint64_t addr, uint32_t bytes, Tick now,
                         FillListener* listener, uint64_t cookie) {
  const uint64_t line_bytes = source.line_bytes();
  RecordFetch f;
  for (uint64_t line = addr & ~(line_bytes - 1); line < addr + bytes; line += line_bytes) {
    const Tick t = source.fetch_line(line, now, listener, cookie);
    if (t == kUnknown)
      ++f.pending;
    else
      f.ready = std::max(f.ready, t);
  }
  if (f.pending) f.ready = kUnknown;
  return f;
}

// A record's bytes line by line (read_record's case of a record across lines).
template <class Source>
void read_record_lines(const Source& source, uint64_t addr, uint32_t bytes, uint8_t* out) {
  const uint64_t line_bytes = source.line_bytes();
  uint32_t done = 0;
  while (done < bytes) {
    const uint64_t a = addr + done;
    const uint64_t line = a & ~(line_bytes - 1);
    const uint32_t n = uint32_t(std::min<uint64_t>(bytes - done, line + line_bytes - a));
    std::memcpy(out + done, source.line_data(line) + (a - line), n);
    done += n;
  }
}

// The record's bytes, once every line was delivered (or is known to be). Always inlined: a unit
// reads a record of a size known where it calls, and the copy of a record on one line (most)
// becomes a few moves.
template <class Source>
[[gnu::always_inline]] inline void read_record(const Source& source, uint64_t addr, uint32_t bytes,
                                               uint8_t* out) {
  const uint64_t first = addr & ~(uint64_t(source.line_bytes()) - 1);
  if (addr + bytes <= first + source.line_bytes())
    std::memcpy(out, source.line_data(first) + (addr - first), bytes);
  else
    read_record_lines(source, addr, bytes, out);
}

}  // namespace rtsim::model
