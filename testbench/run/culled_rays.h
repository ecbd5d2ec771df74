// --culled-rays FILE (rtsim lvb, rtsim run): every culled shadow ray of a frame, so that an
// outside tracer can check each cull. The reference tracer keeps its own (TracerOptions::
// keep_culled); the model's are read off its frame entries' culled bits.
#pragma once

#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "model/units/frame_buffer.h"

#include <string>
#include <vector>

namespace rtsim {

// The shadow rays the model's culling unit culled, as the reference tracer lists them: by pixel,
// path, bounce, light and light sample, each from its hit's surface point towards its light
// sample (the culling unit's own shadow_ray and light_sample_point).
std::vector<CulledRay> culled_rays(const model::FrameBuffer& frame, const MemoryImage& image);

// A record each in a .npy of a structured dtype: pixel, sample (the path), bounce, light,
// light_sample (u4, u4, u2, u2, u4), origin and target (3 x f4 each): the segment an outside
// tracer can test.
void write_culled_rays(const std::string& path, const std::vector<CulledRay>& rays);

}  // namespace rtsim
