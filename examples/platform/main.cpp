// A small SystemC platform that drives the accelerator as a device: a driver thread, a router of
// our own (router.h), one memory (memory.h), and the accelerator with its registers and interrupt.
// The hardware is a hardware file of the package's configs (rtsim_CONFIG_DIR, set by
// find_package(rtsim)): configs/hw/tni-paper.yaml, the paper's T&I engine, unless one is named.
// The memory is sized from the layout the accelerator gives before elaboration (memory_layout).
// The driver loads the scene's memory image over TLM, programs two frames of it with two cameras
// (the scene's and one turned 20 degrees to the right), starts each, waits for the interrupt,
// reads the hit records back over TLM and checks them against the reference tracer; it prints
// a JSON line of the hardware file and the memory's size, then one per frame. Exit status 1 if a
// record is wrong, 2 for bad input.
//
//   platform_example SCENE [WIDTH HEIGHT [HW.yaml]]   160x90 by default; SCENE is
//     city          the procedural city (configs/scenes/city.yaml of the package)
//     FILE.yaml     a scene file (docs/scene-files.md; geometry under $RTSIM_SCENE_ROOT)
//     FILE.aff      a BART scene (e.g. the kitchen)
#include "memory.h"
#include "router.h"

#include "config_loader/hw_config.h"
#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "kernels/lvb.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "model/units/ray_generator.h"
#include "scene_loader/aff_loader.h"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <systemc>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using rtsim::model::DeviceDriver;
namespace regs = rtsim::model::regs;

constexpr uint64_t kRegisterBase = 0xf0000000;  // the registers' window on the router

rtsim::Camera turned(const rtsim::Camera& c, float degrees) {
  const rtsim::Vec3 d = glm::normalize(c.dir);
  const rtsim::Vec3 right = glm::normalize(glm::cross(d, c.up));
  const float a = degrees * 3.14159265f / 180.f;
  rtsim::Camera out = c;
  out.dir = glm::normalize(std::cos(a) * d + std::sin(a) * right);
  return out;
}

// The driver: what a platform's software would do, in one SC_THREAD.
class Driver : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Driver> socket{"socket"};
  sc_core::sc_in<bool> irq{"irq"};

  Driver(sc_core::sc_module_name name, const rtsim::MemoryImage& image,
         std::vector<rtsim::Camera> cameras, int width, int height,
         const rtsim::model::MemoryLayout& layout, int reflection_depth)
      : sc_core::sc_module(name),
        image_(image),
        cameras_(std::move(cameras)),
        width_(width),
        height_(height),
        layout_(layout),
        depth_(reflection_depth) {
    SC_THREAD(run);
  }
  uint64_t wrong() const { return wrong_; }

 private:
  SC_HAS_PROCESS(Driver);

  void run() {
    DeviceDriver bus(socket, kRegisterBase);
    bus.load(image_, layout_.image_base);  // the scene image, over TLM
    const uint64_t fb_base = layout_.fb_base;
    for (size_t k = 0; k < cameras_.size(); ++k) {
      rtsim::model::FrameSetup setup;
      setup.image_base = layout_.image_base;
      setup.fb_base = fb_base;
      setup.camera = cameras_[k];
      setup.width = width_;
      setup.height = height_;
      bus.program(image_, setup);
      // Only hits' records are written: clear the frame buffer the last frame filled (its size
      // is also the register FB_BYTES once the resolution is programmed).
      const std::vector<uint8_t> zeros(layout_.fb_bytes, 0);
      bus.write(fb_base, zeros.data(), layout_.fb_bytes);
      const sc_core::sc_time started = sc_core::sc_time_stamp();
      bus.start();
      sc_core::wait(irq.posedge_event());  // the level may not have fallen yet in this delta
      const uint64_t cycles = bus.finish();
      const uint64_t wrong = check(bus, fb_base, setup.camera);
      wrong_ += wrong;
      nlohmann::json line = {{"frame", k + 1},
                             {"cycles", cycles},
                             {"started_ns", started.to_seconds() * 1e9},
                             {"interrupt_ns", sc_core::sc_time_stamp().to_seconds() * 1e9},
                             {"pixels", width_ * height_},
                             {"hits", hits_},
                             {"wrong_records", wrong}};
      std::printf("%s\n", line.dump().c_str());
    }
  }

  // Reads the primary hit records back over TLM and compares each with the reference tracer's
  // hit: hit or not, triangle, distance (bit for bit) and the hit leaf's LVB word.
  uint64_t check(DeviceDriver& bus, uint64_t fb_base, const rtsim::Camera& camera) {
    const uint32_t stride = bus.read_register(regs::kRecordStride);
    const auto order = bus.read_register(regs::kOrder) == 1 ? rtsim::model::RayOrder::kTiles
                                                            : rtsim::model::RayOrder::kScanline;
    const std::vector<uint32_t> pixel_at =
        rtsim::model::issue_order(width_, height_, order, int(bus.read_register(regs::kTile)));
    const std::vector<uint8_t> records = bus.read(fb_base, uint64_t(pixel_at.size()) * stride);
    rtsim::TracerOptions options;
    options.width = width_;
    options.height = height_;
    options.reflection_depth = depth_;
    options.cull_with_lvb = true;
    const rtsim::TraceResult ref = rtsim::ReferenceTracer(image_).trace_frame(camera, options);
    uint64_t wrong = 0;
    hits_ = 0;
    for (size_t slot = 0; slot < pixel_at.size(); ++slot) {
      const uint8_t* r = &records[slot * stride];
      const rtsim::Hit& want = ref.pixels[pixel_at[slot]].hit;
      const bool hit = (rtsim::image::load_u32(r + 28) & 1u) != 0;
      hits_ += hit;
      if (hit != (want.tri != rtsim::kNoHit))
        ++wrong;
      else if (hit && (rtsim::image::load_u32(r + 48) != want.tri ||
                       rtsim::image::load_u32(r + 52) != bits(want.t) ||
                       rtsim::image::load_u32(r + 24) != ref.pixels[pixel_at[slot]].lvb))
        ++wrong;
    }
    return wrong;
  }
  static uint32_t bits(float f) {
    uint32_t w;
    std::memcpy(&w, &f, 4);
    return w;
  }

  const rtsim::MemoryImage& image_;
  std::vector<rtsim::Camera> cameras_;
  int width_, height_;
  rtsim::model::MemoryLayout layout_;
  int depth_;
  uint64_t wrong_ = 0, hits_ = 0;
};

}  // namespace

int sc_main(int argc, char** argv) {
  if (argc != 2 && argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: %s SCENE.yaml|SCENE.aff|city [WIDTH HEIGHT [HW.yaml]]\n", argv[0]);
    return 2;
  }
  const std::string what = argv[1];
  const int width = argc >= 4 ? std::stoi(argv[2]) : 160,
            height = argc >= 4 ? std::stoi(argv[3]) : 90;
  const std::string configs = RTSIM_CONFIG_DIR;  // the package's configs/
  const std::string hw = argc == 5 ? argv[4] : configs + "/hw/tni-paper.yaml";
  rtsim::SceneSetup setup;
  rtsim::model::AcceleratorConfig config;
  try {
    const bool yaml = what.size() > 5 && what.compare(what.size() - 5, 5, ".yaml") == 0;
    if (what == "city" || yaml)
      setup = rtsim::load_scene_file(what == "city" ? configs + "/scenes/city.yaml" : what);
    else
      rtsim::load_aff(what, 0.0, setup.scene);
    config = rtsim::load_hw_config(hw);  // every error names the file, line and key
    if (config.structure != rtsim::model::Structure::kKdTree)
      throw rtsim::InputError(hw + ": hw.structure: this example builds kd-tree images only");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  const rtsim::Scene& scene = setup.scene;
  // The host's preparation: kd-tree, memory image, light visibility bits.
  const rtsim::KdTree tree = rtsim::build_kdtree(scene.triangles, setup.kdtree);
  rtsim::MemoryImage image(scene, tree);
  rtsim::LvbParams lvb;
  lvb.shadow_offset = rtsim::lvb_shadow_offset(tree);
  lvb.origin_margin = rtsim::lvb_origin_margin(scene, tree);
  const rtsim::LvbResult bits = rtsim::compute_lvb(scene, tree, lvb);
  for (uint32_t i = 0; i < bits.words.size(); ++i) image.set_leaf_lvb(i, bits.words[i]);

  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  rtsim::model::Accelerator accelerator("accelerator", config, {},
                                        rtsim::model::MemoryTarget::kLooselyTimed);
  // The memory the frames need, known before elaboration ends: the image, then the frame buffer.
  const rtsim::model::MemoryLayout layout =
      rtsim::model::memory_layout(config, image.bytes().size(), width, height);
  example::Memory memory("memory", layout.end(), sc_core::sc_time(40, sc_core::SC_NS));
  example::Router router("router", memory.size(), kRegisterBase, regs::kMapBytes);
  Driver driver("driver", image, {scene.camera, turned(scene.camera, 20.f)}, width, height, layout,
                config.reflection_depth);
  sc_core::sc_signal<bool> irq("irq");
  driver.socket.bind(router.target);
  router.memory.bind(memory.socket);
  router.registers.bind(accelerator.register_socket());
  accelerator.memory_socket().bind(memory.socket);
  accelerator.irq.bind(irq);
  driver.irq.bind(irq);
  // What the platform was built from: the hardware file and the memory it sized
  std::printf("%s\n", nlohmann::json{{"hw", hw}, {"memory_bytes", layout.end()}}.dump().c_str());
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    std::fprintf(stderr, "error: %s: %s\n", r.get_msg_type(), r.get_msg());
    return 1;
  }
  return driver.wrong() == 0 ? 0 : 1;
}
