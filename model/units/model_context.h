// What every unit of one accelerator instance shares: its calendar, the ray pool, the memory
// image's layout, the clock and the numeric constants of the traversal (the reference tracer's).
#pragma once

#include "kernels/integrator.h"
#include "kernels/memory_image.h"
#include "model/sim/time.h"
#include "model/units/image_faults.h"
#include "model/units/ray_state.h"

namespace rtsim {
class BvhNodeFormat;
}

namespace rtsim::model {

class Calendar;

struct ModelContext {
  Calendar* calendar = nullptr;  // the accelerator's calendar
  RayPool* pool = nullptr;
  ImageFaultStats* faults = nullptr;  // what the units found unreadable (the accelerator's)
  image::Header header;
  bool bvh = false;  // the image holds a BVH (header.accel): the traversal units walk it
  // Its node format, looked up once with the header (the control registers refused an id that
  // names none); null for a kd-tree.
  const BvhNodeFormat* bvh_format = nullptr;
  Clock clock;
  float abs_eps = 0.f;        // the traversal's absolute slack (1e-6 of the scene diagonal)
  float shadow_offset = 0.f;  // shadow-ray origin offset (1e-5 of the scene diagonal)
  // Per light: shadow rays per hit (1 for a point light). The light table's sample counts, read
  // once with the header, as a culling unit would hold them in registers.
  std::vector<uint32_t> light_samples;
  // The frame's integrator (the configuration's): where a path goes on after a hit.
  Integrator integrator = Integrator::kWhitted;
  PathSettings path;
  bool paths() const { return integrator == Integrator::kPath; }
};

}  // namespace rtsim::model
