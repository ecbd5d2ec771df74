// summary.md of rtsim animate (reports/animation_tables.h): per frame and as medians, the cycles
// culling saves against what rebuilding the LVB costs and what a lazy rebuild would redo.
#include "reports/animation_tables.h"

#include "reports/report_format.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace rtsim::report {

namespace {

using nlohmann::json;
using ptr = json::json_pointer;
using Value = std::optional<double>;

Value at(const json& r, const char* where) {
  const ptr p(where);
  if (r.is_null() || !r.contains(p) || !r.at(p).is_number()) return std::nullopt;
  return r.at(p).get<double>();
}

Value sum(std::initializer_list<Value> v) {
  double s = 0;
  for (const Value& x : v) {
    if (!x) return std::nullopt;
    s += *x;
  }
  return s;
}

Value ratio(Value a, Value b) { return a && b && *b != 0 ? Value(*a / *b) : std::nullopt; }

// The summary's columns after the time, in order.
enum Column {
  kOff,
  kOn,
  kSaved,
  kShare,
  kBuild,
  kPays,
  kLvbS,
  kKdS,
  kDirty,
  kLazy,
  kLazyShare,
  kLazyPays,
  kColumns
};
using Row = std::array<Value, kColumns>;

// The culling-on run's shadow rays culled, as a share of those it generated.
Value culled_share(const json& on) {
  if (on.is_null()) return std::nullopt;
  double all = 0, cut = 0;
  for (const json& l : on["per_light"]) {
    all += l["shadow_rays"].get<double>();
    cut += l["culled"].get<double>();
  }
  return all > 0 ? Value(cut / all) : std::nullopt;
}

Row row_of(const AnimationFrame& f) {
  const json& any = f.on.is_null() ? f.off : f.on;
  Row r;
  r[kOff] = at(f.off, "/cycles_total");
  r[kOn] = at(f.on, "/cycles_total");
  r[kSaved] = r[kOff] && r[kOn] ? Value(*r[kOff] - *r[kOn]) : std::nullopt;
  r[kShare] = culled_share(f.on);
  r[kBuild] = sum({at(f.on, "/lvb/region_tests"), at(f.on, "/lvb/pair_tests")});
  r[kPays] = ratio(r[kSaved], r[kBuild]);
  r[kLvbS] = at(f.on, "/host/seconds/lvb");
  r[kKdS] = at(any, "/host/seconds/kdtree");
  r[kDirty] = ratio(at(f.on, "/lvb/lazy/dirty_pairs"), at(f.on, "/lvb/lazy/pairs"));
  r[kLazy] = sum({at(f.on, "/lvb/lazy/region_tests"), at(f.on, "/lvb/lazy/pair_tests"),
                  at(f.on, "/lvb/lazy/dirty_tests")});
  r[kLazyShare] = ratio(r[kLazy], r[kBuild]);
  r[kLazyPays] = ratio(r[kSaved], r[kLazy]);
  return r;
}

// The middle value, or the mean of the two middle ones; none when there are no values.
Value median(std::vector<double> v) {
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A count rounded to an integer, its digits grouped by threes: -1234.6 -> -1,235.
std::string count(double v) {
  std::string digits = fmt::format("{:.0f}", v), out;
  const size_t sign = digits[0] == '-' ? 1 : 0;
  for (size_t i = sign; i < digits.size(); ++i) {
    if (i > sign && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return digits.substr(0, sign) + out;
}

std::string cell(Column c, const Value& v) {
  if (!v || std::isnan(*v)) return "";
  switch (c) {
    case kShare:
    case kDirty:
    case kLazyShare: return fmt::format("{:.1f}%", *v * 100);
    case kPays:
    case kLazyPays: return fmt::format("{:.4f}", *v);
    case kLvbS:
    case kKdS: return fmt::format("{:.2f}", *v);
    default: return count(*v);
  }
}

std::string line(const std::string& first, const Row& r) {
  std::string md = "| " + first + " |";
  for (int c = 0; c < kColumns; ++c) md += " " + cell(Column(c), r[c]) + " |";
  return md + "\n";
}

}  // namespace

std::string animation_summary(const std::map<double, AnimationFrame>& frames) {
  std::string md =
      "# Culling against its recomputation, per frame\n\nBuilder cycles: the LVB's region and pair "
      "tests at one test per cycle; lazy tests add the dirty tests that find the pairs to redo. "
      "Host seconds vary from run to run (host.csv).\n\n| time | cycles off | cycles on | saved "
      "cycles | shadow rays culled | LVB tests (builder cycles) | saved / LVB tests | LVB s | "
      "kd-tree s | lazy: dirty pairs | lazy: tests | lazy / full | saved / lazy tests |\n|";
  for (int c = 0; c <= kColumns; ++c) md += "---|";
  md += "\n";
  std::array<std::vector<double>, kColumns> columns;
  for (const auto& [t, f] : frames) {
    const Row r = row_of(f);
    md += line(fmt::format("{:g}", t), r);
    for (int c = 0; c < kColumns; ++c)
      if (r[c] && !std::isnan(*r[c])) columns[c].push_back(*r[c]);
  }
  Row medians;
  for (int c = 0; c < kColumns; ++c) medians[c] = median(columns[c]);
  return md + line("**median**", medians);
}

}  // namespace rtsim::report
