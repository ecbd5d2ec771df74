#include "testbench/sampling/sample_pass_file.h"

#include "reports/output_files.h"

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace rtsim {

namespace {

// The file is this binary's own, read back by its own child processes: plain bytes of the values.
static_assert(std::is_trivially_copyable_v<model::BatchFeatures>);
constexpr char kMagic[] = "rtsim sampled pass 1\n";

template <typename T>
void put(std::string& out, const std::vector<T>& v) {
  const uint64_t n = v.size();
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out.append(reinterpret_cast<const char*>(v.data()), n * sizeof(T));
}

void put(std::string& out, const std::string& s) {
  const uint64_t n = s.size();
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out += s;
}

void put(std::string& out, double x) { out.append(reinterpret_cast<const char*>(&x), sizeof x); }

// Reads the values back in the order `put` wrote them; a short file is an error.
class Reader {
 public:
  Reader(std::string bytes, uint64_t at, std::string file)
      : bytes_(std::move(bytes)), file_(std::move(file)), at_(at) {}
  void take(void* to, uint64_t n) {
    if (n > bytes_.size() - at_)
      throw std::runtime_error(fmt::format("{}: a kept functional pass ends early", file_));
    if (n) std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }
  template <typename T>
  std::vector<T> vector() {
    uint64_t n = 0;
    take(&n, sizeof n);
    if (n > (bytes_.size() - at_) / sizeof(T))
      throw std::runtime_error(fmt::format("{}: a kept functional pass ends early", file_));
    std::vector<T> v(n);
    take(v.data(), n * sizeof(T));
    return v;
  }
  double number() {
    double x = 0;
    take(&x, sizeof x);
    return x;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  std::string bytes_, file_;
  uint64_t at_ = 0;
};

}  // namespace

std::optional<SampledPass> read_sampled_pass(const PassKeeping& keep) {
  std::ifstream in(keep.file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  std::string bytes = s.str();
  const size_t magic = sizeof kMagic - 1;
  if (bytes.compare(0, magic, kMagic) != 0)
    throw std::runtime_error(fmt::format("{}: not a kept functional pass", keep.file));
  Reader r(std::move(bytes), magic, keep.file);
  const std::vector<char> key = r.vector<char>();
  if (std::string_view(key.data(), key.size()) != keep.key)
    throw std::runtime_error(
        fmt::format("{}: a functional pass kept for another run's settings", keep.file));
  SampledPass pass;
  pass.walk_steps = r.vector<double>();
  pass.features.primary = r.vector<model::BatchFeatures>();
  pass.features.shadow = r.vector<model::BatchFeatures>();
  pass.features.primary_seconds = r.number();
  pass.features.shadow_seconds = r.number();
  if (!r.done())
    throw std::runtime_error(fmt::format("{}: a kept functional pass runs on", keep.file));
  return pass;
}

void write_sampled_pass(const PassKeeping& keep, const SampledPass& pass) {
  std::string out(kMagic);
  put(out, keep.key);
  put(out, pass.walk_steps);
  put(out, pass.features.primary);
  put(out, pass.features.shadow);
  put(out, pass.features.primary_seconds);
  put(out, pass.features.shadow_seconds);
  write_file_atomic(keep.file, out);
}

}  // namespace rtsim
