// The functional pass's walks (model/functional/batch_features.h), traced by the reference tracer
// in the order the replay takes its rays: the primary rays in issue order, then the shadow rays in
// the culling unit's scan order (record slot, light, sample; lights whose LVB bit is 0 culled).
// Neither order depends on the replay's clock, so the walks can be traced ahead, on a thread of
// their own, while the replay runs the caches and the clock on another: the same walks in the
// same order either way, from the first walk or from whenever a core comes free. Shared by the
// pass's files and by nothing else.
#pragma once

#include "kernels/camera.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

namespace rtsim::model::functional {

struct TracedRay {
  AccessStream stream;    // the records its walk reads
  Hit hit;                // a primary ray's
  bool occluded = false;  // a shadow ray's
};

// The image's lights, in order.
std::vector<image::LightRecord> image_lights(const MemoryImage& image);
// The shadow rays' origin offset: the reference tracer's (TracerOptions), scaled to the scene.
float shadow_offset(const MemoryImage& image);

// The shadow rays of a primary ray's hit (`pixel`: its pixel), as the culling unit emits them:
// light by light, each light's samples in order (kernels/light_samples.h), `offset` from the
// surface (shadow_offset); a light whose bit in the hit leaf's LVB word is 0 is left out when
// `culling`. Into `out`, cleared first.
void hit_shadow_rays(const MemoryImage& image, const std::vector<image::LightRecord>& lights,
                     const Ray& primary, const Hit& hit, uint32_t pixel, float offset, bool culling,
                     std::vector<Ray>& out);

class Walks {
 public:
  // `order`: the primary rays' pixels in issue order; `shadows`: the shadow rays follow.
  // `stride`: the shadow rays of one batch of record slots in `stride` (FeaturePassOptions).
  // `threaded`: traced ahead from the first walk; else from the first chunk after `ahead_from`
  // (when given) turns true.
  Walks(const MemoryImage& image, const Camera& camera, int width, int height,
        const std::vector<uint32_t>& order, bool culling, bool shadows, uint32_t stride,
        bool threaded, const std::atomic<bool>* ahead_from = nullptr);
  ~Walks();
  Walks(const Walks&) = delete;
  Walks& operator=(const Walks&) = delete;
  // The next walk (the caller may take its stream): valid until the next call.
  TracedRay& next();
  // A stream the caller is done with: its buffer serves a later walk.
  void recycle(AccessStream& s) {
    if (s.reads.capacity() > 0 && returned_.size() < 2 * kChunk)
      returned_.push_back(std::move(s.reads));
  }

 private:
  static constexpr size_t kChunk = 512, kChunksAhead = 8;
  // Traces up to kChunk walks in order into `out`; false when there are none left.
  bool produce(std::vector<TracedRay>& out);
  bool produce_shadow(TracedRay& r);  // the next shadow ray's walk: false at the scan's end
  void run_thread();
  void start_thread();

  const MemoryImage& image_;
  ReferenceTracer tracer_;
  PinholeCamera camera_;
  uint32_t width_;
  const std::vector<uint32_t>& order_;
  bool culling_, shadows_;
  uint32_t stride_;
  float offset_;
  std::vector<image::LightRecord> lights_;
  // The producer's place: primary ray `primary_`, then record slot `slot_`'s shadow ray `ray_`.
  uint64_t primary_ = 0, slot_ = 0;
  std::vector<Hit> hits_;  // the primary rays', by issue index
  std::vector<Ray> rays_;  // the open slot's shadow rays
  size_t ray_ = 0;
  bool slot_open_ = false;
  // The consumer's chunk, and the chunks traced ahead (threaded).
  std::vector<TracedRay> current_;
  size_t at_ = 0;
  // Recycled buffers: the consumer's since its last chunk, the producer's, and (threaded) those
  // on their way from one to the other.
  std::vector<std::vector<Access>> returned_, spare_, handed_;
  bool threaded_;
  const std::atomic<bool>* ahead_from_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<TracedRay>> ready_;
  bool finished_ = false, stop_ = false;
  std::thread thread_;
};

}  // namespace rtsim::model::functional
