// The memory image: kd-tree, leaf records, primitive lists, triangles, materials and lights laid
// out as one little-endian byte array. It is the contract between host and model: the reference
// tracer and the SystemC model both decode exactly these bytes. Layout: docs/memory-image.md.
#pragma once

#include "kernels/bvh_image.h"
#include "kernels/kdtree.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace rtsim {

namespace image {

inline constexpr uint32_t kMagic = 0x4d535452;  // "RTSM"
inline constexpr uint32_t kVersion = 1;
inline constexpr uint32_t kSectionAlign = 64;  // every section starts on a cache-line boundary
inline constexpr uint32_t kHeaderBytes = 128;
inline constexpr uint32_t kNodeBytes = 8;
inline constexpr uint32_t kLeafBytes = 16;
inline constexpr uint32_t kPrimBytes = 4;
inline constexpr uint32_t kTriangleBytes = 48;
inline constexpr uint32_t kMaterialBytes = 32;
inline constexpr uint32_t kLightBytes = 32;
inline constexpr uint32_t kMaxLights = 32;  // a leaf's LVB is one 32-bit word

struct Section {
  uint32_t base = 0;   // byte address of record 0
  uint32_t count = 0;  // number of records
};

struct Header {
  uint32_t magic = kMagic;
  uint32_t version = kVersion;
  Section nodes, leaves, prims, triangles, materials, lights;
  uint32_t image_bytes = 0;
  uint32_t light_count = 0;  // lights (the section holds twice as many records with area lights)
  AABB bounds;               // root cell of the kd-tree, or the BVH's root box
  Accel accel = Accel::kKdTree;  // what the node section holds (kernels/bvh_image.h)
  uint32_t node_bytes() const { return bvh_node_bytes(accel); }
};

// Leaf record: where the leaf's primitive list is, and its light visibility bits.
struct LeafRecord {
  uint32_t prim_offset = 0;  // index of the first entry in the primitive-list section
  uint32_t prim_count = 0;
  uint32_t lvb = 0;  // bit i = 1: shadow rays to light i must be traced
};

struct TriangleRecord {
  Vec3 v0, v1, v2;
  uint32_t material = 0;
};

struct MaterialRecord {
  Vec3 diffuse;
  float reflectance = 0;
  Vec3 specular;
  float shininess = 0;
};

// A light: a point, or an area light (position is its corner; edges from its second record).
struct LightRecord {
  Vec3 position;
  Vec3 color;
  uint32_t samples = 1;  // shadow rays per hit (1 for a point light)
  bool area = false;
  bool two_sided = true;
  Vec3 edge1{0.f}, edge2{0.f};
};
// Flags word of a light record (offset 28).
inline constexpr uint32_t kLightArea = 1u, kLightTwoSided = 2u;

// Decoders: each reads one record from the bytes at p (as fetched from memory).
inline uint32_t load_u32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}
inline float load_f32(const uint8_t* p) {
  float v;
  std::memcpy(&v, p, 4);
  return v;
}
inline Vec3 load_vec3(const uint8_t* p) {
  return Vec3(load_f32(p), load_f32(p + 4), load_f32(p + 8));
}

inline KdNode decode_node(const uint8_t* p) {
  KdNode n;
  n.word0 = load_u32(p);
  n.word1 = load_u32(p + 4);
  return n;
}
inline LeafRecord decode_leaf(const uint8_t* p) {
  return {load_u32(p), load_u32(p + 4), load_u32(p + 8)};
}
inline TriangleRecord decode_triangle(const uint8_t* p) {
  return {load_vec3(p), load_vec3(p + 12), load_vec3(p + 24), load_u32(p + 36)};
}
inline MaterialRecord decode_material(const uint8_t* p) {
  return {load_vec3(p), load_f32(p + 12), load_vec3(p + 16), load_f32(p + 28)};
}
// A light's first record; an area light's edges are in its second record (decode_light_area).
inline LightRecord decode_light(const uint8_t* p) {
  LightRecord l;
  l.position = load_vec3(p);
  l.samples = std::max<uint32_t>(1, load_u32(p + 12));
  l.color = load_vec3(p + 16);
  const uint32_t flags = load_u32(p + 28);
  l.area = flags & kLightArea;
  l.two_sided = !l.area || (flags & kLightTwoSided);
  return l;
}
inline void decode_light_area(const uint8_t* p, LightRecord& l) {
  l.edge1 = load_vec3(p);
  l.edge2 = load_vec3(p + 16);
}
Header decode_header(const uint8_t* p);

}  // namespace image

class MemoryImage {
 public:
  // Lays out the tree and the scene; every leaf's LVB word starts as all ones (no culling).
  MemoryImage(const Scene& scene, const KdTree& tree);
  // The same with a BVH in node format `accel` (bvh.branching must be the format's).
  MemoryImage(const Scene& scene, const Bvh& bvh, Accel accel);

  const std::vector<uint8_t>& bytes() const { return bytes_; }
  const image::Header& header() const { return header_; }

  uint32_t node_addr(uint32_t i) const { return header_.nodes.base + i * header_.node_bytes(); }
  uint32_t leaf_addr(uint32_t i) const { return header_.leaves.base + i * image::kLeafBytes; }
  uint32_t prim_addr(uint32_t i) const { return header_.prims.base + i * image::kPrimBytes; }
  uint32_t triangle_addr(uint32_t i) const {
    return header_.triangles.base + i * image::kTriangleBytes;
  }
  uint32_t material_addr(uint32_t i) const {
    return header_.materials.base + i * image::kMaterialBytes;
  }
  uint32_t light_addr(uint32_t i) const { return header_.lights.base + i * image::kLightBytes; }
  // An area light's second record: after every light's first one.
  uint32_t light_area_addr(uint32_t i) const { return light_addr(header_.light_count + i); }

  // Host-side decoding of the same bytes (the reference tracer's path into memory).
  KdNode node(uint32_t i) const { return image::decode_node(&bytes_[node_addr(i)]); }
  BvhNodeView bvh_node(uint32_t i) const {
    return decode_bvh_node(header_.accel, &bytes_[node_addr(i)]);
  }
  image::LeafRecord leaf(uint32_t i) const { return image::decode_leaf(&bytes_[leaf_addr(i)]); }
  uint32_t prim(uint32_t i) const { return image::load_u32(&bytes_[prim_addr(i)]); }
  image::TriangleRecord triangle(uint32_t i) const {
    return image::decode_triangle(&bytes_[triangle_addr(i)]);
  }
  image::MaterialRecord material(uint32_t i) const {
    return image::decode_material(&bytes_[material_addr(i)]);
  }
  image::LightRecord light(uint32_t i) const {
    image::LightRecord l = image::decode_light(&bytes_[light_addr(i)]);
    if (l.area) image::decode_light_area(&bytes_[light_area_addr(i)], l);
    return l;
  }

  // The LVB preprocessor writes each leaf's word here.
  void set_leaf_lvb(uint32_t leaf, uint32_t lvb);

 private:
  // The header's sections and sizes, for `nodes` node records and `leaves` leaf records.
  void lay_out(const Scene& scene, size_t nodes, size_t leaves, size_t prims);
  void write_header();
  void write_tree(const KdTree& tree);
  void write_leaf(uint32_t i, uint32_t first, uint32_t count);
  void write_scene(const Scene& scene);

  std::vector<uint8_t> bytes_;
  image::Header header_;
};

}  // namespace rtsim
