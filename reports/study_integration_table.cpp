// The figures tests and examples of the build print (docs/systemc-integration.md): each row reads
// one program run's stdout.txt, as its ProgramFigure says.
#include "reports/study_integration_table.h"

#include "common/error.h"
#include "reports/study_files.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>

namespace fs = std::filesystem;
using nlohmann::json;

namespace rtsim::report {

namespace {

// The `NAME: N cycles` lines of a program's output (the tests that print the figures docs
// quote), in order.
std::vector<std::pair<std::string, std::string>> cycles_lines(const std::string& text) {
  static const std::regex line(R"((\S[^:\n]*): (\d+) cycles)");
  std::vector<std::pair<std::string, std::string>> out;
  size_t at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    std::smatch m;
    const std::string l = text.substr(at, end - at);
    if (std::regex_match(l, m, line)) out.emplace_back(m[1], m[2]);
    at = end + 1;
  }
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// An integer as 1,234; a JSON number that is not one is an InputError naming the file.
std::string integer(const json& v, const std::string& file) {
  if (!v.is_number_integer())
    throw InputError(fmt::format("{}: expected an integer, got {}", file, v.dump()));
  return fmt_int(v.get<double>());
}

// A count of frames in words, as the docs' prose writes it.
std::string count_word(size_t n) {
  static const char* const words[] = {"no",   "one", "two",   "three", "four",
                                      "five", "six", "seven", "eight", "nine"};
  return n < std::size(words) ? words[n] : std::to_string(n);
}

// examples/platform's frames (its JSON lines with "frame"): the row's text, at the frames' pixels,
// their interrupt times and wrong records; the cell, their cycles.
std::pair<std::string, std::string> platform_cells(const ProgramFigure& f, const std::string& text,
                                                   const std::string& file) {
  std::vector<json> frames;
  size_t at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    if (text[at] == '{') {
      json j = json::parse(text.substr(at, end - at), nullptr, false);
      if (j.is_discarded()) throw InputError(file + ": a line starting with '{' is not JSON");
      if (j.contains("frame")) frames.push_back(std::move(j));
    }
    at = end + 1;
  }
  if (frames.empty()) throw InputError(file + ": no frame line (examples/platform's output?)");
  std::vector<std::string> interrupts, wrong, cycles;
  for (const json& x : frames) {
    interrupts.push_back(fmt_int(x.at("interrupt_ns").get<double>()));
    wrong.push_back(x.at("wrong_records").dump());
    cycles.push_back(fmt_int(x.at("cycles").get<double>()));
  }
  const size_t n = frames.size();
  return {fmt::format("{} at {} pixels, {} camera{} (interrupt {} ns; wrong records {})", f.figure,
                      integer(frames[0].at("pixels"), file), count_word(n), n == 1 ? "" : "s",
                      joined(interrupts), joined(wrong)),
          joined(cycles)};
}

}  // namespace

std::string integration_table(const StudyTable& t, const std::string& run_dir) {
  std::string out = table_row({"figure", "cycles", "measured by"}) + "\n" + table_rule(3);
  for (const ProgramFigure& f : t.rows) {
    const std::string file = (fs::path(run_dir) / f.run / "stdout.txt").string();
    const std::string text = read_text_file(file);
    std::pair<std::string, std::string> cells{f.figure, ""};
    if (f.cells == "platform") {
      cells = platform_cells(f, text, file);
    } else {
      std::vector<std::string> names, cycles;
      for (const auto& [name, n] : cycles_lines(text)) {
        names.push_back(name);
        cycles.push_back(fmt_int(std::stod(n)));
      }
      if (f.cells == "named_cycles") cells.first += ": " + joined(names);
      cells.second = joined(cycles);
    }
    out += "\n" + table_row({cells.first, cells.second, "`" + f.by + "`"});
  }
  return out;
}

}  // namespace rtsim::report
