// A BVH node format that exists only in this test: bvh8r, Embree's eight-wide structure-of-arrays
// node with its children stored in reverse slot order, and with a decode cost (decode_cycles).
// It is registered here and nowhere else: no file in kernels/, model/, testbench/, reports/ or
// scripts/ names it, yet images are built in it, the reference tracer walks them, `run` takes it
// as run.accel, the BVH machine renders the reference's frame from it and charges its decode.
#include "kernels/bvh_format.h"
#include "kernels/bvh_node_words.h"
#include "kernels/reference_tracer.h"
#include "testbench/commands.h"
#include "tests/kernels/bvh_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace rtsim {
namespace {

namespace fs = std::filesystem;
using namespace bvh_words;
using nlohmann::json;

constexpr uint32_t kW = 8;

class ReversedBvh8Format final : public BvhNodeFormat {
 public:
  ReversedBvh8Format() : BvhNodeFormat({/*id=*/0x7e57, kW, 32 * kW, /*decode_cycles=*/true}) {}

  BvhNodeSection encode(const Bvh& bvh) const override {
    return encode_in_tree_order(bvh, *this, [](const BvhNode& n, uint8_t* p) {
      for (uint32_t i = 0; i < n.child_count; ++i) {
        const uint32_t slot = n.child_count - 1 - i;
        const AABB& b = n.children[i].box;
        for (int a = 0; a < 3; ++a) {
          put_f32(p + 4 * ((2 * a) * kW + slot), b.lo[a]);
          put_f32(p + 4 * ((2 * a + 1) * kW + slot), b.hi[a]);
        }
        put_u32(p + 4 * (6 * kW + slot), child_ref(n.children[i]));
      }
      put_u32(p + 28 * kW, n.child_count);
    });
  }

  BvhNodeView decode(const uint8_t* p) const override {
    BvhNodeView v;
    v.count = std::min(load_u32(p + 28 * kW), kW);
    for (uint32_t i = 0; i < v.count; ++i) {
      for (int a = 0; a < 3; ++a) {
        v.box[i].lo[a] = load_f32(p + 4 * ((2 * a) * kW + i));
        v.box[i].hi[a] = load_f32(p + 4 * ((2 * a + 1) * kW + i));
      }
      const uint32_t ref = load_u32(p + 4 * (6 * kW + i));
      v.leaf[i] = is_leaf_ref(ref);
      v.ref[i] = ref_index(ref);
    }
    return v;
  }
};

const bool registered = register_bvh_format(
    "bvh8r", [] { return std::make_unique<ReversedBvh8Format>(); },
    "bvh8 with its children in reverse slot order (a test's)");

const Accel kBvh8r = parse_accel("bvh8r");

TEST(RegisteredBvhFormat, ItsNameAndIdAreTheRegistrys) {
  ASSERT_TRUE(registered);
  EXPECT_EQ(uint32_t(kBvh8r), 0x7e57u);
  EXPECT_EQ(to_string(kBvh8r), "bvh8r");
  EXPECT_TRUE(known_accel(kBvh8r));
  EXPECT_EQ(accel_branching(kBvh8r), 8u);
  EXPECT_EQ(bvh_node_bytes(kBvh8r), 256u);
  EXPECT_EQ(accel_names().back().name, "bvh8r");
  try {
    parse_accel("bvh9");
    ADD_FAILURE() << "bvh9 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bvh8r'"), std::string::npos) << e.what();
  }
  // A second format with its name or its id is a programming error.
  EXPECT_THROW(register_bvh_format(
                   "bvh8r", [] { return std::make_unique<ReversedBvh8Format>(); }, ""),
               std::logic_error);
  EXPECT_THROW(register_bvh_format(
                   "other", [] { return std::make_unique<ReversedBvh8Format>(); }, ""),
               std::logic_error);
}

