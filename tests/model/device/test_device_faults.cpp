// The device on memory that does not hold a readable image (issue 39): a zeroed memory behind a
// valid header, and images with one node garbled (a child past the nodes section, a cycle of
// nodes, a BVH's child past its section). Each frame must end, in bounded time, with STATUS
// error kBadImage, the interrupt, every transaction complete under the protocol checker, and
// the faults counted by name; nothing may be thrown past SystemC.
#include "config_loader/hw_config.h"
#include "kernels/bvh.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "tests/model/city_frame.h"
#include "tests/model/memory/tlm_target_styles.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstring>

namespace rtsim::model {
namespace {

constexpr int kWidth = 32, kHeight = 18;
// A frame must end before this: far beyond a legal frame of this size, far below a hang.
constexpr double kLimitMs = 50;

// A host that programs `image`'s header over whatever memory holds, starts one frame and waits
// for the interrupt.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  sc_core::sc_in<bool> irq{"irq"};

  Host(sc_core::sc_module_name name, const MemoryImage& image, const FrameSetup& setup)
      : sc_core::sc_module(name), image_(image), setup_(setup) {
    SC_THREAD(run);
  }
  bool ended = false;
  uint32_t status = 0, frames = 0;
  uint64_t cycles = 0;
  sc_core::sc_time irq_at;

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    DeviceDriver regs(*registers.operator->(), 0);  // the forward path, as any initiator gives
    regs.program(image_, setup_);
    regs.start();
    sc_core::wait(irq.posedge_event());
    irq_at = sc_core::sc_time_stamp();
    status = regs.read_register(regs::kStatus);
    frames = regs.read_register(regs::kFrames);
    cycles = regs.finish();
    ended = true;
  }
  const MemoryImage& image_;
  FrameSetup setup_;
};

struct Outcome {
  bool ended = false;
  uint32_t status = 0, frames = 0;
  uint64_t cycles = 0;
  sc_core::sc_time irq_at;
  AcceleratorResult result;
  uint64_t faults(const std::string& kind) const {
    return uint64_t(result.stats["faults"][kind].get<double>());
  }
};

// One frame of the city's camera over `memory` (the image's bytes, or not), on a 40 ns memory
// behind the protocol checker, with `image`'s header in the registers.
Outcome run_frame(const AcceleratorConfig& cfg, const MemoryImage& image, const Camera& camera,
                  std::vector<uint8_t> memory) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const FrameSetup setup = frame_after_image(image, camera, kWidth, kHeight, true);
  memory.resize(setup.fb_base + uint64_t(kWidth) * kHeight * 64 * (cfg.reflection_depth + 1), 0);
  SimulationHooks hooks;
  hooks.tlm_checks = true;
  Accelerator device("device", cfg, hooks, MemoryTarget::kApproximatelyTimed);
  test::StyledMemory mem("memory", test::TargetStyle::kAcceptLater, std::move(memory),
                         sc_core::sc_time(40, sc_core::SC_NS), sc_core::sc_time(2, sc_core::SC_NS));
  Host host("host", image, setup);
  sc_core::sc_signal<bool> irq("irq");
  device.memory_socket().bind(mem.socket);
  host.registers.bind(device.register_socket());
  device.irq.bind(irq);
  host.irq.bind(irq);
  sc_core::sc_start(kLimitMs,
                    sc_core::SC_MS);  // an sc_report would throw out of here and fail the test
  EXPECT_TRUE(host.ended) << "no interrupt within " << kLimitMs << " ms";
  return Outcome{host.ended, host.status, host.frames, host.cycles, host.irq_at, device.result()};
}

uint32_t error_of(uint32_t status) { return status >> regs::kErrorShift; }

uint64_t all_faults(const Outcome& o) {
  uint64_t n = 0;
  for (const auto& [kind, count] : o.result.stats["faults"].items()) n += o.faults(kind);
  return n;
}

// The checks every unreadable image must pass: the frame ended (DONE, the interrupt, FRAMES),
// with kBadImage, every primary ray retired, and faults counted.
void expect_faulted_frame(const Outcome& o) {
  EXPECT_EQ(error_of(o.status), regs::kBadImage);
  EXPECT_TRUE(o.status & regs::kDone);
  EXPECT_FALSE(o.status & regs::kBusy);
  EXPECT_EQ(o.frames, 1u);
  EXPECT_EQ(o.cycles, o.result.cycles_total);
  EXPECT_EQ(o.result.primary_rays, uint64_t(kWidth) * kHeight);
  EXPECT_GT(all_faults(o), 0u);
  // The figures the docs quote.
  std::cout << "cycles " << o.result.cycles_total << ", interrupt at " << o.irq_at << ", faults "
            << o.result.stats["faults"] << ", primary hits " << o.result.primary_hits << "\n";
}

