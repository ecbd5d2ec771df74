#include "model/functional/walks.h"

#include "kernels/light_samples.h"
#include "model/units/ray_generator.h"

#include <stdexcept>

namespace rtsim::model::functional {

namespace {
constexpr uint64_t kBatchRays = RayGenerator::kBatchRays;

// Recycled buffers from one hand to the other; `from` is left empty.
void pass_on(std::vector<std::vector<Access>>& from, std::vector<std::vector<Access>>& to) {
  for (std::vector<Access>& b : from) to.push_back(std::move(b));
  from.clear();
}
}  // namespace

Walks::Walks(const MemoryImage& image, const Camera& camera, int width, int height,
             const std::vector<uint32_t>& order, bool culling, bool shadows, uint32_t stride,
             bool threaded, const std::atomic<bool>* ahead_from)
    : image_(image),
      tracer_(image),
      camera_(camera, width, height),
      width_(uint32_t(width)),
      order_(order),
      culling_(culling),
      shadows_(shadows),
      stride_(stride),
      offset_(shadow_offset(image)),
      lights_(image_lights(image)),
      hits_(order.size()),
      threaded_(false),
      ahead_from_(ahead_from) {
  if (threaded) start_thread();
}

// The producer's state is the consumer's until this call, the producer thread's after it.
void Walks::start_thread() {
  threaded_ = true;
  thread_ = std::thread([this] { run_thread(); });
}

Walks::~Walks() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

TracedRay& Walks::next() {
  if (at_ == current_.size()) {
    at_ = 0;
    if (!threaded_ && ahead_from_ && ahead_from_->load(std::memory_order_relaxed)) start_thread();
    if (!threaded_) {
      pass_on(returned_, spare_);
      if (!produce(current_))
        throw std::logic_error("the pass asked for more walks than there are");
    } else {
      std::unique_lock<std::mutex> lock(mutex_);
      if (handed_.size() < 2 * kChunk) pass_on(returned_, handed_);
      returned_.clear();
      changed_.wait(lock, [this] { return !ready_.empty() || finished_; });
      if (ready_.empty()) throw std::logic_error("the pass asked for more walks than there are");
      current_ = std::move(ready_.front());
      ready_.pop_front();
      changed_.notify_all();
    }
  }
  return current_[at_++];
}

void Walks::run_thread() {
  for (;;) {
    std::vector<TracedRay> chunk;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      pass_on(handed_, spare_);
    }
    const bool any = produce(chunk);
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return stop_ || ready_.size() < kChunksAhead; });
    if (stop_) return;
    if (!any) {
      finished_ = true;
      changed_.notify_all();
      return;
    }
    ready_.push_back(std::move(chunk));
    changed_.notify_all();
  }
}

bool Walks::produce(std::vector<TracedRay>& out) {
  out.resize(kChunk);
  size_t n = 0;
  for (; n < kChunk; ++n) {
    TracedRay& r = out[n];
    if (r.stream.reads.capacity() == 0 && !spare_.empty()) {
      r.stream.reads = std::move(spare_.back());
      spare_.pop_back();
    }
    r.stream.clear();
    if (primary_ < order_.size()) {
      const uint32_t pixel = order_[primary_];
      const Ray ray = camera_.ray(int(pixel % width_), int(pixel / width_));
      r.hit = tracer_.closest_hit(ray, r.stream);
      hits_[primary_++] = r.hit;
      continue;
    }
    if (!shadows_ || !produce_shadow(r)) break;
  }
  out.resize(n);
  return n > 0;
}

bool Walks::produce_shadow(TracedRay& r) {
  for (;;) {
    if (!slot_open_) {
      if (slot_ == order_.size()) return false;
      const Hit& hit = hits_[slot_];
      if (hit.tri == kNoHit || lights_.empty() || (slot_ / kBatchRays) % stride_ != 0) {
        ++slot_;
        continue;
      }
      const uint32_t pixel = order_[slot_];
      const Ray primary = camera_.ray(int(pixel % width_), int(pixel / width_));
      hit_shadow_rays(image_, lights_, primary, hit, pixel, offset_, culling_, rays_);
      slot_open_ = true;
      ray_ = 0;
    }
    if (ray_ == rays_.size()) {
      slot_open_ = false;
      ++slot_;
      continue;
    }
    r.occluded = tracer_.occluded(rays_[ray_++], r.stream);
    return true;
  }
}

std::vector<image::LightRecord> image_lights(const MemoryImage& image) {
  std::vector<image::LightRecord> out;
  for (uint32_t i = 0; i < image.header().light_count; ++i) out.push_back(image.light(i));
  return out;
}

float shadow_offset(const MemoryImage& image) {
  return TracerOptions{}.shadow_offset * image.header().bounds.diagonal();
}

void hit_shadow_rays(const MemoryImage& image, const std::vector<image::LightRecord>& lights,
                     const Ray& primary, const Hit& hit, uint32_t pixel, float offset, bool culling,
                     std::vector<Ray>& out) {
  out.clear();
  const image::TriangleRecord tri = image.triangle(hit.tri);
  const SurfacePoint surface = surface_point(primary, hit.t, tri.v0, tri.v1, tri.v2);
  const uint32_t lvb = image.leaf(hit.leaf).lvb;
  for (uint32_t l = 0; l < lights.size(); ++l) {
    if (culling && !((lvb >> l) & 1u)) continue;
    for (uint32_t k = 0; k < lights[l].samples; ++k)
      out.push_back(shadow_ray(surface, light_sample_point(lights[l], pixel, 0, l, k), offset));
  }
}

}  // namespace rtsim::model::functional
