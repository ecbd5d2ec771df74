// A BVH node format: how a BVH's nodes sit in the memory image's nodes section, as one
// registered class in its own file (Ramulator 2.0's way, common/registry.h). The format's file
// holds its name, its id, its traits, its encoder and its decoder; kernels/bvh_formats.cpp lists
// the files. Everything else (the image, the reference tracer, the BVH unit, the device's
// checks, the command line and its errors) asks the registry.
#pragma once

#include "kernels/bvh_image.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rtsim {

// The largest node record the BVH unit holds while it fetches one (model/units/bvh_unit.h).
inline constexpr uint32_t kBvhMaxNodeBytes = 256;

// What the rest of the simulator needs to know of a format besides its bytes.
struct BvhFormatTraits {
  // The header word `accel` and the device's register: part of the memory image format and the
  // register map, so never renumbered or reused (0 is the kd-tree's).
  uint32_t id = 0;
  uint32_t branching = 0;   // children per node: the BVH builder's 2, 4 or 8
  uint32_t node_bytes = 0;  // one record, a multiple of 16, at most kBvhMaxNodeBytes
  // Decoding a node costs the BVH unit hw `bvh.decode_latency` extra cycles (a compressed node).
  bool decode_cycles = false;
};

class BvhNodeFormat {
 public:
  explicit BvhNodeFormat(const BvhFormatTraits& traits) : traits_(traits) {}
  virtual ~BvhNodeFormat() = default;

  const std::string& name() const { return name_; }
  const BvhFormatTraits& traits() const { return traits_; }

  // The nodes section of `bvh`, whose branching factor is the format's (encode_bvh_nodes checks
  // it first): root first, and every inner child's record after its parent's (the walks refuse
  // an image otherwise). Throws std::length_error naming the format, the field and the count when
  // the tree does not fit the format's index fields.
  virtual BvhNodeSection encode(const Bvh& bvh) const = 0;
  // One record of traits().node_bytes bytes, as fetched.
  virtual BvhNodeView decode(const uint8_t* p) const = 0;

 private:
  friend class BvhFormats;
  BvhFormatTraits traits_;
  std::string name_;  // the registered one
};

// The registered formats, one instance each, by name and by id.
class BvhFormats {
 public:
  using Factory = std::function<std::unique_ptr<BvhNodeFormat>()>;

  // A name or an id registered twice, or the id 0, is a programming error (std::logic_error).
  void add(std::string name, Factory make, std::string description);
  const BvhNodeFormat* find(Accel a) const;
  const BvhNodeFormat* find(const std::string& name) const;
  const std::vector<RegisteredName>& names() const { return registry_.names(); }

 private:
  Registry<BvhNodeFormat> registry_{"BVH node format"};
  std::vector<std::unique_ptr<const BvhNodeFormat>> formats_;  // in the list's order
};

const BvhFormats& bvh_formats();
// Adds a format (a test's, say) after the listed ones, before any image uses it. Returns true
// (for a static initialiser).
bool register_bvh_format(std::string name, BvhFormats::Factory make, std::string description);

}  // namespace rtsim
