// The paper's machine is written twice on purpose: as the named defaults of AcceleratorConfig
// (model/accelerator_config.h, paper_machine) and as configs/hw/tni-paper.yaml, the file users
// run and read. They must agree key for key, the DRAM's timings included.
#include "config_loader/hw_config.h"
#include "model/accelerator_config.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace rtsim {
namespace {

TEST(PaperMachine, TniPaperYamlStatesTheDefaults) {
  const model::AcceleratorConfig file =
      load_hw_config((test::source_dir() / "configs/hw/tni-paper.yaml").string());
  const nlohmann::json from_file = hw_config_json(file), defaults = hw_config_json({});
  ASSERT_TRUE(defaults.contains("trv"));
  for (const auto& [key, value] : defaults.items())
    EXPECT_EQ(from_file[key], value) << "hw." << key;
  EXPECT_EQ(from_file.size(), defaults.size());
}

TEST(PaperMachine, ChangingADefaultIsSeen) {
  model::AcceleratorConfig other;
  other.ist.l1 = model::paper_machine::l1(8, 4);  // the paper's IST L1 is 16 KB
  EXPECT_NE(hw_config_json(other)["ist"], hw_config_json({})["ist"]);
}

}  // namespace
}  // namespace rtsim
