// Hardware configuration files (YAML) -> model::AcceleratorConfig, checked key by key.
// Format: configs/README.md.
#pragma once

#include "common/yaml_reader.h"
#include "model/accelerator.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {

// Loads and validates; every error names the file, the line and the key path (InputError).
// `overrides` are "--set hw.KEY=VALUE" without the "hw." prefix.
model::AcceleratorConfig load_hw_config(const std::string& path,
                                        const std::vector<ConfigOverride>& overrides = {});
// The same from a map (a file's top level, or the "hw" section of a config.json).
model::AcceleratorConfig read_hw_config(YamlMap top);
// The resolved configuration, as written beside every report: every key of the hardware file,
// the DRAM's timings included (not only its preset's name).
nlohmann::json hw_config_json(const model::AcceleratorConfig& c);
// Every key of a hardware file with its default (the paper's T&I engine), range, unit and meaning:
// a markdown table (rtsim params; the table in configs/README.md).
std::string hw_params_markdown();

}  // namespace rtsim
