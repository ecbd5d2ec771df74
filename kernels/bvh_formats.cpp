// The list of BVH node formats (common/registry.h says why it is explicit). A new format is a
// class in its own file with an `add_...` function, and one line here.
#include "kernels/bvh_format.h"

#include <stdexcept>

namespace rtsim {

// What each format's file registers (no header: nothing else calls them).
void add_bvh2_format(BvhFormats& r);
void add_soa_formats(BvhFormats& r);
void add_cwbvh8_format(BvhFormats& r);

namespace {

// The order is the one `--accel`, its help and the errors show (after the kd-tree).
BvhFormats& formats() {
  static BvhFormats r = [] {
    BvhFormats f;
    add_bvh2_format(f);
    add_soa_formats(f);
    add_cwbvh8_format(f);
    return f;
  }();
  return r;
}

}  // namespace

void BvhFormats::add(std::string name, Factory make, std::string description) {
  std::unique_ptr<BvhNodeFormat> f = make();
  const BvhFormatTraits& t = f->traits();
  auto refuse = [&](const std::string& why) {
    throw std::logic_error("BVH node format '" + name + "': " + why);
  };
  if (t.id == uint32_t(Accel::kKdTree)) refuse("id 0 is the kd-tree's");
  if (find(Accel(t.id))) refuse("id " + std::to_string(t.id) + " registered twice");
  if (t.branching != 2 && t.branching != 4 && t.branching != 8)  // what the builder builds
    refuse("a branching factor of " + std::to_string(t.branching) + " (expected 2, 4 or 8)");
  if (t.node_bytes == 0 || t.node_bytes % 16 || t.node_bytes > kBvhMaxNodeBytes)
    refuse(std::to_string(t.node_bytes) + "-byte nodes");
  registry_.add(name, std::move(make), std::move(description));  // refuses a name twice
  f->name_ = std::move(name);
  formats_.push_back(std::move(f));
}

const BvhNodeFormat* BvhFormats::find(Accel a) const {
  for (const auto& f : formats_)
    if (f->traits().id == uint32_t(a)) return f.get();
  return nullptr;
}

const BvhNodeFormat* BvhFormats::find(const std::string& name) const {
  for (const auto& f : formats_)
    if (f->name() == name) return f.get();
  return nullptr;
}

const BvhFormats& bvh_formats() { return formats(); }

bool register_bvh_format(std::string name, BvhFormats::Factory make, std::string description) {
  formats().add(std::move(name), std::move(make), std::move(description));
  return true;
}

}  // namespace rtsim
