#include "scene_loader/kb_spline.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rtsim {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

namespace kb_detail {

SegmentWeights segment_weights(double t0, double t1, double t2, double t3, const Tcb& c1,
                               const Tcb& c2) {
  // Kochanek-Bartels' spacing adjustment: a tangent built from differences over two
  // intervals is rescaled to the length of the interval it is used on, so unevenly spaced
  // keys keep a continuous speed. Coincident times (0/0) fall back to even spacing.
  auto adjust = [](double num, double den) { return den != 0.0 ? 2.0 * num / den : 1.0; };
  double adj_out = adjust(t2 - t1, t2 - t0);
  double adj_in = adjust(t2 - t1, t3 - t1);

  double out = 0.5 * adj_out * (1.0 - c1.tension);
  double in = 0.5 * adj_in * (1.0 - c2.tension);
  SegmentWeights w;
  w.out_prev = out * (1.0 + c1.continuity) * (1.0 + c1.bias);
  w.out_next = out * (1.0 - c1.continuity) * (1.0 - c1.bias);
  w.in_prev = in * (1.0 - c2.continuity) * (1.0 + c2.bias);
  w.in_next = in * (1.0 + c2.continuity) * (1.0 - c2.bias);
  return w;
}

void locate(const std::vector<double>& starts, const std::vector<double>& ends, double t,
            std::size_t& segment, double& s) {
  // The first segment whose end lies after t, as BART's reference does. A linear scan rather
  // than a binary search because real key lists are not always sorted (robots/Robot1.aff
  // jumps back from 48 to 42); this rule still picks a segment with start <= t < end.
  if (!(t > starts.front())) {
    segment = 0;
    s = 0.0;
    return;
  }
  if (!(t < ends.back())) {
    segment = ends.size() - 1;
    s = 1.0;
    return;
  }
  std::size_t i = 0;
  while (i + 1 < ends.size() && !(t < ends[i])) ++i;
  segment = i;
  double range = ends[i] - starts[i];
  s = range > 0.0 ? std::clamp((t - starts[i]) / range, 0.0, 1.0) : 0.0;
}

}  // namespace kb_detail

template <typename T>
KbSpline<T>::KbSpline(const std::vector<KbKey<T>>& keys) {
  if (keys.size() < 4) throw std::invalid_argument("KbSpline needs at least 4 keys");
  for (std::size_t i = 0; i + 3 < keys.size(); ++i) {
    const KbKey<T>& k0 = keys[i];
    const KbKey<T>& k1 = keys[i + 1];
    const KbKey<T>& k2 = keys[i + 2];
    const KbKey<T>& k3 = keys[i + 3];
    kb_detail::SegmentWeights w =
        kb_detail::segment_weights(k0.time, k1.time, k2.time, k3.time, k1.tcb, k2.tcb);
    T d = k2.value - k1.value;
    T tan_out = w.out_prev * (k1.value - k0.value) + w.out_next * d;
    T tan_in = w.in_prev * d + w.in_next * (k3.value - k2.value);
    // Hermite basis (p1, tan_out, p2, tan_in) rewritten in power form for Horner evaluation.
    segments_.push_back(
        Segment{k1.value, tan_out, 3.0 * d - 2.0 * tan_out - tan_in, -2.0 * d + tan_out + tan_in});
    starts_.push_back(k1.time);
    ends_.push_back(k2.time);
  }
}

template <typename T>
T KbSpline<T>::evaluate(double t) const {
  if (segments_.empty()) return T{};
  std::size_t i;
  double s;
  kb_detail::locate(starts_, ends_, t, i, s);
  const Segment& g = segments_[i];
  return g.c0 + s * (g.c1 + s * (g.c2 + s * g.c3));
}

template class KbSpline<double>;
template class KbSpline<glm::dvec3>;

