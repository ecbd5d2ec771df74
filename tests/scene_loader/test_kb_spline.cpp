// Kochanek-Bartels splines of scalars, vectors and rotations (BART's keyframes): keys hit,
// Catmull-Rom at zero TCB, clamping, tension, uneven spacing, unit quaternions.
#include "common/error.h"
#include "scene_loader/aff_loader.h"
#include "scene_loader/kb_spline.h"
#include "tests/scene_loader/aff_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim {
namespace {

using namespace aff_test;

// Catmull-Rom through p1..p2 with neighbours p0, p3, evenly spaced (written out independently
// of the KB code: the textbook matrix form).
double catmull_rom(double p0, double p1, double p2, double p3, double s) {
  return 0.5 * (2 * p1 + (-p0 + p2) * s + (2 * p0 - 5 * p1 + 4 * p2 - p3) * s * s +
                (-p0 + 3 * p1 - 3 * p2 + p3) * s * s * s);
}

std::vector<KbKey<double>> scalar_keys(const std::vector<double>& times,
                                       const std::vector<double>& values, Tcb tcb = {}) {
  std::vector<KbKey<double>> keys;
  for (std::size_t i = 0; i < times.size(); ++i) keys.push_back({times[i], values[i], tcb});
  return keys;
}

// Rotation angle in degrees between two unit quaternions (sign-independent).
double angle_between_deg(const glm::dquat& a, const glm::dquat& b) {
  double d = std::min(1.0, std::abs(glm::dot(a, b)));
  return 2.0 * std::acos(d) * 180.0 / kPi;
}

// ---- KB splines ------------------------------------------------------------------------------

TEST(KbSpline, HitsInnerKeysAndIsCatmullRomWithZeroTcb) {
  std::vector<double> p = {0.0, 1.0, 4.0, 2.0, 5.0, -1.0};
  KbSpline<double> s(scalar_keys({0, 1, 2, 3, 4, 5}, p));
  for (int k = 1; k <= 4; ++k) EXPECT_NEAR(s.evaluate(k), p[k], 1e-12) << "key " << k;
  EXPECT_NEAR(s.evaluate(1.5), catmull_rom(p[0], p[1], p[2], p[3], 0.5), 1e-12);
  EXPECT_NEAR(s.evaluate(2.25), catmull_rom(p[1], p[2], p[3], p[4], 0.25), 1e-12);
  EXPECT_NEAR(s.evaluate(3.8), catmull_rom(p[2], p[3], p[4], p[5], 0.8), 1e-12);
  // The midpoint of the first segment is not the chord midpoint: the curve really bends.
  EXPECT_GT(std::abs(s.evaluate(1.5) - 2.5), 0.1);
}

TEST(KbSpline, ClampsOutsideSecondAndNextToLastKeys) {
  std::vector<double> p = {10.0, 1.0, 4.0, 2.0, -7.0};
  KbSpline<double> s(scalar_keys({-1, 0, 1, 2, 3}, p));
  EXPECT_DOUBLE_EQ(s.evaluate(-0.5), 1.0);  // between first and second key: second key
  EXPECT_DOUBLE_EQ(s.evaluate(-100.0), 1.0);
  EXPECT_DOUBLE_EQ(s.evaluate(0.0), 1.0);
  EXPECT_DOUBLE_EQ(s.evaluate(2.0), 2.0);
  EXPECT_DOUBLE_EQ(s.evaluate(2.5), 2.0);  // between next-to-last and last: next-to-last
  EXPECT_DOUBLE_EQ(s.evaluate(100.0), 2.0);
}

TEST(KbSpline, FullTensionGivesZeroTangents) {
  // Zero tangents leave the Hermite blend p1 + (3s^2 - 2s^3)(p2 - p1).
  Tcb tight{1.0, 0.0, 0.0};
  KbSpline<double> s(scalar_keys({0, 1, 2, 3}, {5.0, 1.0, 3.0, -4.0}, tight));
  EXPECT_NEAR(s.evaluate(1.5), 2.0, 1e-12);
  double u = 0.3, h = 3 * u * u - 2 * u * u * u;
  EXPECT_NEAR(s.evaluate(1.0 + u), 1.0 + h * 2.0, 1e-12);
}

TEST(KbSpline, UnevenKeySpacingScalesTangents) {
  // Times 0, 1, 3, 4: the segment 1 -> 3 is twice as long as its neighbours. KB's adjustment
  // scales the Catmull-Rom tangent at key 1 by 2*(t2-t1)/(t2-t0) and at key 2 by
  // 2*(t2-t1)/(t3-t1), both measured in the segment's own parameter s in [0, 1].
  double p0 = 0, p1 = 1, p2 = 5, p3 = 4;
  KbSpline<double> s(scalar_keys({0, 1, 3, 4}, {p0, p1, p2, p3}));
  double m1 = (2.0 * 2.0 / 3.0) * 0.5 * (p2 - p0);
  double m2 = (2.0 * 2.0 / 3.0) * 0.5 * (p3 - p1);
  double u = 0.25;
  double h00 = 2 * u * u * u - 3 * u * u + 1, h10 = u * u * u - 2 * u * u + u;
  double h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  EXPECT_NEAR(s.evaluate(1.5), h00 * p1 + h10 * m1 + h01 * p2 + h11 * m2, 1e-12);
}

TEST(KbSpline, VectorKeysInterpolatePerComponent) {
  std::vector<KbKey<glm::dvec3>> keys;
  std::vector<glm::dvec3> p = {{0, 0, 0}, {1, 2, 3}, {4, -2, 0}, {2, 2, 2}, {5, 0, 1}};
  for (int i = 0; i < 5; ++i) keys.push_back({double(i), p[i], {}});
  KbSpline<glm::dvec3> s(keys);
  glm::dvec3 v = s.evaluate(2.4);
  EXPECT_NEAR(v.x, catmull_rom(p[1].x, p[2].x, p[3].x, p[4].x, 0.4), 1e-12);
  EXPECT_NEAR(v.y, catmull_rom(p[1].y, p[2].y, p[3].y, p[4].y, 0.4), 1e-12);
  EXPECT_NEAR(v.z, catmull_rom(p[1].z, p[2].z, p[3].z, p[4].z, 0.4), 1e-12);
}

TEST(KbSpline, RejectsFewerThanFourKeys) {
  EXPECT_THROW(KbSpline<double>(scalar_keys({0, 1, 2}, {0, 1, 2})), std::invalid_argument);
  EXPECT_THROW(KbQuatSpline(std::vector<KbKey<glm::dquat>>(3)), std::invalid_argument);
}

std::vector<KbKey<glm::dquat>> rotation_keys(const std::vector<glm::dvec3>& axes,
                                             const std::vector<double>& degrees) {
  std::vector<KbKey<glm::dquat>> keys;
  for (std::size_t i = 0; i < axes.size(); ++i)
    keys.push_back({double(i), quat_from_axis_angle(axes[i], degrees[i]), {}});
  return keys;
}

TEST(KbQuatSpline, HitsKeysAndStaysUnit) {
  std::vector<glm::dvec3> axes = {{1, 0, 0}, {0, 1, 0},  {1, 1, 0},
                                  {0, 0, 1}, {1, -2, 3}, {0, 1, 1}};
  std::vector<double> deg = {10, 40, -70, 120, 200, 5};
  auto keys = rotation_keys(axes, deg);
  KbQuatSpline s(keys);
  for (int k = 1; k <= 4; ++k)
    EXPECT_LT(angle_between_deg(s.evaluate(k), keys[k].value), 1e-6) << "key " << k;
  for (double t = -1.0; t <= 6.0; t += 0.05) EXPECT_NEAR(glm::length(s.evaluate(t)), 1.0, 1e-12);
  // Clamping like the vector spline.
  EXPECT_LT(angle_between_deg(s.evaluate(0.3), keys[1].value), 1e-9);
  EXPECT_LT(angle_between_deg(s.evaluate(4.7), keys[4].value), 1e-9);
}

TEST(KbQuatSpline, EvenStepsAboutOneAxisInterpolateLinearly) {
  // Equal steps about one axis make every tangent equal to the step, so squad reduces to
  // slerp: 15 degrees halfway between the 10 and 20 degree keys. Key 2 is given as -q (the
  // same rotation) to check that the spline still takes the short way round.
  auto keys =
      rotation_keys({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}}, {0, 10, 20, 30, 40});
  keys[2].value = -keys[2].value;
  KbQuatSpline s(keys);
  glm::dquat q = s.evaluate(1.5);
  EXPECT_LT(angle_between_deg(q, quat_from_axis_angle({0, 0, 1}, 15)), 1e-9);
  EXPECT_LT(angle_between_deg(s.evaluate(2.75), quat_from_axis_angle({0, 0, 1}, 27.5)), 1e-9);
}

TEST(KbQuatSpline, AxisAngleNormalisesAxis) {
  glm::dquat a = quat_from_axis_angle({0, 0, 2}, 90);
  glm::dvec3 x = a * glm::dvec3(1, 0, 0);
  EXPECT_NEAR(x.x, 0.0, 1e-12);
  EXPECT_NEAR(x.y, 1.0, 1e-12);
  EXPECT_NEAR(glm::length(a), 1.0, 1e-12);
}

// ---- the shared BART scenes ------------------------------------------------------------------

}  // namespace
}  // namespace rtsim
