// Timing goldens: every file in tests/golden/ names an rtsim command line and the figures it must
// produce. Cycles are results: a change here is a change of the model's timing, which
// docs/timing-changes.md and the commit message explain (scripts/update-goldens.py rewrites the
// files). The frozen goldens are the model before contention was modelled: the ideal settings of
// every limit must reproduce them exactly.
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <fstream>

namespace rtsim {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> golden_files() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "tests/golden"))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// The value at a dotted path, or null.
nlohmann::json lookup(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* node = &j;
  size_t start = 0;
  while (start <= path.size()) {
    const size_t dot = path.find('.', start);
    const std::string part =
        path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node->is_object() || !node->contains(part)) return nullptr;
    node = &(*node)[part];
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return *node;
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, FiguresAreUnchanged) {
  const nlohmann::json golden =
      read_json(test::source_dir() / "tests/golden" / (GetParam() + ".json"));
  ASSERT_TRUE(golden.contains("expect")) << "no figures yet: run scripts/update-goldens.py";
  const fs::path out = test::temp_dir("golden");
  std::string cmd = "cd '" + test::source_dir().string() + "' && '" + RTSIM_BINARY + "'";
  for (const auto& a : golden["args"]) cmd += " '" + a.get<std::string>() + "'";
  cmd += " --out '" + out.string() + "' --no-plots --quiet";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;
  const nlohmann::json report = read_json(out / "report.json");
  for (const auto& [key, want] : golden["expect"].items()) {
    const nlohmann::json got = lookup(report, key);
    ASSERT_FALSE(got.is_null()) << key << " is not in the report";
    EXPECT_EQ(got.get<double>(), want.get<double>()) << GetParam() << ": " << key;
  }
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(City, Golden, ::testing::ValuesIn(golden_files()), [](const auto& p) {
  std::string n = p.param;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
});

}  // namespace
}  // namespace rtsim
