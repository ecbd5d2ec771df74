// Pinhole camera: one ray through each pixel centre, row 0 at the top. Shared by the reference
// tracer and the ray generator model so both issue bit-identical primary rays.
#pragma once

#include "kernels/ray.h"
#include "scene/scene.h"

#include <cmath>

namespace rtsim {

class PinholeCamera {
 public:
  PinholeCamera(const Camera& cam, int width, int height)
      : eye_(cam.eye), width_(width), height_(height) {
    forward_ = glm::normalize(cam.dir);
    right_ = glm::normalize(glm::cross(forward_, cam.up));
    up_ = glm::cross(right_, forward_);
    float tan_half = std::tan(0.5f * cam.vfov_deg * 3.14159265358979f / 180.f);
    scale_y_ = tan_half;
    scale_x_ = tan_half * float(width) / float(height);
  }

  Ray ray(int px, int py) const {
    float sx = (2.f * (float(px) + 0.5f) / float(width_) - 1.f) * scale_x_;
    float sy = (1.f - 2.f * (float(py) + 0.5f) / float(height_)) * scale_y_;
    Ray r;
    r.o = eye_;
    r.d = glm::normalize(forward_ + sx * right_ + sy * up_);
    return r;
  }

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Vec3 eye_, forward_, right_, up_;
  float scale_x_ = 1, scale_y_ = 1;
  int width_, height_;
};

}  // namespace rtsim
