// An AFF keyframe block (`k NAME { transl ... rot ... scale ... visibility ... }`) read and
// evaluated at the load time: Kochanek-Bartels splines (kernels of scene_loader/kb_spline.h),
// BART's T * R * S order.
#pragma once

#include "scene_loader/aff_tokenizer.h"
#include "scene_loader/kb_spline.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

#include <string>

namespace rtsim::aff {

using glm::dmat4;
using glm::dquat;

inline dvec3 transform_point(const dmat4& m, const dvec3& p) {
  return dvec3(m * glm::dvec4(p, 1.0));
}

// M = T * R * S: scale first, then rotate, then translate (BART's order for xs and x).
inline dmat4 trs(const dvec3& t, const dquat& r, const dvec3& s) {
  return glm::translate(dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(dmat4(1.0), s);
}

// A `k NAME` block evaluated at the load time.
struct Animation {
  bool has_translation = false, has_rotation = false;
  dvec3 translation{0.0};
  dquat rotation{1.0, 0.0, 0.0, 0.0};
  dvec3 scale{1.0};
  bool visible = true;

  dmat4 matrix() const { return trs(translation, rotation, scale); }
};

// Reads the block after its `k` keyword: `name` gets its name; the result is its transform and
// visibility at `time`.
Animation parse_keyframes(Tokenizer& tk, double time, KbQuatSpline::Flip rotation_flip,
                          std::string& name);

}  // namespace rtsim::aff
