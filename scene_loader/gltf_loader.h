// glTF 2.0 scenes (.gltf with external or embedded buffers, and .glb) as scene triangles,
// materials, point lights and camera (parsed by tinygltf).
#pragma once

#include "scene/scene.h"

#include <string>

namespace rtsim {

// Appends the glTF scene at `path` to `scene`. ".glb" (any case) is read as binary glTF,
// anything else as JSON glTF.
//
// Traverses the default scene (else scene 0, else every root node) composing each node's
// matrix or translation * rotation * scale with its parents', and appends in world space:
// - the triangles of every mesh primitive of mode TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN,
//   indexed (u8/u16/u32) or not, from its float VEC3 POSITION accessor (byteStride honoured).
//   Point and line primitives, and primitives without POSITION data (no attribute, or an
//   accessor without a bufferView, which would be all zeros) are skipped with a warning.
//   Skins and morph targets are ignored (bind-pose positions).
// - one Material per glTF material used: pbrMetallicRoughness.baseColorFactor rgb -> diffuse;
//   primitives without a material share one white default.
// - KHR_lights_punctual point lights attached to nodes: position = the node's world origin,
//   color = the light's color (intensity is not applied). Spot/directional lights are skipped.
// - the first perspective camera met in traversal sets scene.camera and has_camera:
//   eye = node world origin, dir = node world -Z, up = node world +Y (both normalised),
//   vfov_deg = yfov in degrees. Resolution is left as "not given".
//
// Throws InputError "FILE: ..." with tinygltf's message when parsing fails, and for broken
// references: indices out of range, accessors outside their buffers, node cycles, unsupported
// (sparse, non-float) position data.
void load_gltf(const std::string& path, Scene& scene);

}  // namespace rtsim
