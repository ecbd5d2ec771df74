#include "model/units/ray_router.h"

namespace rtsim::model {

RayRouter::RayRouter(sc_core::sc_module_name name, const ModelContext& ctx)
    : sc_core::sc_module(name),
      returns("returns"),
      finished("finished"),
      owners("owners"),
      shading("shading"),
      phases("phases"),
      ctx_(ctx) {
  returns.bind(*this);
  finished.bind(*this);
}

void RayRouter::end_of_elaboration() {
  const size_t trv = size_t(owners.size()), units = size_t(shading.size());
  for (size_t i = 0; i < trv; ++i) {
    owners_.push_back(owners[int(i)]);
    shading_of_.push_back(shading[int(i * units / trv)]);
  }
}

void RayRouter::add_producer(Unit* producer) {
  for (int s = 0; s < shading.size(); ++s) shading[s]->add_producer(producer);
}

void RayRouter::retire(uint32_t ray, RayType type, Tick when) {
  release_slot(ray);
  ctx_.pool->release(ray);
  phases->retired(type, when);
}

}  // namespace rtsim::model
