// The procedural city as the model tests use it: the scene, its kd-tree and memory image with the
// LVB words in, and the reference tracer's frame to compare a simulated frame with, pixel by pixel.
#pragma once

#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "kernels/lvb.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "model/units/frame_buffer.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>

#include <memory>

namespace rtsim::test {

struct CityFrame {
  CityFrame(int w, int h) : width(w), height(h) {
    const SceneSetup setup = load_scene_file((source_dir() / "configs/scenes/city.yaml").string());
    scene = setup.scene;
    tree = build_kdtree(scene.triangles, setup.kdtree);
    image = std::make_unique<MemoryImage>(scene, tree);
    LvbParams lp;
    lp.shadow_offset = lvb_shadow_offset(tree);
    lp.origin_margin = lvb_origin_margin(scene, tree);
    const LvbResult lvb = compute_lvb(scene, tree, lp);
    for (uint32_t i = 0; i < lvb.words.size(); ++i) image->set_leaf_lvb(i, lvb.words[i]);
    TracerOptions opt;
    opt.width = w;
    opt.height = h;
    opt.cull_with_lvb = true;
    reference = ReferenceTracer(*image).trace_frame(scene.camera, opt);
  }

  // Pixels whose hit (triangle, t, leaf) or shadow result differs from the reference; the first
  // few are reported as test failures.
  int mismatches(const model::FrameBuffer& frame) const {
    int n = 0;
    for (size_t i = 0; i < reference.pixels.size(); ++i) {
      const PixelRecord& a = reference.pixels[i];
      const model::PixelState& b = frame.pixels[i];
      const bool same = a.hit.tri == b.hit.tri &&
                        (a.hit.tri == kNoHit || (a.hit.t == b.hit.t && a.hit.leaf == b.hit.leaf &&
                                                 a.occluded == b.occluded && a.culled == b.culled));
      if (!same && ++n <= 5)
        ADD_FAILURE() << "pixel " << i << ": reference tri " << a.hit.tri << " t " << a.hit.t
                      << " occluded " << a.occluded << " culled " << a.culled << "; model tri "
                      << b.hit.tri << " t " << b.hit.t << " occluded " << b.occluded << " culled "
                      << b.culled;
    }
    return n;
  }

  int width, height;
  Scene scene;
  KdTree tree;
  std::unique_ptr<MemoryImage> image;
  TraceResult reference;
};

// The camera turned `degrees` to its right about its up vector (another frame of the same scene).
inline Camera turned(const Camera& c, float degrees) {
  const Vec3 d = glm::normalize(c.dir), right = glm::normalize(glm::cross(d, c.up));
  const float a = degrees * 3.14159265f / 180.f;
  Camera out = c;
  out.dir = glm::normalize(std::cos(a) * d + std::sin(a) * right);
  return out;
}

}  // namespace rtsim::test
