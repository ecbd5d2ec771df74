#include "reports/study_files.h"

#include "common/error.h"
#include "reports/report_format.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace rtsim::report {

namespace {

// The records of a CSV text: cells split at commas outside quotes, "" inside quotes a quote, a
// line break inside quotes part of the cell.
std::vector<std::vector<std::string>> csv_records(const std::string& text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record(1);
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"')
        record.back() += text[++i];
      else if (c == '"')
        quoted = false;
      else
        record.back() += c;
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      record.emplace_back();
      any = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (any || record.size() > 1 || !record.back().empty()) records.push_back(record);
      record.assign(1, "");
      any = false;
    } else {
      record.back() += c;
      any = true;
    }
  }
  if (any || record.size() > 1 || !record.back().empty()) records.push_back(record);
  return records;
}

}  // namespace

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": file not found (has the study run?)");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<CsvRow> read_results_csv(const std::string& run_dir) {
  return read_csv_file((fs::path(run_dir) / "results.csv").string());
}

std::vector<CsvRow> read_csv_file(const std::string& file) {
  const std::vector<std::vector<std::string>> records = csv_records(read_text_file(file));
  if (records.empty()) throw InputError(file + ": expected a header line");
  std::vector<CsvRow> rows;
  for (size_t r = 1; r < records.size(); ++r) {
    if (records[r].size() > records[0].size())
      throw InputError(fmt::format("{}: row {} has {} cells, the header {}", file, r,
                                   records[r].size(), records[0].size()));
    CsvRow row;
    for (size_t c = 0; c < records[0].size(); ++c)
      row[records[0][c]] = c < records[r].size() ? records[r][c] : "";
    rows.push_back(std::move(row));
  }
  return rows;
}

const std::string& cell(const CsvRow& row, const std::string& column, const std::string& file) {
  const auto it = row.find(column);
  if (it == row.end()) throw InputError(fmt::format("{}: no column '{}'", file, column));
  return it->second;
}

std::pair<std::string, std::string> machine_and_culling(const CsvRow& row,
                                                        const std::string& file) {
  const std::string& variant = cell(row, "variant", file);
  const size_t dash = variant.rfind('-');
  if (dash == std::string::npos)
    throw InputError(
        fmt::format("{}: variant '{}': expected MACHINE-off, -paper or -exact", file, variant));
  return {variant.substr(0, dash), variant.substr(dash + 1)};
}

const CsvRow& finished_point(const CsvRow* found, const std::string& what,
                             const std::string& file) {
  if (!found) throw InputError(fmt::format("{}: no point of {}", file, what));
  if (!cell(*found, "failure", file).empty())
    throw InputError(
        fmt::format("{}: the point of {} failed: {}", file, what, cell(*found, "failure", file)));
  return *found;
}

double cell_number(const CsvRow& row, const std::string& column, const std::string& file) {
  const std::string& text = cell(row, column, file);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0')
    throw InputError(
        fmt::format("{}: column '{}': expected a number, got '{}'", file, column, text));
  return v;
}

double median(std::vector<double> v, const std::string& what) {
  if (v.empty()) throw InputError(what + ": no value to take the median of");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

std::string fmt_int(double v) { return grouped(int64_t(std::nearbyint(v))); }

std::string fmt_pct(double v) { return fmt::format("{:.1f}%", 100 * v); }

std::string fmt_1(double v) { return fmt::format("{:.1f}", v); }

std::string table_row(const std::vector<std::string>& cells) {
  std::string s = "|";
  for (const std::string& c : cells) s += " " + c + " |";
  return s;
}

std::string table_rule(size_t n) {
  std::string s = "|";
  for (size_t i = 0; i < n; ++i) s += "---|";
  return s;
}

std::string strip(const std::string& text) {
  auto space = [](char c) {
    return (c >= '\t' && c <= '\r') || c == ' ' || (c >= 0x1c && c <= 0x1f);
  };
  size_t b = 0, e = text.size();
  while (b < e && space(text[b])) ++b;
  while (e > b && space(text[e - 1])) --e;
  return text.substr(b, e - b);
}

}  // namespace rtsim::report