// Rewrites kd-tree node `index` of `bytes` (an image at address 0).
void put_node(std::vector<uint8_t>& bytes, const MemoryImage& image, uint32_t index, KdNode n) {
  uint8_t* p = bytes.data() + image.header().nodes.base + index * image::kNodeBytes;
  std::memcpy(p, &n.word0, 4);
  std::memcpy(p + 4, &n.word1, 4);
}

TEST(DeviceFaults, AZeroedMemoryEndsTheFrameWithBadImage) {
  const test::CityFrame city(kWidth, kHeight);
  const std::vector<uint8_t> zeros(city.image->bytes().size(), 0);
  const Outcome o = run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, zeros);
  expect_faulted_frame(o);
  // Node 0 reads as an inner node whose above child is itself.
  EXPECT_GT(o.faults("node_index"), 0u);
  EXPECT_EQ(o.result.primary_hits, 0u);  // no triangle was ever read as one
}

TEST(DeviceFaults, AChildPastTheNodesSectionEndsTheFrameWithBadImage) {
  const test::CityFrame city(kWidth, kHeight);
  std::vector<uint8_t> bytes = city.image->bytes();
  const KdNode root = city.image->node(0);
  ASSERT_FALSE(root.is_leaf());
  const uint32_t past = city.image->header().nodes.count + 5;
  put_node(bytes, *city.image, 0, KdNode::inner(root.axis(), root.split(), past));
  const Outcome o = run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, bytes);
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("node_index"), 0u);
  // The rays that never go above the root's split still find their hits.
  EXPECT_GT(o.result.primary_hits, 0u);
}

TEST(DeviceFaults, ANodeThatIsItsOwnChildEndsEachRayAtItsFirstStep) {
  const test::CityFrame city(kWidth, kHeight);
  std::vector<uint8_t> bytes = city.image->bytes();
  // The root as its own above child, its split below the scene so that every ray goes there: a
  // walk that would push nothing and move for ever. Nodes are stored depth first, so a child at
  // or before its parent is caught when the parent is read.
  put_node(bytes, *city.image, 0, KdNode::inner(0, -1e30f, 0));
  const Outcome o = run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, bytes);
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("node_index"), 0u);
  EXPECT_EQ(o.result.primary_hits, 0u);
  // Each ray that entered the scene's box fetched the root once and stopped.
  const auto fetches = uint64_t(o.result.stats["trv"]["total"]["node_fetches"].get<double>());
  EXPECT_EQ(fetches, o.faults("node_index"));
}

// The city's image with nodes 0..levels-2 splitting the scene's box in its middle along x, each
// with node i + 1 as both its below and its above child (children after their parents, as
// stored depth first), and an empty leaf last: a ray that crosses the middle pushes at every
// level and would visit 2^(levels-1) paths, each legal to look at.
std::vector<uint8_t> ladder(const test::CityFrame& city, uint32_t levels) {
  std::vector<uint8_t> bytes = city.image->bytes();
  const image::Header& h = city.image->header();
  const float middle = 0.5f * (h.bounds.lo.x + h.bounds.hi.x);
  for (uint32_t i = 0; i + 1 < levels; ++i)
    put_node(bytes, *city.image, i, KdNode::inner(0, middle, i + 1));
  put_node(bytes, *city.image, levels - 1, KdNode::leaf(0, 0));
  return bytes;
}

TEST(DeviceFaults, ALadderOfSharedChildrenIsCaughtByTheStepBound) {
  const test::CityFrame city(kWidth, kHeight);
  // 2^20 paths, a stack of 20 at most: only the count of steps tells it from a tree.
  constexpr uint32_t kLevels = 21;
  const image::Header& h = city.image->header();
  ASSERT_LT(h.nodes.count, 1u << (kLevels - 1));
  const Outcome o =
      run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, ladder(city, kLevels));
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("step_bound"), 0u);
  EXPECT_EQ(o.faults("node_index") + o.faults("stack_overflow"), 0u);
  EXPECT_EQ(o.result.primary_hits, 0u);
  // A faulting ray made exactly as many steps as the tree has nodes.
  const auto fetches = uint64_t(o.result.stats["trv"]["total"]["node_fetches"].get<double>());
  EXPECT_GE(fetches, o.faults("step_bound") * h.nodes.count);
}

TEST(DeviceFaults, ALadderDeeperThanTheStackOverflowsIt) {
  const test::CityFrame city(kWidth, kHeight);
  // A push per level on the first way down: more levels than stack entries.
  const uint32_t levels = kTraversalStackDepth + 6;
  ASSERT_LT(levels, city.image->header().nodes.count);
  const Outcome o =
      run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, ladder(city, levels));
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("stack_overflow"), 0u);
  EXPECT_EQ(all_faults(o), o.faults("stack_overflow"));
  EXPECT_EQ(o.result.primary_hits, 0u);
}

// Writes `value` at byte `offset` of every record of `section` (of `record_bytes` each).
void put_in_every(std::vector<uint8_t>& bytes, const image::Section& section, uint32_t record_bytes,
                  uint32_t offset, uint32_t value) {
  for (uint32_t i = 0; i < section.count; ++i)
    std::memcpy(bytes.data() + section.base + i * record_bytes + offset, &value, 4);
}