glm::dquat quat_from_axis_angle(const glm::dvec3& axis, double degrees) {
  double len = glm::length(axis);
  if (!(len > 0.0)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  double half = 0.5 * degrees * (kPi / 180.0);
  glm::dvec3 v = (std::sin(half) / len) * axis;
  return glm::dquat(std::cos(half), v.x, v.y, v.z);
}

glm::dquat quat_log(const glm::dquat& q) {
  glm::dvec3 v(q.x, q.y, q.z);
  double sin_half = glm::length(v);
  // atan2 rather than acos(w): accurate near 0 and valid for w < 0 (half angle > 90 deg).
  double half = std::atan2(sin_half, q.w);
  double k = sin_half > 1e-12 ? half / sin_half : 1.0;
  return glm::dquat(0.0, k * v.x, k * v.y, k * v.z);
}

glm::dquat quat_exp(const glm::dquat& v) {
  glm::dvec3 u(v.x, v.y, v.z);
  double half = glm::length(u);
  double k = half > 1e-12 ? std::sin(half) / half : 1.0;
  return glm::dquat(std::cos(half), k * u.x, k * u.y, k * u.z);
}

glm::dquat quat_slerp(const glm::dquat& p, const glm::dquat& q, double s) {
  double c = std::clamp(glm::dot(p, q), -1.0, 1.0);
  double omega = std::acos(c);
  double sin_omega = std::sin(omega);
  glm::dquat r;
  if (sin_omega < 1e-9) {
    // Nearly equal (or opposite) quaternions: the arc is degenerate, a lerp is exact enough.
    r = (1.0 - s) * p + s * q;
  } else {
    r = (std::sin((1.0 - s) * omega) / sin_omega) * p + (std::sin(s * omega) / sin_omega) * q;
  }
  double len = glm::length(r);
  return len > 0.0 ? r / len : p;
}

KbQuatSpline::KbQuatSpline(const std::vector<KbKey<glm::dquat>>& keys, Flip flip) {
  if (keys.size() < 4) throw std::invalid_argument("KbQuatSpline needs at least 4 keys");
  // q and -q are the same rotation; keeping neighbours within 90 degrees of each other (in
  // quaternion space) makes a segment take the short way round.
  std::vector<glm::dquat> q(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    q[i] = glm::normalize(keys[i].value);
    if (flip == Flip::kAll && i > 0 && glm::dot(q[i - 1], q[i]) < 0.0) q[i] = -q[i];
  }
  for (std::size_t i = 0; i + 3 < keys.size(); ++i) {
    // BART's kbsplrot.c: each segment flips its end key to its start key's side, for good (a
    // later segment sees the flipped key), but takes the key after it as written.
    if (flip == Flip::kBart && glm::dot(q[i + 1], q[i + 2]) < 0.0) q[i + 2] = -q[i + 2];
    const glm::dquat &q0 = q[i], &q1 = q[i + 1], &q2 = q[i + 2], &q3 = q[i + 3];
    kb_detail::SegmentWeights w =
        kb_detail::segment_weights(keys[i].time, keys[i + 1].time, keys[i + 2].time,
                                   keys[i + 3].time, keys[i + 1].tcb, keys[i + 2].tcb);
    // The vector KB tangents, taken in the log space of relative rotations.
    glm::dquat d = quat_log(glm::conjugate(q1) * q2);
    glm::dquat tan_out = w.out_prev * quat_log(glm::conjugate(q0) * q1) + w.out_next * d;
    glm::dquat tan_in = w.in_prev * d + w.in_next * quat_log(glm::conjugate(q2) * q3);
    // Squad inner control points that make the curve leave q1 along tan_out and reach q2
    // along tan_in.
    glm::dquat a = q1 * quat_exp(0.5 * (tan_out - d));
    glm::dquat b = q2 * quat_exp(0.5 * (d - tan_in));
    segments_.push_back(Segment{q1, a, b, q2});
    starts_.push_back(keys[i + 1].time);
    ends_.push_back(keys[i + 2].time);
  }
}

glm::dquat KbQuatSpline::evaluate(double t) const {
  if (segments_.empty()) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  std::size_t i;
  double s;
  kb_detail::locate(starts_, ends_, t, i, s);
  const Segment& g = segments_[i];
  return quat_slerp(quat_slerp(g.p, g.q, s), quat_slerp(g.a, g.b, s), 2.0 * s * (1.0 - s));
}

}  // namespace rtsim
