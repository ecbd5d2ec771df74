#include "testbench/sample_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rtsim {

double t95(uint64_t df) {
  // Student's t, 0.975 quantile, df = 1..30 (any statistics table); beyond, the normal's.
  static constexpr double kT[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                                  2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                                  2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                                  2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (df == 0) throw std::invalid_argument("t95: no degree of freedom");
  return df <= 30 ? kT[df - 1] : 1.96;
}

std::vector<uint64_t> systematic_sample(uint64_t population, double fraction, uint64_t start) {
  if (!(fraction > 0.0 && fraction <= 1.0))
    throw std::invalid_argument("sample fraction " + std::to_string(fraction) + " outside (0, 1]");
  const uint64_t k = std::max<uint64_t>(1, uint64_t(std::llround(1.0 / fraction)));
  std::vector<uint64_t> units;
  for (uint64_t u = start % k; u < population; u += k) units.push_back(u);
  return units;
}

SampleEstimate estimate_total(const std::vector<double>& values, uint64_t population) {
  const uint64_t n = values.size();
  if (n == 0 || n > population)
    throw std::invalid_argument("estimate_total: " + std::to_string(n) + " values of " +
                                std::to_string(population) + " units");
  double sum = 0;
  for (double v : values) sum += v;
  const double mean = sum / double(n);
  SampleEstimate e;
  e.population = population;
  e.sampled = n;
  e.total = mean * double(population);
  if (n == population) return e;  // every unit: the total itself
  if (n == 1) {
    e.ci95 = std::numeric_limits<double>::infinity();
    return e;
  }
  double squares = 0;
  for (double v : values) squares += (v - mean) * (v - mean);
  const double s = std::sqrt(squares / double(n - 1));
  const double fpc = std::sqrt(1.0 - double(n) / double(population));
  e.ci95 = t95(n - 1) * double(population) * s / std::sqrt(double(n)) * fpc;
  return e;
}

}  // namespace rtsim
