// The DRAM presets' files (configs/dram/*.yaml), compiled into the library at build time
// (cmake/embed-files.cmake writes dram_preset_files.cpp): the presets need no file at run time.
#pragma once

#include <vector>

namespace rtsim::model {

struct EmbeddedFile {
  const char* path;  // below the source tree, e.g. "configs/dram/gddr3-gt200.yaml"
  const char* text;
};

// In the order of their paths.
const std::vector<EmbeddedFile>& dram_preset_files();

struct DramConfig;
// One preset file, read and validated (dram_preset() reads the embedded ones so); a `base` is
// looked up among the embedded files. A malformed file is an InputError naming it, the line and
// the key.
DramConfig read_dram_preset(const EmbeddedFile& file);

}  // namespace rtsim::model
