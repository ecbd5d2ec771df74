// How the reports write numbers: locale-free thousands separators, percentages, milliseconds.
// One set of rules for report.md, reproduction.md and ablation.md, so a figure reads the same in
// each.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <string>

namespace rtsim::report {

// A figure that is missing (a run that did not finish, a ratio over nothing).
inline constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

// Digits in groups of three: 1234567 -> 1,234,567.
std::string grouped(int64_t v);
// A count rounded to an integer and grouped; "n/a" when missing.
std::string num(double v);
// part / whole as a percentage with two decimals; "n/a" when whole is not positive.
std::string pct(double part, double whole);
// A ratio as a percentage with two decimals; "n/a" when missing.
std::string rate(double v);
// (off - on) / off as a percentage: what culling saved; "n/a" when off is not positive.
std::string reduction(double on, double off);
// 100 (x - base) / base; missing when either is, or base is not positive.
double change_pct(double x, double base);
// A percentage already computed: "+1.25%" (signed) or "1.25%"; "n/a" when missing.
std::string signed_pct(double v);
std::string plain_pct(double v);
// Milliseconds: three decimals, or four significant digits below 1 ms (small test frames).
std::string ms_text(double v);
// A JSON number, or null when missing.
nlohmann::json finite_or_null(double v);

}  // namespace rtsim::report
