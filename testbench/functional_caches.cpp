#include "testbench/functional_caches.h"

#include "model/accelerator_topology.h"

#include <algorithm>
#include <stdexcept>

namespace rtsim {

TagArray::TagArray(uint32_t size_bytes, uint32_t ways, uint32_t line_bytes) : ways_(ways) {
  const uint32_t sets = size_bytes / (ways * line_bytes);
  if (ways == 0 || sets == 0 || (sets & (sets - 1)) != 0)
    throw std::invalid_argument("a cache's sets must be a power of two");
  set_mask_ = sets - 1;
  tags_.assign(size_t(sets) * ways, kEmpty);
}

void CacheCounts::add(const CacheCounts& o) {
  for (int u = 0; u < kAccessUnits; ++u) {
    reads[u] += o.reads[u];
    l1_lines[u] += o.l1_lines[u];
    l1_misses[u] += o.l1_misses[u];
    l2_misses[u] += o.l2_misses[u];
  }
}

namespace {

TagArray tags(const model::CacheConfig& c) { return TagArray(c.size_bytes, c.ways, c.line_bytes); }

// A type's L1s, and its L2s (one shared, or one per unit) appended to `l2s`.
void add_type(const model::UnitTypeConfig& u, std::vector<TagArray>& l1,
              std::vector<uint32_t>& l2_of, std::vector<TagArray>& l2s) {
  for (uint32_t i = 0; i < u.count; ++i) l1.push_back(tags(u.l1));
  const bool shared = u.l2_sharing == model::L2Sharing::kType;
  for (uint32_t i = 0; i < u.count; ++i) {
    if (!shared || i == 0) l2s.push_back(tags(u.l2));
    l2_of.push_back(uint32_t(l2s.size() - 1));
  }
}

}  // namespace

FunctionalCaches::FunctionalCaches(const model::AcceleratorConfig& cfg) {
  const model::UnitTypeConfig& trv = cfg.traversal();
  line_bytes_ = trv.l1.line_bytes;
  const model::UnitTypeConfig* types[] = {&trv, &cfg.list, &cfg.ist, &cfg.shading};
  for (const model::UnitTypeConfig* t : types)
    if (t->l1.line_bytes != line_bytes_ || t->l2.line_bytes != line_bytes_)
      throw std::invalid_argument("the functional caches need one line size throughout");
  if (line_bytes_ == 0 || (line_bytes_ & (line_bytes_ - 1)) != 0)
    throw std::invalid_argument("a line's size must be a power of two");
  line_shift_ = 0;
  while ((1u << line_shift_) < line_bytes_) ++line_shift_;
  const size_t trv_i = size_t(AccessUnit::kTraversal), list_i = size_t(AccessUnit::kList),
               ist_i = size_t(AccessUnit::kIst), shading_i = size_t(AccessUnit::kShading);
  add_type(trv, l1_[trv_i], l2_of_[trv_i], l2s_);
  l2_type_.resize(l2s_.size(), AccessUnit::kTraversal);
  add_type(cfg.list, l1_[list_i], l2_of_[list_i], l2s_);
  l2_type_.resize(l2s_.size(), AccessUnit::kList);
  add_type(cfg.ist, l1_[ist_i], l2_of_[ist_i], l2s_);
  // The shading L1s on the IST's shared L2, or on one of their own with its configuration.
  const bool ist_shared = cfg.ist.l2_sharing == model::L2Sharing::kType;
  if (!ist_shared) l2s_.push_back(tags(cfg.ist.l2));
  l2_type_.resize(l2s_.size(), AccessUnit::kIst);
  const uint32_t shading_l2 = ist_shared ? l2_of_[ist_i][0] : uint32_t(l2s_.size() - 1);
  for (uint32_t i = 0; i < cfg.shading.count; ++i) {
    l1_[shading_i].push_back(tags(cfg.shading.l1));
    l2_of_[shading_i].push_back(shading_l2);
  }
  // AccessUnit's types are the stages, in stage order (kernels/access_stream.h).
  static_assert(size_t(AccessUnit::kShading) == model::kShadingStage &&
                kAccessUnits == model::kStages);
  for (uint32_t t = 0; t < trv.count; ++t) routes_.push_back(model::ray_route(cfg, t));
}

int FunctionalCaches::read(uint32_t unit, const Access& a, CacheCounts& counts,
                           std::vector<LineMiss>* misses) {
  const size_t type = size_t(a.unit);
  TagArray& l1 = l1_[type][unit];
  TagArray& l2 = l2s_[l2_of_[type][unit]];
  ++counts.reads[type];
  int level = 0;
  if (a.bytes == 0) return level;
  const uint64_t first = a.addr >> line_shift_,
                 last = (uint64_t(a.addr) + a.bytes - 1) >> line_shift_;
  for (uint64_t line = first; line <= last; ++line) {
    ++counts.l1_lines[type];
    if (l1.access(line)) continue;
    ++counts.l1_misses[type];
    level = std::max(level, 1);
    const bool l2_hit = l2.access(line);
    if (misses) misses->push_back({uint32_t(line), l2_of_[type][unit], !l2_hit});
    if (l2_hit) continue;
    ++counts.l2_misses[type];
    level = 2;
  }
  return level;
}

}  // namespace rtsim