// One frame of `city` with a u32 field of every record of one section set to the count of
// another (one past its last record): faults of `kind`, and no other, for every ray that reads
// such a record.
using SectionOf = const image::Section image::Header::*;
Outcome run_with_every(const test::CityFrame& city, SectionOf section, uint32_t record_bytes,
                       uint32_t offset, SectionOf past, const std::string& kind) {
  std::vector<uint8_t> bytes = city.image->bytes();
  const image::Header& h = city.image->header();
  put_in_every(bytes, h.*section, record_bytes, offset, (h.*past).count);
  const Outcome o = run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, bytes);
  expect_faulted_frame(o);
  EXPECT_EQ(o.result.primary_hits, 0u);  // every ray that reached a leaf read one
  EXPECT_GT(o.faults(kind), 0u);
  EXPECT_EQ(all_faults(o), o.faults(kind));
  return o;
}

TEST(DeviceFaults, LeavesPastTheLeavesSectionAreCounted) {
  const test::CityFrame city(kWidth, kHeight);
  std::vector<uint8_t> bytes = city.image->bytes();
  const image::Header& h = city.image->header();
  for (uint32_t i = 0; i < h.nodes.count; ++i) {
    const KdNode n = city.image->node(i);
    if (n.is_leaf()) put_node(bytes, *city.image, i, KdNode::leaf(h.leaves.count, n.prim_count()));
  }
  const Outcome o = run_frame(AcceleratorConfig{}, *city.image, city.scene.camera, bytes);
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("leaf_index"), 0u);
  EXPECT_EQ(all_faults(o), o.faults("leaf_index"));
  EXPECT_EQ(o.result.primary_hits, 0u);
}

TEST(DeviceFaults, LeafRecordsWhoseListsLiePastThePrimsSectionAreCounted) {
  const test::CityFrame city(kWidth, kHeight);
  run_with_every(city, &image::Header::leaves, image::kLeafBytes, 0, &image::Header::prims,
                 "prim_range");
}

TEST(DeviceFaults, PrimitivesNamingTrianglesPastTheirSectionAreCounted) {
  const test::CityFrame city(kWidth, kHeight);
  run_with_every(city, &image::Header::prims, image::kPrimBytes, 0, &image::Header::triangles,
                 "triangle_index");
}

TEST(DeviceFaults, TrianglesNamingMaterialsPastTheirSectionFaultEveryHit) {
  const test::CityFrame city(kWidth, kHeight);
  const Outcome o = run_with_every(city, &image::Header::triangles, image::kTriangleBytes, 36,
                                   &image::Header::materials, "material_index");
  // Only shading reads a material, once per hit: each of the reference's hits faults.
  uint64_t hits = 0;
  for (const PixelRecord& p : city.reference.pixels) hits += p.hit.tri != kNoHit;
  EXPECT_GT(hits, 0u);
  EXPECT_EQ(o.faults("material_index"), hits);
}

// The city as a bvh8 image, for the BVH machine of configs/hw/bvh-tni.yaml.
struct CityBvh8 {
  CityBvh8()
      : city(kWidth, kHeight),
        cfg(load_hw_config((test::source_dir() / "configs/hw/bvh-tni.yaml").string())),
        image(city.scene, build_bvh(city.scene.triangles, bvh8()), parse_accel("bvh8")) {}
  static BvhConfig bvh8() {
    BvhConfig c;
    c.branching = 8;
    return c;
  }
  // The bytes with the root's child slot 0 (after the six rows of 8 bounds) referring to `ref`.
  std::vector<uint8_t> root_child(uint32_t ref) const {
    std::vector<uint8_t> bytes = image.bytes();
    std::memcpy(bytes.data() + image.header().nodes.base + 4 * 6 * 8, &ref, 4);
    return bytes;
  }
  test::CityFrame city;
  AcceleratorConfig cfg;
  MemoryImage image;
};

TEST(DeviceFaults, ABvhChildPastTheNodesSectionEndsTheFrameWithBadImage) {
  const CityBvh8 b;
  const Outcome o = run_frame(b.cfg, b.image, b.city.scene.camera,
                              b.root_child(b.image.header().nodes.count + 3));
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("node_index"), 0u);
  EXPECT_GT(o.result.primary_hits, 0u);  // the rays that miss that child's box
}

TEST(DeviceFaults, ABvhRootThatIsItsOwnChildEndsTheFrameWithBadImage) {
  const CityBvh8 b;
  const Outcome o = run_frame(b.cfg, b.image, b.city.scene.camera, b.root_child(0));
  expect_faulted_frame(o);
  EXPECT_GT(o.faults("node_index"), 0u);
  EXPECT_EQ(o.faults("step_bound") + o.faults("stack_overflow"), 0u);
}

}  // namespace
}  // namespace rtsim::model
