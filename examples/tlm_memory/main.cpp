// Attaching a TLM-2.0 memory of one's own to the accelerator: one sc_main holds several
// accelerators side by side, each wired to a FixedLatencyMemory of a different latency, and one
// with the built-in GDDR3 model for comparison; each renders the same frame, and the program
// prints one JSON line of figures per accelerator.
//
//   tlm_memory_example triangle LATENCY_NS...   one ray at one triangle (no lights)
//   tlm_memory_example city LATENCY_NS...       the procedural city (configs/scenes/city.yaml) at
//                                               160x90
//
// The steps a platform takes are the four marked below (docs/model-design.md, "Embedding the
// model").
#include "examples/tlm_memory/fixed_latency_memory.h"  // installed with the package's headers

#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "model/accelerator.h"
#include "scene_loader/procedural.h"

#include <nlohmann/json.hpp>
#include <systemc>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Job {
  rtsim::Scene scene;
  rtsim::KdTreeParams kdtree;
  int width = 1, height = 1;
};

Job one_triangle() {
  Job j;
  j.scene.name = "triangle";
  j.scene.add_material(rtsim::Material{});
  j.scene.triangles.push_back({rtsim::Vec3(-1.f, -1.f, -5.f), rtsim::Vec3(1.f, -1.f, -5.f),
                               rtsim::Vec3(0.f, 1.f, -5.f), 0});
  return j;  // the default camera looks down -z from the origin: the one pixel's ray hits it
}

Job city() {
  Job j;
  rtsim::make_city(rtsim::CityParams{}, j.scene);  // configs/scenes/city.yaml's parameters
  j.width = 160;
  j.height = 90;
  return j;
}

}  // namespace

int sc_main(int argc, char** argv) {
  if (argc < 3 || (std::string(argv[1]) != "triangle" && std::string(argv[1]) != "city")) {
    std::fprintf(stderr, "usage: %s triangle|city LATENCY_NS...\n", argv[0]);
    return 2;
  }
  const Job job = std::string(argv[1]) == "city" ? city() : one_triangle();
  const rtsim::KdTree tree = rtsim::build_kdtree(job.scene.triangles, job.kdtree);
  const rtsim::MemoryImage image(job.scene, tree);
  // The paper's T&I engine (model/accelerator_config.h)
  const rtsim::model::AcceleratorConfig config;
  const rtsim::model::FrameJob frame{job.scene.camera, job.width, job.height};

  // 1. A time resolution that holds the accelerator clock (1 ns at 1 GHz); the platform sets it.
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  std::vector<std::unique_ptr<rtsim::model::Accelerator>> accelerators;
  std::vector<std::unique_ptr<example::FixedLatencyMemory>> memories;
  std::vector<double> latencies;
  for (int i = 2; i < argc; ++i) {
    latencies.push_back(std::stod(argv[i]));
    const std::string name = "fixed" + std::to_string(i - 2);
    // 2. An accelerator built without its GDDR3 model ...
    accelerators.push_back(std::make_unique<rtsim::model::Accelerator>(
        name.c_str(), config, image, frame, rtsim::model::SimulationHooks{},
        rtsim::model::MemoryTarget::kApproximatelyTimed));
    // 3. ... and a memory holding the image, with room for the frame buffer after it, bound to its
    // socket.
    std::vector<uint8_t> bytes(image.bytes());
    bytes.resize(accelerators.back()->memory_bytes(), 0);
    memories.push_back(std::make_unique<example::FixedLatencyMemory>(
        (name + "_memory").c_str(), std::move(bytes),
        sc_core::sc_time(latencies.back(), sc_core::SC_NS)));
    accelerators.back()->memory_socket().bind(memories.back()->socket);
  }
  accelerators.push_back(
      std::make_unique<rtsim::model::Accelerator>("gddr3", config, image, frame));
  // 4. The platform runs the simulation; the model reports errors as sc_reports of type rtsim/*.
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    std::fprintf(stderr, "error: %s: %s\n", r.get_msg_type(), r.get_msg());
    return 1;
  }
  for (size_t i = 0; i < accelerators.size(); ++i) {
    const rtsim::model::AcceleratorResult r = accelerators[i]->result();
    const nlohmann::json& port = r.stats["memory"]["port"];
    nlohmann::json line = {{"accelerator", accelerators[i]->name()},
                           {"memory", i < memories.size() ? "fixed_latency" : "gddr3"},
                           {"cycles", r.cycles_total},
                           {"memory_reads", port["reads"]},
                           {"memory_writes", port["writes"]},
                           {"primary_hits", r.primary_hits}};
    if (i < memories.size()) line["latency_ns"] = latencies[i];
    std::printf("%s\n", line.dump().c_str());
  }
  return 0;
}
