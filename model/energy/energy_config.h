// A technology node's energies (configs/energy/<node>.yaml, compiled in; or a file of the user's):
// what one SRAM access, one operation of a unit and one byte on a link cost, and an SRAM array's
// leakage. The DRAM's currents are not here: they are the device's, in its preset
// (dram_config.h, `power`). Every figure's source is a comment in its file; docs/energy.md says
// how they are used. The hardware file selects a node (`energy: 65nm`).
#pragma once

#include "model/memory/dram_preset_files.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rtsim::model {

// Energies of the embedded node files (configs/energy/*.yaml), in the order of their paths.
const std::vector<EmbeddedFile>& energy_node_files();

// A figure by array size, read between its points on log-log axes (a power law between two
// sourced sizes) and beyond the ends along the end segment's: ../shared/docs/energy-params.md,
// section 1.4.
class SizeTable {
 public:
  SizeTable() = default;
  // Points of (bytes, value), sizes strictly increasing, values positive.
  explicit SizeTable(std::vector<std::pair<double, double>> points);
  double at(double bytes) const;
  const std::vector<std::pair<double, double>>& points() const { return points_; }

 private:
  std::vector<std::pair<double, double>> points_;
};

// The operations a unit's work is priced by (a unit type's row names them: accelerator_units.h).
// An energy file gives each one's energy; one it lacks, or one it names that no machine has, is
// an error.
const std::vector<std::string>& energy_operations();

struct EnergyConfig {
  std::string node;  // the file's name ("65nm"), or its path when the user's
  std::string file;  // where it was read from (for messages and the report)
  // SRAM: the dynamic energy of one access of `access_bytes` to an array of a given size, in pJ
  // (a cache access reads line_bytes / access_bytes of them from its bank); a write costs
  // `write_factor` times a read; leakage in mW per array of a given size.
  double access_bytes = 64;
  SizeTable read_pj;
  double write_factor = 1.0;
  SizeTable leakage_mw;
  std::map<std::string, double> operation_pj;  // by energy_operations()' names
  double link_pj_per_byte = 0;                 // a byte crossing a crossbar (switch and wires)

  double sram_access_pj(double bank_bytes, double line_bytes) const {
    return read_pj.at(bank_bytes) * line_bytes / access_bytes;
  }
  double operation(const std::string& name) const { return operation_pj.at(name); }
};

// `name_or_path`: an embedded node's name ("65nm"), or a path to a YAML file of the same keys.
// A missing file, an unknown node, a malformed or negative figure, or an operation no machine has
// is an InputError naming the file, the key and what was expected.
EnergyConfig energy_config(const std::string& name_or_path);
std::vector<std::string> energy_node_names();  // sorted

}  // namespace rtsim::model
