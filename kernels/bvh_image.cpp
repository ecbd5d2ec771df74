// The acceleration structure's name, id and traits, and the node formats' encode and decode, as
// the registry (kernels/bvh_format.h) answers them; the kd-tree is the one structure not in it.
#include "kernels/bvh_image.h"
#include "kernels/names.h"

#include "kernels/bvh_format.h"
#include "kernels/memory_image.h"

#include <stdexcept>

namespace rtsim {

namespace {

const BvhNodeFormat& format_of(Accel a, const char* what) {
  if (const BvhNodeFormat* f = bvh_formats().find(a)) return *f;
  throw std::invalid_argument(std::string(what) + ": " + to_string(a) +
                              " is not a BVH node format");
}

}  // namespace

std::vector<RegisteredName> accel_names() {
  std::vector<RegisteredName> names{{kKdTreeFamily, "the paper's kd-tree, 8 B nodes"}};
  for (const RegisteredName& n : bvh_formats().names()) names.push_back(n);
  return names;
}

std::string to_string(Accel a) {
  if (!is_bvh(a)) return kKdTreeFamily;
  const BvhNodeFormat* f = bvh_formats().find(a);
  return f ? f->name() : "accel " + std::to_string(uint32_t(a));
}

Accel parse_accel(const std::string& name, const std::string& key) {
  if (name == kKdTreeFamily) return Accel::kKdTree;
  if (const BvhNodeFormat* f = bvh_formats().find(name)) return Accel(f->traits().id);
  throw std::invalid_argument(key + ": expected " + quoted_names(accel_names()) + ", got '" + name +
                              "'");
}

bool known_accel(Accel a) { return !is_bvh(a) || bvh_formats().find(a); }

uint32_t accel_branching(Accel a) {
  const BvhNodeFormat* f = bvh_formats().find(a);
  return f ? f->traits().branching : 0;
}

uint32_t bvh_node_bytes(Accel a) {
  if (!is_bvh(a)) return image::kNodeBytes;
  const BvhNodeFormat* f = bvh_formats().find(a);
  return f ? f->traits().node_bytes : 0;
}

BvhNodeSection encode_bvh_nodes(const Bvh& bvh, Accel a) {
  const BvhNodeFormat& f = format_of(a, "encode_bvh_nodes");
  if (bvh.branching != f.traits().branching)
    throw std::invalid_argument(f.name() + " needs a branching factor of " +
                                std::to_string(f.traits().branching) + ", got " +
                                std::to_string(bvh.branching));
  return f.encode(bvh);
}

BvhNodeView decode_bvh_node(Accel a, const uint8_t* p) {
  return format_of(a, "decode_bvh_node").decode(p);
}

}  // namespace rtsim
