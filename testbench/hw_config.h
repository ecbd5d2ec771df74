// Hardware configuration files (YAML) -> model::AcceleratorConfig, checked key by key.
// Format: configs/README.md.
#pragma once

#include "model/accelerator.h"

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim {

// Loads and validates; every error names the file, the line and the key path (InputError).
model::AcceleratorConfig load_hw_config(const std::string& path);
// The resolved configuration, as written beside every report.
nlohmann::json hw_config_json(const model::AcceleratorConfig& c);

}  // namespace rtsim
