// The names the host algorithms go by in the files others write (run reports, hardware files,
// studies), spelled once. Header only: reports/ reads a report's sections by them without linking
// the kernels.
#pragma once

namespace rtsim {

// The acceleration structures' families: the kd-tree and every BVH format (kernels/bvh_image.h's
// Accel). A run report's section of the structure's figures, the hardware file's `structure:`
// and the BVH study (`rtsim reproduce --bvh`, its directory, a study's run of it) go by them.
inline constexpr const char* kKdTreeFamily = "kdtree";
inline constexpr const char* kBvhFamily = "bvh";
inline const char* structure_family(bool bvh) { return bvh ? kBvhFamily : kKdTreeFamily; }

// The LVB's culling of shadow rays (kernels/lvb.h): a study run's field of its culling (off, the
// paper's method or the exact mode).
inline constexpr const char* kCulling = "culling";

}  // namespace rtsim
