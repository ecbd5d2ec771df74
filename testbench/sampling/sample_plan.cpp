#include "testbench/sampling/sample_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>

namespace rtsim {

namespace {

// The windows of detail of the measured units, merged where a window would begin less than a
// batch after the previous one ends.
std::vector<model::DetailWindow> windows_of(const SamplePlan& p, uint64_t warmup) {
  std::vector<model::DetailWindow> out;
  for (const MeasuredUnit& u : p.units) {
    const uint64_t begin = u.index * p.unit, end = std::min(begin + p.unit, p.rays);
    const uint64_t from = begin > warmup ? begin - warmup : 0;
    if (!out.empty() && from < out.back().end + model::kBatchRays)
      out.back().end = end;
    else
      out.push_back({from, end});
  }
  return out;
}

}  // namespace

std::vector<std::pair<uint64_t, uint64_t>> neyman_strata(const std::vector<double>& aux,
                                                         uint64_t first, uint64_t end,
                                                         uint64_t count) {
  std::vector<std::pair<uint64_t, uint64_t>> out;
  if (end <= first || count == 0) return out;
  // Prefix sums of the values and their squares: N_h x S_h of any run of units in O(1).
  std::vector<double> c1(end - first + 1, 0.0), c2(end - first + 1, 0.0);
  for (uint64_t i = first; i < end; ++i) {
    c1[i - first + 1] = c1[i - first] + aux[i];
    c2[i - first + 1] = c2[i - first] + aux[i] * aux[i];
  }
  const auto measure = [&](uint64_t a, uint64_t b) {  // units first + a .. first + b - 1
    const double n = double(b - a), s1 = c1[b] - c1[a];
    return n * std::sqrt(std::max(0.0, (c2[b] - c2[a]) / n - (s1 / n) * (s1 / n)));
  };
  const uint64_t n = end - first;
  const auto cut = [&](double bound) {
    std::vector<std::pair<uint64_t, uint64_t>> strata;
    for (uint64_t a = 0, b = 1; b <= n; ++b)
      if (b == n || measure(a, b + 1) > bound) {
        strata.push_back({first + a, first + b});
        a = b;
      }
    return strata;
  };
  double lo = 0, hi = measure(0, n) + 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (cut(mid).size() > count ? lo : hi) = mid;
  }
  out = cut(hi);
  while (out.size() < count && out.size() < n) {
    const auto widest = std::max_element(out.begin(), out.end(), [](const auto& x, const auto& y) {
      return x.second - x.first < y.second - y.first;
    });
    const uint64_t a = widest->first, b = widest->second, mid = (a + b) / 2;
    *widest = {a, mid};
    out.insert(widest + 1, {mid, b});
  }
  return out;
}

SamplePlan plan_sample(uint64_t rays, const SampleSettings& s,
                       const std::vector<double>& auxiliary) {
  if (!(s.fraction > 0 && s.fraction <= 1) || s.unit == 0 || s.unit % model::kBatchRays ||
      s.warmup % model::kBatchRays)
    throw std::invalid_argument("plan_sample: settings out of range");
  SamplePlan p;
  p.rays = rays;
  p.unit = s.unit;
  p.population = (rays + s.unit - 1) / s.unit;
  const uint64_t k = stratum_units(s.fraction);
  if (k == 1 || p.population <= 2) {
    for (uint64_t u = 0; u < p.population; ++u) p.units.push_back({u, 1, true});
  } else {
    std::mt19937_64 rng(s.seed);
    p.units.push_back({0, 1, true});
    std::vector<std::pair<uint64_t, uint64_t>> strata;
    if (s.strata == SampleStrata::kNeyman) {
      if (auxiliary.size() != p.population)
        throw std::invalid_argument("plan_sample: Neyman strata need an auxiliary per unit");
      strata = neyman_strata(auxiliary, 1, p.population - 1, strata_count(p.population, k));
    } else {
      for (uint64_t first = 1; first + 1 < p.population; first += k)
        strata.push_back({first, std::min(first + k, p.population - 1)});
    }
    for (const auto& [first, end] : strata)
      p.units.push_back({first + rng() % (end - first), end - first, false});
    p.units.push_back({p.population - 1, 1, true});
  }
  p.windows = windows_of(p, s.warmup);
  return p;
}

std::vector<double> unit_cycles(const SamplePlan& plan,
                                const std::vector<model::WindowBatches>& windows) {
  std::map<uint64_t, uint64_t> batch;  // every timed batch's cycles
  for (const model::WindowBatches& w : windows)
    for (size_t b = 0; b < w.cycles.size(); ++b) batch[w.first_batch + b] = w.cycles[b];
  const uint64_t per_unit = plan.unit / model::kBatchRays;
  const uint64_t batches = (plan.rays + model::kBatchRays - 1) / model::kBatchRays;
  std::vector<double> out;
  for (const MeasuredUnit& u : plan.units) {
    double sum = 0;
    for (uint64_t b = u.index * per_unit; b < std::min((u.index + 1) * per_unit, batches); ++b) {
      const auto it = batch.find(b);
      if (it == batch.end()) throw std::logic_error("unit_cycles: a measured batch not timed");
      sum += double(it->second);
    }
    out.push_back(sum);
  }
  return out;
}

SampleEstimate estimate_plan(const SamplePlan& plan, const std::vector<double>& values,
                             std::vector<double>* residuals) {
  if (values.size() != plan.units.size())
    throw std::invalid_argument("estimate_plan: one value per measured unit");
  SampleEstimate e;
  e.population = plan.population;
  e.sampled = values.size();
  std::vector<double> drawn;  // value x weight
  uint64_t drawn_from = 0;    // the units the drawn ones stand for
  for (size_t i = 0; i < values.size(); ++i) {
    const MeasuredUnit& u = plan.units[i];
    e.total += values[i] * double(u.weight);
    if (u.certain) continue;
    drawn.push_back(values[i] * double(u.weight));
    drawn_from += u.weight;
  }
  const uint64_t n = drawn.size();
  if (residuals) {  // each drawn unit's delete-one jackknife deviation (sample_regression.h)
    const double sum = std::accumulate(drawn.begin(), drawn.end(), 0.0), all = double(drawn_from);
    residuals->clear();
    for (size_t i = 0, k = 0; i < values.size(); ++i) {
      if (plan.units[i].certain) continue;
      const double w = double(plan.units[i].weight);
      residuals->push_back(n > 1 ? all / (all - w) * (sum - drawn[k]) - sum : 0.0);
      ++k;
    }
  }
  if (n == 0 || drawn_from == n) return e;  // every unit measured: the total itself
  if (n == 1) {
    e.ci95 = std::numeric_limits<double>::infinity();
    return e;
  }
  double squares = 0;
  for (size_t h = 1; h < n; ++h) squares += (drawn[h] - drawn[h - 1]) * (drawn[h] - drawn[h - 1]);
  const double fpc = 1.0 - double(n) / double(drawn_from);
  e.ci95 = t95(n - 1) * std::sqrt(double(n) * fpc * squares / (2.0 * double(n - 1)));
  return e;
}

}  // namespace rtsim