// Its records are not bvh8's bytes, but decode to bvh8's children in reverse order.
TEST(RegisteredBvhFormat, RecordsAreBvh8sChildrenReversed) {
  const Scene city = bvh_test::load_city().scene;
  BvhConfig c;
  c.branching = 8;
  const Bvh bvh = build_bvh(city.triangles, c);
  const MemoryImage r(city, bvh, kBvh8r), e(city, bvh, bvh_test::kBvh8);
  EXPECT_EQ(image::decode_header(r.bytes().data()).accel, kBvh8r);
  ASSERT_EQ(r.header().nodes.count, e.header().nodes.count);
  uint32_t differ = 0;
  for (uint32_t n = 0; n < r.header().nodes.count; ++n) {
    const BvhNodeView a = r.bvh_node(n), b = e.bvh_node(n);
    ASSERT_EQ(a.count, b.count) << "node " << n;
    for (uint32_t i = 0; i < a.count; ++i) {
      const uint32_t j = b.count - 1 - i;
      EXPECT_EQ(a.ref[i], b.ref[j]) << "node " << n;
      EXPECT_EQ(a.leaf[i], b.leaf[j]) << "node " << n;
      EXPECT_EQ(bvh_test::bits(a.box[i].lo.x), bvh_test::bits(b.box[j].lo.x)) << "node " << n;
    }
    differ += a.count > 1 && !std::equal(r.bytes().begin() + r.node_addr(n),
                                         r.bytes().begin() + r.node_addr(n) + 256,
                                         e.bytes().begin() + e.node_addr(n));
  }
  EXPECT_GT(differ, 0u);
}

// One run of the city at 64x36 on the BVH machine, checked against the reference tracer. A
// process holds one SystemC simulation, so each run is a child process: a death-test child in
// gtest's threadsafe style, which is this binary again (so it knows the format) and runs the test
// from its start up to its own run. The runs write under `out`.
void run_city(const std::string& accel, const fs::path& out, const std::string& set = {}) {
  RunArgs args;
  args.sources.scene_file = (test::source_dir() / "configs/scenes/city.yaml").string();
  args.sources.hw_file = (test::source_dir() / "configs/hw/bvh-tni.yaml").string();
  args.sources.run_flags["accel"] = accel;
  args.sources.run_flags["width"] = 64;
  args.sources.run_flags["height"] = 36;
  args.sources.run_flags["check"] = true;
  args.sources.run_flags["plots"] = false;
  if (!set.empty()) args.sources.set.push_back(set);
  args.out = out.string();
  args.quiet = true;
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(std::exit(run_model(args)), testing::ExitedWithCode(0), "") << accel << " " << set;
}

json report(const fs::path& out) { return json::parse(test::slurp(out / "report.json")); }

// The BVH machine walks it: its frame is the reference tracer's (the run's --check) and bvh8's;
// its decode_cycles trait makes the unit charge hw bvh.decode_latency, which bvh8 does not.
TEST(RegisteredBvhFormat, TheModelRendersTheReferencesFrameAndChargesItsDecode) {
  // The parent's folder, which its children inherit.
  if (!std::getenv("RTSIM_TEST_BVH8R_OUT"))
    setenv("RTSIM_TEST_BVH8R_OUT", test::temp_dir("registered-bvh-format").c_str(), 1);
  const fs::path out = std::getenv("RTSIM_TEST_BVH8R_OUT");
  const std::string slow = "hw.bvh.decode_latency=7";
  run_city("bvh8r", out / "bvh8r");
  run_city("bvh8r", out / "bvh8r-7", slow);
  run_city("bvh8", out / "bvh8");
  run_city("bvh8", out / "bvh8-7", slow);
  if (HasFailure()) return;

  const json r = report(out / "bvh8r"), rs = report(out / "bvh8r-7");
  const json e = report(out / "bvh8"), es = report(out / "bvh8-7");
  for (const json* j : {&r, &rs}) {
    EXPECT_EQ((*j)["accel"], "bvh8r");
    EXPECT_TRUE((*j)["reference_check"]["image_identical"].get<bool>());
    EXPECT_EQ((*j)["reference_check"]["mismatched_pixels"], 0);
  }
  EXPECT_EQ(test::slurp(out / "bvh8r/mask.npy"), test::slurp(out / "bvh8/mask.npy"));
  EXPECT_EQ(test::slurp(out / "bvh8r/render.png"), test::slurp(out / "bvh8/render.png"));
  const json& visits = r["stats"]["bvh"]["total"]["node_fetches"];
  EXPECT_GT(visits.get<double>(), 0);
  EXPECT_EQ(rs["stats"]["bvh"]["total"]["node_fetches"], visits);
  EXPECT_GT(rs["cycles_total"].get<double>(), r["cycles_total"].get<double>());
  EXPECT_EQ(es["cycles_total"], e["cycles_total"]);  // bvh8 decodes for free
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtsim
