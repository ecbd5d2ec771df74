#include "testbench/run/simulate.h"

#include "common/error.h"
#include "kernels/light_samples.h"
#include "kernels/path_sampling.h"
#include "model/device/device_driver.h"
#include "model/sim/report.h"

#include <tlm_utils/simple_initiator_socket.h>
#include <systemc>

#include <stdexcept>
#include <string>

namespace rtsim {

namespace {

// The model's report types as this program's errors.
[[noreturn]] void rethrow(const sc_core::sc_report& r) {
  const std::string type = r.get_msg_type(), msg = r.get_msg();
  if (type == model::kReportWatchdog)
    throw std::runtime_error("the accelerator model stopped: " + msg);
  if (type == model::kReportConfig || type == model::kReportDevice) throw InputError(msg);
  if (type == model::kReportTlm) throw std::runtime_error("TLM-2.0 protocol violation: " + msg);
  throw std::runtime_error(type + ": " + msg);
}

// The testbench's platform is a host and the accelerator: the host's thread loads the image into
// the accelerator's memory through its host port, programs one frame through the registers as
// any platform would (model/device/device_driver.h), starts it and waits for the interrupt.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  tlm_utils::simple_initiator_socket<Host> memory{"memory"};
  sc_core::sc_in<bool> irq{"irq"};

  Host(sc_core::sc_module_name name, const MemoryImage& image, const model::FrameSetup& setup)
      : sc_core::sc_module(name), image_(image), setup_(setup) {
    SC_THREAD(run);
  }
  uint64_t cycles() const { return cycles_; }
  uint32_t status_error() const { return status_error_; }

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    model::DeviceDriver host_memory(memory, 0), device(registers, 0);
    host_memory.load(image_, setup_.image_base);
    device.program(image_, setup_);
    device.start();
    sc_core::wait(irq.posedge_event());
    cycles_ = device.finish();
    status_error_ = device.status_error();
  }

  const MemoryImage& image_;
  model::FrameSetup setup_;
  uint64_t cycles_ = 0;
  uint32_t status_error_ = 0;
};

// A frame the device ended with an error: this program built the image, so that is a bug.
void check_status(uint32_t error, const nlohmann::json& stats) {
  if (error == 0) return;
  std::string faults;
  if (stats.contains("faults"))
    for (const auto& [name, count] : stats["faults"].items())
      if (count.get<double>() > 0)
        faults += (faults.empty() ? "; " : ", ") + ("faults." + name) + " " + count.dump();
  throw std::runtime_error("the accelerator ended the frame with STATUS error " +
                           std::to_string(error) + " (" + model::status_error_name(error) + ")" +
                           faults);
}

}  // namespace

void run_simulation() {
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    rethrow(r);
  }
}

SimulatedFrame simulate_frame(const model::AcceleratorConfig& config, const MemoryImage& image,
                              const Camera& camera, int width, int height,
                              const model::SimulationHooks& hooks, double resolution_ps,
                              const std::vector<model::DetailWindow>& windows,
                              const model::WarmSource& warm) {
  // A resolution coarser than 1 ns moves SystemC's default time unit with it: expected here.
  sc_core::sc_report_handler::set_actions(sc_core::SC_ID_DEFAULT_TIME_UNIT_CHANGED_,
                                          sc_core::SC_DO_NOTHING);
  sc_core::sc_set_time_resolution(resolution_ps, sc_core::SC_PS);
  SimulatedFrame out;
  try {
    model::Accelerator accelerator("rtsim", config, hooks);
    if (!windows.empty()) accelerator.sample(windows, warm);
    Host host("host", image,
              model::frame_after_image(image, camera, width, height, config.lvb_culling));
    sc_core::sc_signal<bool> irq("irq");
    host.registers.bind(accelerator.register_socket());
    host.memory.bind(accelerator.memory_host_socket());
    accelerator.irq.bind(irq);
    host.irq.bind(irq);
    run_simulation();
    static_cast<model::AcceleratorResult&>(out) = accelerator.result();
    if (out.cycles_total != host.cycles())
      throw std::runtime_error("the CYCLES register says " + std::to_string(host.cycles()) +
                               " cycles, the frame " + std::to_string(out.cycles_total));
    check_status(host.status_error(), out.stats);
  } catch (const sc_core::sc_report& r) {
    rethrow(r);
  }
  if (config.integrator == Integrator::kPath)
    out.radiance = compose_paths(out.frame, image, config.path);
  out.rgb = out.radiance.empty() ? compose_pixels(out.frame, image) : display_bytes(out.radiance);
  return out;
}

namespace {

// An entry's direct light: each light's term in turn onto `color` (the reference's order), its
// samples blocked as the entry's shadow rays found.
Vec3 direct_light(Vec3 color, const model::FrameBuffer& frame, const MemoryImage& image,
                  uint32_t entry) {
  const model::PixelState& px = frame.pixels[entry];
  for (uint32_t l = 0; l < image.header().light_count; ++l)
    color += light_term(
        px.surface, px.diffuse, image.light(l), frame.pixel_of(entry), frame.key_of(entry), l,
        [&](uint32_t k, const Vec3&) { return frame.sample_occluded(entry, l, k); });
  return color;
}

}  // namespace

std::vector<float> compose_paths(const model::FrameBuffer& frame, const MemoryImage& image,
                                 const PathSettings& settings) {
  std::vector<float> radiance(frame.pixel_count() * 3, 0.f);
  for (uint32_t i = 0; i < frame.pixel_count(); ++i) {
    Vec3 sum(0.f);
    for (int path = 0; path < frame.paths; ++path) {
      // The reference's path (kernels/reference_tracer.cpp) with the frame's entries for its
      // traces: the same decisions, from the same numbers, on the same floats.
      Vec3 light(0.f), throughput(1.f);
      for (uint32_t bounce = 0;; ++bounce) {
        const uint32_t entry = frame.entry(i, int(bounce), path);
        const model::PixelState& px = frame.pixels[entry];
        if (px.hit.tri == kNoHit) {
          light = light + throughput * kBackground;
          break;
        }
        light +=
            throughput * ((1.f - px.reflectance) * direct_light(Vec3(0.f), frame, image, entry));
        if (int(bounce) == settings.max_depth) break;
        if (!path_mirror(i, uint32_t(path), bounce, px.reflectance)) throughput *= px.diffuse;
        if (!path_survives(throughput, i, uint32_t(path), bounce, settings)) break;
      }
      sum += light;
    }
    const Vec3 c = sum / float(frame.paths);
    for (int k = 0; k < 3; ++k) radiance[3 * size_t(i) + k] = c[k];
  }
  return radiance;
}

std::vector<uint8_t> display_bytes(const std::vector<float>& radiance) {
  std::vector<uint8_t> rgb(radiance.size());
  for (size_t k = 0; k < radiance.size(); ++k) rgb[k] = to_display(radiance[k]);
  return rgb;
}

std::vector<uint8_t> compose_pixels(const model::FrameBuffer& frame, const MemoryImage& image) {
  std::vector<uint8_t> rgb(frame.pixel_count() * 3, 0);
  for (uint32_t i = 0; i < frame.pixel_count(); ++i) {
    Vec3 reflected = kBackground;
    for (int level = frame.levels - 1; level >= 0; --level) {
      const model::PixelState& px = frame.at(i, level);
      if (px.hit.tri == kNoHit) {
        reflected = kBackground;
        continue;
      }
      Vec3 c = direct_light(kAmbient * px.diffuse, frame, image, frame.entry(i, level));
      if (px.reflectance > 0.f && level + 1 < frame.levels)
        c = (1.f - px.reflectance) * c + px.reflectance * reflected;
      reflected = c;
    }
    for (int k = 0; k < 3; ++k) rgb[3 * size_t(i) + k] = to_display(reflected[k]);
  }
  return rgb;
}

}  // namespace rtsim
