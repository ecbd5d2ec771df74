#include "testbench/hw_config.h"

#include "common/yaml_reader.h"

#include <stdexcept>

namespace rtsim {

namespace {

// Integers are read as int64 so that a negative value is reported as out of range.
uint32_t get_u32(YamlMap& m, const std::string& key, uint32_t fallback, int64_t lo, int64_t hi) {
  return uint32_t(m.get_in_range<int64_t>(key, fallback, lo, hi));
}

// `sharing`: where the cache is an L2, its sharing key (null for L1s, where the key is unknown).
model::CacheConfig read_cache(YamlMap m, model::CacheConfig c, model::L2Sharing* sharing = nullptr) {
  if (sharing) {
    const std::string v = m.get<std::string>("sharing", *sharing == model::L2Sharing::kType ? "type" : "unit");
    if (v != "type" && v != "unit") m.fail("sharing", "expected 'type' (one L2 per unit type) or 'unit' (a private L2 per unit)");
    *sharing = v == "type" ? model::L2Sharing::kType : model::L2Sharing::kUnit;
  }
  c.size_bytes = get_u32(m, "size_kb", c.size_bytes / 1024, 1, 1 << 20) * 1024;
  c.ways = get_u32(m, "ways", c.ways, 1, 1024);
  c.line_bytes = get_u32(m, "line_bytes", c.line_bytes, 4, 4096);
  c.hit_latency = get_u32(m, "hit_latency", c.hit_latency, 0, 10000);
  c.mshrs = get_u32(m, "mshrs", c.mshrs, 1, 65536);
  c.banks = get_u32(m, "banks", c.banks, 1, 1024);
  c.ports = get_u32(m, "ports", c.ports, 0, 64);
  const std::string fill = m.get<std::string>("fill_port", c.fill_port == model::FillPort::kShared ? "shared" : "separate");
  if (fill != "shared" && fill != "separate") m.fail("fill_port", "expected 'shared' or 'separate'");
  c.fill_port = fill == "shared" ? model::FillPort::kShared : model::FillPort::kSeparate;
  m.finish();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    m.fail("size_kb", e.what());
  }
  return c;
}

model::LinkConfig read_link(YamlMap m, model::LinkConfig l) {
  l.latency = get_u32(m, "latency", l.latency, 0, 10000);
  l.bytes_per_cycle = get_u32(m, "bytes_per_cycle", l.bytes_per_cycle, 0, 4096);
  l.header_bytes = get_u32(m, "header_bytes", l.header_bytes, 0, 4096);
  m.finish();
  return l;
}

void read_unit(YamlMap m, model::UnitTypeConfig& u, bool has_l2) {
  u.count = get_u32(m, "count", u.count, 1, 1024);
  u.latency = get_u32(m, "latency", u.latency, 1, 10000);
  u.capacity = get_u32(m, "capacity", u.capacity, 1, 65536);
  u.fifo_depth = get_u32(m, "fifo_depth", u.fifo_depth, 1, 65536);
  if (m.has("l1")) u.l1 = read_cache(m.map("l1"), u.l1);
  if (has_l2 && m.has("l2")) u.l2 = read_cache(m.map("l2"), u.l2, &u.l2_sharing);
  if (has_l2 && m.has("link")) u.link = read_link(m.map("link"), u.link);
  m.finish();
}

}  // namespace

model::AcceleratorConfig load_hw_config(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  return read_hw_config(YamlMap::load_file(path, overrides));
}

