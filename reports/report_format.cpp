#include "reports/report_format.h"

#include <fmt/format.h>

#include <cmath>

namespace rtsim::report {

std::string grouped(int64_t v) {
  std::string d = std::to_string(v < 0 ? -v : v), out;
  for (size_t i = 0; i < d.size(); ++i) {
    if (i && (d.size() - i) % 3 == 0) out += ',';
    out += d[i];
  }
  return (v < 0 ? "-" : "") + out;
}

std::string num(double v) { return std::isnan(v) ? "n/a" : grouped(std::llround(v)); }

std::string pct(double part, double whole) {
  return whole > 0 ? fmt::format("{:.2f}%", 100.0 * part / whole) : "n/a";
}

std::string rate(double v) { return std::isnan(v) ? "n/a" : fmt::format("{:.2f}%", 100.0 * v); }

std::string reduction(double on, double off) {
  return off > 0 ? fmt::format("{:.2f}%", 100 * (off - on) / off) : "n/a";
}

double change_pct(double x, double base) {
  return std::isfinite(x) && std::isfinite(base) && base > 0 ? 100 * (x - base) / base : kMissing;
}

std::string signed_pct(double v) { return std::isfinite(v) ? fmt::format("{:+.2f}%", v) : "n/a"; }

std::string plain_pct(double v) { return std::isfinite(v) ? fmt::format("{:.2f}%", v) : "n/a"; }

std::string ms_text(double v) {
  if (!std::isfinite(v)) return "-";
  return std::fabs(v) < 1 ? fmt::format("{:.4g}", v) : fmt::format("{:.3f}", v);
}

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace rtsim::report
