// The TRV units own their rays' slots (the T&I engine's scheme: a ray keeps its slot while it
// visits LIST and IST). IST and shading hand a ray back to its TRV unit, send it to the shading
// unit that serves its TRV unit, or free its slot through this interface; the accelerator
// implements it over its TRV units.
#pragma once

#include "model/memory/line_source.h"

#include <cstdint>

namespace rtsim::model {

class RayFifo;

class RayOwners {
 public:
  virtual ~RayOwners() = default;
  // The ray goes back to its TRV unit and continues there at `when`.
  virtual void return_ray(uint32_t ray, Tick when) = 0;
  // The ray retired: its slot in its TRV unit frees.
  virtual void retire(uint32_t ray) = 0;
  // Where the ray goes when its traversal is over: the input of its TRV unit's shading unit.
  virtual RayFifo* shading_input(uint32_t ray) = 0;
};

}  // namespace rtsim::model
