#include "model/energy/energy_config.h"

#include "common/error.h"
#include "common/yaml_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace rtsim::model {

SizeTable::SizeTable(std::vector<std::pair<double, double>> points) : points_(std::move(points)) {
  if (points_.empty()) throw std::invalid_argument("expected at least one [bytes, value] point");
  for (size_t i = 0; i < points_.size(); ++i) {
    if (!(points_[i].first > 0) || !(points_[i].second > 0))
      throw std::invalid_argument("expected sizes and values above 0");
    if (i > 0 && !(points_[i].first > points_[i - 1].first))
      throw std::invalid_argument("expected sizes in increasing order");
  }
}

double SizeTable::at(double bytes) const {
  if (points_.size() == 1) return points_[0].second;
  // The segment that holds `bytes`, or the end one beyond either end.
  size_t i = 1;
  while (i + 1 < points_.size() && bytes > points_[i].first) ++i;
  const auto [x0, y0] = points_[i - 1];
  const auto [x1, y1] = points_[i];
  const double slope = std::log(y1 / y0) / std::log(x1 / x0);
  return y0 * std::pow(bytes / x0, slope);
}

const std::vector<std::string>& energy_operations() {
  // The operations the unit table's rows and the fixed blocks price (accelerator_units.cpp,
  // energy_model.cpp); each energy file gives them all.
  static const std::vector<std::string> ops = {
      "ray_generation", "ray_setup", "kd_step",      "box_test",   "triangle_test", "triangle_hit",
      "list_entry",     "shade",     "light_sample", "lvb_lookup", "bounce_sample"};
  return ops;
}

namespace {

std::string name_of(const std::string& path) { return std::filesystem::path(path).stem().string(); }

SizeTable table(YamlMap& m, const std::string& key) {
  const YAML::Node seq = m.raw_sequence(key);
  std::vector<std::pair<double, double>> points;
  try {
    for (const YAML::Node& p : seq) {
      if (!p.IsSequence() || p.size() != 2) throw YAML::Exception(p.Mark(), "");
      points.emplace_back(p[0].as<double>(), p[1].as<double>());
    }
  } catch (const YAML::Exception&) {
    m.fail(key, "expected a list of [bytes, value] pairs");
  }
  try {
    return SizeTable(std::move(points));
  } catch (const std::invalid_argument& e) {
    m.fail(key, e.what());
  }
}

EnergyConfig read(YamlMap doc, const std::string& node) {
  EnergyConfig c;
  c.node = node;
  c.file = doc.file();
  YamlMap sram = doc.map("sram");
  c.access_bytes = sram.get_in_range<double>("access_bytes", 0, 1, 4096);
  c.read_pj = table(sram, "read_pj");
  c.write_factor = sram.get_in_range<double>("write_factor", 1.0, 0, 100);
  c.leakage_mw = table(sram, "leakage_mw");
  sram.finish();
  YamlMap ops = doc.map("operations");
  for (const std::string& op : energy_operations()) {
    if (!ops.has(op)) ops.fail(op, "expected the energy of operation '" + op + "' (pJ)");
    c.operation_pj[op] = ops.get_in_range<double>(op, 0, 0, 1e9);
  }
  // An operation no machine has: a misspelling, or a structure the model lacks.
  for (const std::string& key : ops.keys())
    if (!c.operation_pj.count(key)) {
      std::string known;
      for (const std::string& op : energy_operations()) known += (known.empty() ? "" : ", ") + op;
      ops.fail(key, "no unit of any machine performs '" + key + "' (known: " + known + ")");
    }
  c.link_pj_per_byte = doc.get_in_range<double>("link_pj_per_byte", 0, 0, 1e6);
  doc.finish();
  return c;
}

}  // namespace

std::vector<std::string> energy_node_names() {
  std::vector<std::string> names;
  for (const EmbeddedFile& f : energy_node_files()) names.push_back(name_of(f.path));
  std::sort(names.begin(), names.end());
  return names;
}

EnergyConfig energy_config(const std::string& name_or_path) {
  for (const EmbeddedFile& f : energy_node_files())
    if (name_of(f.path) == name_or_path) {
      YAML::Node doc;
      try {
        doc = YAML::Load(f.text);
      } catch (const YAML::Exception& e) {
        throw_at_line(f.path, e.mark.line + 1, e.msg);
      }
      return read(YamlMap::from_node(doc, f.path, ""), name_or_path);
    }
  const bool path = name_or_path.find('/') != std::string::npos ||
                    name_or_path.find(".yaml") != std::string::npos;
  if (!path) {
    std::string known;
    for (const std::string& n : energy_node_names()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("no node file '" + name_or_path + "' (known: " + known +
                     "; or a path to a .yaml file)");
  }
  return read(YamlMap::load_file(name_or_path), name_or_path);
}

}  // namespace rtsim::model