model::AcceleratorConfig read_hw_config(YamlMap top) {
  model::AcceleratorConfig c;
  c.clock_ghz = top.get_in_range("clock_ghz", c.clock_ghz, 0.01, 100.0);
  c.ray_pool = get_u32(top, "ray_pool", c.ray_pool, 1, 1 << 24);
  const std::string order = top.get<std::string>("order", "tiles");
  if (order != "tiles" && order != "scanline") top.fail("order", "expected 'tiles' or 'scanline'");
  c.order = order == "tiles" ? model::RayOrder::kTiles : model::RayOrder::kScanline;
  const std::string schedule = top.get<std::string>("schedule", "two-phase");
  if (schedule != "two-phase" && schedule != "one-phase") top.fail("schedule", "expected 'two-phase' or 'one-phase'");
  c.schedule = schedule == "two-phase" ? model::Schedule::kTwoPhase : model::Schedule::kOnePhase;
  c.tile = top.get_in_range("tile", c.tile, 1, 4096);
  c.watchdog_cycles = uint64_t(top.get_in_range<int64_t>("watchdog_cycles", int64_t(c.watchdog_cycles), 1000, int64_t(1) << 40));
  if (top.has("trv")) read_unit(top.map("trv"), c.trv, true);
  if (top.has("list")) read_unit(top.map("list"), c.list, true);
  if (top.has("ist")) read_unit(top.map("ist"), c.ist, true);
  if (top.has("shading")) {
    YamlMap m = top.map("shading");
    c.write_records = m.get<bool>("write_records", c.write_records);
    read_unit(m, c.shading, false);
  }
  if (top.has("culling")) {
    YamlMap m = top.map("culling");
    c.culling.records_per_cycle = get_u32(m, "records_per_cycle", c.culling.records_per_cycle, 0, 64);
    c.culling.prefetch = get_u32(m, "prefetch", c.culling.prefetch, 1, 65536);
    m.finish();
  }
  if (top.has("raygen")) {
    YamlMap g = top.map("raygen");
    c.raygen_rays_per_cycle = get_u32(g, "rays_per_cycle", c.raygen_rays_per_cycle, 1, 64);
    g.finish();
  }
  if (top.has("memory_link")) c.memory_link = read_link(top.map("memory_link"), c.memory_link);
  if (top.has("dram")) {
    YamlMap d = top.map("dram");
    const std::string preset = d.get<std::string>("preset", "gddr3-gt200-1ghz");
    try {
      c.dram = model::dram_preset(preset);
    } catch (const std::invalid_argument& e) {
      d.fail("preset", e.what());
    }
    c.dram.channels = get_u32(d, "channels", c.dram.channels, 1, 64);
    c.dram.queue_size = get_u32(d, "queue_size", c.dram.queue_size, 1, 4096);
    c.dram.address_mapping = d.get<std::string>("address_mapping", c.dram.address_mapping);
    d.finish();
  }
  top.finish();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(top.file() + ": " + e.what());
  }
  return c;
}

nlohmann::json hw_config_json(const model::AcceleratorConfig& c) {
  auto cache = [](const model::CacheConfig& k) {
    return nlohmann::json{{"size_kb", k.size_bytes / 1024}, {"ways", k.ways}, {"line_bytes", k.line_bytes},
                          {"hit_latency", k.hit_latency}, {"mshrs", k.mshrs}, {"banks", k.banks},
                          {"ports", k.ports},
                          {"fill_port", k.fill_port == model::FillPort::kShared ? "shared" : "separate"}};
  };
  auto link = [](const model::LinkConfig& l) {
    return nlohmann::json{
        {"latency", l.latency}, {"bytes_per_cycle", l.bytes_per_cycle}, {"header_bytes", l.header_bytes}};
  };
  auto unit = [&](const model::UnitTypeConfig& u, bool l2) {
    nlohmann::json j = {{"count", u.count}, {"latency", u.latency}, {"capacity", u.capacity},
                        {"fifo_depth", u.fifo_depth}, {"l1", cache(u.l1)}};
    if (l2) {
      j["l2"] = cache(u.l2);
      j["l2"]["sharing"] = u.l2_sharing == model::L2Sharing::kType ? "type" : "unit";
      j["link"] = link(u.link);
    }
    return j;
  };
  return {{"clock_ghz", c.clock_ghz},
          {"ray_pool", c.ray_pool},
          {"order", c.order == model::RayOrder::kTiles ? "tiles" : "scanline"},
          {"schedule", c.schedule == model::Schedule::kTwoPhase ? "two-phase" : "one-phase"},
          {"tile", c.tile},
          {"watchdog_cycles", c.watchdog_cycles},
          {"trv", unit(c.trv, true)},
          {"list", unit(c.list, true)},
          {"ist", unit(c.ist, true)},
          {"shading", [&] {
             nlohmann::json j = unit(c.shading, false);
             j["write_records"] = c.write_records;
             return j;
           }()},
          {"culling", {{"records_per_cycle", c.culling.records_per_cycle}, {"prefetch", c.culling.prefetch}}},
          {"raygen", {{"rays_per_cycle", c.raygen_rays_per_cycle}}},
          {"memory_link", link(c.memory_link)},
          {"dram",
           {{"preset", c.dram.preset},
            {"channels", c.dram.channels},
            {"queue_size", c.dram.queue_size},
            {"address_mapping", c.dram.address_mapping}}}};
}

}  // namespace rtsim
