#include "kernels/memory_image.h"

#include "common/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace rtsim {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "IEEE-754 floats");

namespace image {
namespace {

void store_u32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
void store_f32(uint8_t* p, float v) { std::memcpy(p, &v, 4); }
void store_vec3(uint8_t* p, const Vec3& v) {
  store_f32(p, v.x);
  store_f32(p + 4, v.y);
  store_f32(p + 8, v.z);
}
uint64_t align_up(uint64_t x) { return (x + kSectionAlign - 1) / kSectionAlign * kSectionAlign; }

}  // namespace

Header decode_header(const uint8_t* p) {
  Header h;
  h.magic = load_u32(p);
  h.version = load_u32(p + 4);
  Section* sections[] = {&h.nodes, &h.leaves, &h.prims, &h.triangles, &h.materials, &h.lights};
  for (int i = 0; i < 6; ++i) {
    sections[i]->base = load_u32(p + 8 + 8 * i);
    sections[i]->count = load_u32(p + 12 + 8 * i);
  }
  h.image_bytes = load_u32(p + 56);
  h.light_count = load_u32(p + 60);
  h.bounds.lo = load_vec3(p + 64);
  h.bounds.hi = load_vec3(p + 76);
  h.accel = static_cast<Accel>(load_u32(p + 88));
  return h;
}

}  // namespace image

using namespace image;

MemoryImage::MemoryImage(const Scene& scene, const KdTree& tree) {
  header_.bounds = tree.bounds;
  lay_out(scene, tree.nodes.size(), tree.leaves.size(), tree.prims.size());
  bytes_.assign(header_.image_bytes, 0);
  write_header();
  write_tree(tree);
  write_scene(scene);
}

MemoryImage::MemoryImage(const Scene& scene, const Bvh& bvh, Accel accel) {
  const BvhNodeSection nodes = encode_bvh_nodes(bvh, accel);
  header_.accel = accel;
  header_.bounds = bvh.bounds;
  lay_out(scene, nodes.count, bvh.leaves.size(), bvh.prims.size());
  bytes_.assign(header_.image_bytes, 0);
  write_header();
  std::copy(nodes.bytes.begin(), nodes.bytes.end(), bytes_.begin() + header_.nodes.base);
  for (size_t i = 0; i < bvh.leaves.size(); ++i)
    write_leaf(static_cast<uint32_t>(i), bvh.leaves[i].first, bvh.leaves[i].count);
  for (size_t i = 0; i < bvh.prims.size(); ++i)
    store_u32(&bytes_[prim_addr(static_cast<uint32_t>(i))], bvh.prims[i]);
  write_scene(scene);
}

void MemoryImage::lay_out(const Scene& scene, size_t nodes, size_t leaves, size_t prims) {
  Header& h = header_;
  uint64_t cursor = kHeaderBytes;
  // Addresses are 32-bit in every record; refuse what cannot be addressed, before any truncation.
  auto place = [&](Section& s, size_t count, uint32_t record_bytes) {
    const uint64_t base = align_up(cursor);
    cursor = base + uint64_t(count) * record_bytes;
    if (align_up(cursor) > std::numeric_limits<uint32_t>::max())
      throw InputError(
          fmt::format("scene too large for the 32-bit memory image (more than {} bytes)",
                      std::numeric_limits<uint32_t>::max()));
    s.base = static_cast<uint32_t>(base);
    s.count = static_cast<uint32_t>(count);
  };
  place(h.nodes, nodes, h.node_bytes());
  place(h.leaves, leaves, kLeafBytes);
  place(h.prims, prims, kPrimBytes);
  place(h.triangles, scene.triangles.size(), kTriangleBytes);
  place(h.materials, scene.materials.size(), kMaterialBytes);
  // With an area light, a second block of records holds the lights' edges (point-only scenes keep
  // the one block, byte for byte as before).
  const bool any_area = std::any_of(scene.lights.begin(), scene.lights.end(),
                                    [](const Light& l) { return l.is_area(); });
  place(h.lights, scene.lights.size() * (any_area ? 2 : 1), kLightBytes);
  h.image_bytes = static_cast<uint32_t>(align_up(cursor));
  h.light_count = static_cast<uint32_t>(scene.lights.size());
}

void MemoryImage::write_header() {
  const Header& h = header_;
  uint8_t* b = bytes_.data();
  store_u32(b, h.magic);
  store_u32(b + 4, h.version);
  const Section* sections[] = {&h.nodes,     &h.leaves,    &h.prims,
                               &h.triangles, &h.materials, &h.lights};
  for (int i = 0; i < 6; ++i) {
    store_u32(b + 8 + 8 * i, sections[i]->base);
    store_u32(b + 12 + 8 * i, sections[i]->count);
  }
  store_u32(b + 56, h.image_bytes);
  store_u32(b + 60, h.light_count);
  store_vec3(b + 64, h.bounds.lo);
  store_vec3(b + 76, h.bounds.hi);
  store_u32(b + 88, static_cast<uint32_t>(h.accel));  // 0 for the kd-tree: its images unchanged
}

void MemoryImage::write_tree(const KdTree& tree) {
  uint8_t* b = bytes_.data();
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    uint8_t* p = b + node_addr(static_cast<uint32_t>(i));
    store_u32(p, tree.nodes[i].word0);
    store_u32(p + 4, tree.nodes[i].word1);
  }
  for (size_t i = 0; i < tree.leaves.size(); ++i)
    write_leaf(static_cast<uint32_t>(i), tree.leaves[i].first, tree.leaves[i].count);
  for (size_t i = 0; i < tree.prims.size(); ++i)
    store_u32(b + prim_addr(static_cast<uint32_t>(i)), tree.prims[i]);
}

void MemoryImage::write_leaf(uint32_t i, uint32_t first, uint32_t count) {
  const uint32_t lights = header_.light_count;
  uint8_t* p = &bytes_[leaf_addr(i)];
  store_u32(p, first);
  store_u32(p + 4, count);
  store_u32(p + 8, lights >= 32 ? ~0u : (1u << lights) - 1u);  // no culling until the LVB is set
}

void MemoryImage::write_scene(const Scene& scene) {
  uint8_t* b = bytes_.data();
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    uint8_t* p = b + triangle_addr(static_cast<uint32_t>(i));
    store_vec3(p, t.v0);
    store_vec3(p + 12, t.v1);
    store_vec3(p + 24, t.v2);
    store_u32(p + 36, t.material);
  }
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    uint8_t* p = b + material_addr(static_cast<uint32_t>(i));
    store_vec3(p, m.diffuse);
    store_f32(p + 12, m.reflectance);
    store_vec3(p + 16, m.specular);
    store_f32(p + 28, m.shininess);
  }
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    uint8_t* p = b + light_addr(static_cast<uint32_t>(i));
    store_vec3(p, l.position);
    store_vec3(p + 16, l.color);
    if (l.samples != 1) store_u32(p + 12, l.samples);
    if (!l.is_area()) continue;
    store_u32(p + 28, kLightArea | (l.two_sided ? kLightTwoSided : 0u));
    uint8_t* a = b + light_area_addr(static_cast<uint32_t>(i));
    store_vec3(a, l.edge1);
    store_vec3(a + 16, l.edge2);
  }
}

void MemoryImage::set_leaf_lvb(uint32_t leaf, uint32_t lvb) {
  store_u32(&bytes_[leaf_addr(leaf) + 8], lvb);
}

}  // namespace rtsim
