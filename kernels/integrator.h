// How a frame gathers a pixel's light, one setting for the reference tracer and the model alike:
// Whitted's (one primary ray, a shadow ray per light sample, mirror bounces, an ambient term) or a
// path tracer's (`spp` paths a pixel, each a diffuse or mirror bounce at every hit, with
// next-event shadow rays to every light sample there; kernels/path_sampling.h).
#pragma once

#include <fmt/format.h>

#include <string>

namespace rtsim {

enum class Integrator { kWhitted, kPath };

inline const char* to_string(Integrator i) { return i == Integrator::kPath ? "path" : "whitted"; }

struct PathSettings {
  int spp = 1;  // paths per pixel
  // Bounces after the primary hit (every hit, the primary's included, has its shadow rays).
  int max_depth = 3;
  // Russian roulette on the bounces from this one on: a path survives with the probability of its
  // throughput's largest channel, at most 1, and is reweighted.
  int roulette_depth = 2;
  // "" when in range, else what is wrong.
  std::string invalid() const {
    if (spp >= 1 && spp <= 65536 && max_depth >= 0 && max_depth <= 64 && roulette_depth >= 1)
      return "";
    return fmt::format(
        "spp {}, max_depth {}, roulette_depth {}: expected spp in [1, 65536], max_depth in "
        "[0, 64], roulette_depth >= 1",
        spp, max_depth, roulette_depth);
  }
};

}  // namespace rtsim
