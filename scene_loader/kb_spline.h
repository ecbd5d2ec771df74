// Kochanek-Bartels (TCB) splines for keyframed animation: scalars, vectors and rotations.
//
// A key list k[0..n-1] (n >= 4) is interpolated through k[1]..k[n-2]; k[0] and k[n-1] only
// shape the end tangents, as in BART. Times at or before k[1].time give k[1], times at or
// after k[n-2].time give k[n-2]. With tension = continuity = bias = 0 and evenly spaced keys
// the spline is Catmull-Rom.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace rtsim {

// Per-key shape parameters, each usually in [-1, 1].
struct Tcb {
  double tension = 0.0;     // +1 shortens the tangents (tighter curve), -1 lengthens them
  double continuity = 0.0;  // != 0 lets incoming and outgoing tangents differ (corners)
  double bias = 0.0;        // +1 leans the tangent towards the previous key, -1 the next
};

template <typename T>
struct KbKey {
  double time = 0.0;
  T value{};
  Tcb tcb;
};

namespace kb_detail {

// Tangent weights of one segment k[i1] -> k[i2], with neighbours k[i0] and k[i3].
// out_* build the outgoing tangent at k[i1] from (k1 - k0) and (k2 - k1); in_* build the
// incoming tangent at k[i2] from (k2 - k1) and (k3 - k2).
struct SegmentWeights {
  double out_prev, out_next, in_prev, in_next;
};
SegmentWeights segment_weights(double t0, double t1, double t2, double t3, const Tcb& c1,
                               const Tcb& c2);

// Finds the segment holding `t` and the local parameter s in [0, 1]; segment i runs from
// starts[i] to ends[i]. Clamps before the first and after the last segment.
void locate(const std::vector<double>& starts, const std::vector<double>& ends, double t,
            std::size_t& segment, double& s);

}  // namespace kb_detail

// Position-like values: T = double or glm::dvec3 (anything with +, -, and scalar *).
template <typename T>
class KbSpline {
 public:
  KbSpline() = default;
  // Throws std::invalid_argument for fewer than 4 keys.
  explicit KbSpline(const std::vector<KbKey<T>>& keys);

  bool empty() const { return segments_.empty(); }
  T evaluate(double t) const;

 private:
  // Cubic Hermite segment in power form: p(s) = c0 + s (c1 + s (c2 + s c3)).
  struct Segment {
    T c0, c1, c2, c3;
  };
  std::vector<Segment> segments_;
  std::vector<double> starts_, ends_;
};

extern template class KbSpline<double>;
extern template class KbSpline<glm::dvec3>;

// Unit quaternion (rotation) keys, interpolated with squad in the KB form: the squad control
// quaternions come from TCB tangents taken in the log (tangent) space between keys.
class KbQuatSpline {
 public:
  KbQuatSpline() = default;
  // Which keys are flipped to the hemisphere of their predecessor (q and -q are one rotation):
  // kBart as BART's kbsplrot.c does, segment by segment (keys 2 .. n-2, each when it ends a
  // segment; a segment's tangent takes the key after it unflipped), so frames match BART's; kAll
  // flips every key first, so that every segment and tangent takes the short way round.
  enum class Flip { kBart, kAll };
  // Throws for fewer than 4 keys.
  explicit KbQuatSpline(const std::vector<KbKey<glm::dquat>>& keys, Flip flip = Flip::kBart);

  bool empty() const { return segments_.empty(); }
  glm::dquat evaluate(double t) const;  // always unit length

 private:
  // squad(s) = slerp(slerp(p, q, s), slerp(a, b, s), 2 s (1 - s)).
  struct Segment {
    glm::dquat p, a, b, q;
  };
  std::vector<Segment> segments_;
  std::vector<double> starts_, ends_;
};

// Rotation of `degrees` about `axis` (normalised here; a zero axis gives the identity).
glm::dquat quat_from_axis_angle(const glm::dvec3& axis, double degrees);

// Quaternion helpers, exposed for tests and reuse. log/exp map between unit quaternions and
// pure quaternions (w = 0) holding half the rotation angle times the axis.
glm::dquat quat_log(const glm::dquat& q);
glm::dquat quat_exp(const glm::dquat& v);
// Great-arc interpolation without hemisphere correction (callers choose the side).
glm::dquat quat_slerp(const glm::dquat& p, const glm::dquat& q, double s);

}  // namespace rtsim
