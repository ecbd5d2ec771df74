#include "testbench/sampling_walks.h"

#include "kernels/light_samples.h"
#include "model/units/ray_generator.h"

#include <stdexcept>

namespace rtsim::sampling_detail {

namespace {
constexpr uint64_t kBatchRays = model::RayGenerator::kBatchRays;
}  // namespace

Walks::Walks(const MemoryImage& image, const Camera& camera, int width, int height,
             const std::vector<uint32_t>& order, bool culling, bool shadows, uint32_t stride,
             bool threaded)
    : image_(image),
      tracer_(image),
      camera_(camera, width, height),
      width_(uint32_t(width)),
      order_(order),
      culling_(culling),
      shadows_(shadows),
      stride_(stride),
      offset_(1e-5f * image.header().bounds.diagonal()),
      hits_(order.size()),
      threaded_(threaded) {
  for (uint32_t i = 0; i < image.header().light_count; ++i) lights_.push_back(image.light(i));
  if (threaded_) thread_ = std::thread([this] { run_thread(); });
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
    if (!threaded_) {
      if (!produce(current_))
        throw std::logic_error("the pass asked for more walks than there are");
    } else {
      std::unique_lock<std::mutex> lock(mutex_);
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
      pixel_ = order_[slot_];
      const Ray primary = camera_.ray(int(pixel_ % width_), int(pixel_ / width_));
      const image::TriangleRecord tri = image_.triangle(hit.tri);
      surface_ = surface_point(primary, hit.t, tri.v0, tri.v1, tri.v2);
      lvb_ = image_.leaf(hit.leaf).lvb;
      slot_open_ = true;
      light_ = sample_ = 0;
    }
    if (light_ == lights_.size()) {
      slot_open_ = false;
      ++slot_;
      continue;
    }
    if (culling_ && !((lvb_ >> light_) & 1u)) {
      ++light_;
      continue;
    }
    const image::LightRecord& light = lights_[light_];
    const Ray ray =
        shadow_ray(surface_, light_sample_point(light, pixel_, 0, light_, sample_), offset_);
    r.occluded = tracer_.occluded(ray, r.stream);
    if (++sample_ == light.samples) {
      sample_ = 0;
      ++light_;
    }
    return true;
  }
}

}  // namespace rtsim::sampling_detail
