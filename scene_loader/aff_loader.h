// Loader for BART's AFF scenes (NFF plus includes, transforms, meshes and keyframe animation).
#pragma once

#include "scene/scene.h"
#include "scene_loader/kb_spline.h"

#include <string>

namespace rtsim {

// Loads `path` and the files it includes, with every animated transform (and the camera)
// evaluated at animation time `time`. Appends triangles, materials and lights to `scene` and
// sets its camera, resolution and time. Spheres and cones are tessellated; textures are
// ignored (texture files are never opened). Throws InputError ("FILE:LINE: ...") for
// malformed input, unknown keywords and missing include files.
// `rotation_flip`: which rotation keys are flipped to their neighbour's hemisphere (kBart: as
// BART's own code, so frames match BART's; kAll: every key, each segment the short way).
void load_aff(const std::string& path, double time, Scene& scene,
              KbQuatSpline::Flip rotation_flip = KbQuatSpline::Flip::kBart);

}  // namespace rtsim
