#include "testbench/sampling/sample_regression.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rtsim {

namespace {

using Matrix = std::vector<std::vector<double>>;

// The inverse of a small symmetric positive definite matrix (Gauss-Jordan, partial pivoting);
// false when it is singular.
bool invert(Matrix m, Matrix& inv) {
  const size_t n = m.size();
  inv.assign(n, std::vector<double>(n, 0.0));
  for (size_t i = 0; i < n; ++i) inv[i][i] = 1.0;
  for (size_t c = 0; c < n; ++c) {
    size_t p = c;
    for (size_t r = c + 1; r < n; ++r)
      if (std::abs(m[r][c]) > std::abs(m[p][c])) p = r;
    if (std::abs(m[p][c]) < 1e-12) return false;
    std::swap(m[p], m[c]);
    std::swap(inv[p], inv[c]);
    const double d = m[c][c];
    for (size_t k = 0; k < n; ++k) m[c][k] /= d, inv[c][k] /= d;
    for (size_t r = 0; r < n; ++r) {
      if (r == c || m[r][c] == 0.0) continue;
      const double f = m[r][c];
      for (size_t k = 0; k < n; ++k) m[r][k] -= f * m[c][k], inv[r][k] -= f * inv[c][k];
    }
  }
  return true;
}

// Row `u` of the design matrix: 1, then the auxiliaries over their scale (for conditioning).
std::vector<double> design_row(const UnitAuxiliaries& aux, size_t u,
                               const std::vector<double>& scale) {
  std::vector<double> a(aux.features + 1, 1.0);
  for (size_t j = 0; j < aux.features; ++j) a[j + 1] = aux.at(u, j) / scale[j];
  return a;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

UnitAuxiliaries primary_auxiliaries(const SamplePlan& plan,
                                    const std::vector<model::BatchFeatures>& b,
                                    uint32_t in_flight) {
  auto ist = [&](size_t i) { return double(b[i].caches.reads[model::kIstStage]); };
  auto l1 = [&](size_t i) {
    double s = 0;
    for (uint64_t m : b[i].caches.l1_misses) s += double(m);
    return s;
  };
  // The batches in flight ahead of batch i: in_flight .. 2 x in_flight - 1 batches earlier.
  auto ahead = [&](size_t i, auto f) {
    double s = 0;
    for (size_t k = std::max<uint32_t>(1, in_flight); k < 2 * std::max<uint32_t>(1, in_flight); ++k)
      if (i >= k) s += f(i - k);
    return s;
  };
  UnitAuxiliaries aux;
  aux.features = 5;
  const size_t per_unit = plan.unit / model::kBatchRays;
  for (uint64_t u = 0; u < plan.population; ++u) {
    double row[5] = {0, 0, 0, 0, 0};
    for (size_t i = u * per_unit; i < std::min(b.size(), (u + 1) * per_unit); ++i) {
      row[0] += double(b[i].replay_cycles);
      row[1] += ist(i);
      row[2] += ahead(i, ist);
      row[3] += l1(i);
      row[4] += ahead(i, l1);
    }
    aux.x.insert(aux.x.end(), row, row + 5);
  }
  return aux;
}

namespace {

// The weighted least-squares fit of the drawn units' values `y` on their design rows with weights
// `w` (0 leaves a unit out): the coefficients, false when the normal equations are singular.
bool fit(const std::vector<std::vector<double>>& rows, const std::vector<double>& y,
         const std::vector<double>& w, std::vector<double>& beta) {
  const size_t p = rows.empty() ? 0 : rows[0].size();
  Matrix ata(p, std::vector<double>(p, 0.0)), inv;
  std::vector<double> aty(p, 0.0);
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t r = 0; r < p; ++r) {
      aty[r] += w[i] * rows[i][r] * y[i];
      for (size_t c = 0; c < p; ++c) ata[r][c] += w[i] * rows[i][r] * rows[i][c];
    }
  if (!invert(ata, inv)) return false;
  beta.assign(p, 0.0);
  for (size_t r = 0; r < p; ++r) beta[r] = dot(inv[r], aty);
  return true;
}

// The GREG total of the units not measured with certainty for the coefficients `beta`: the fit's
// prediction of them all (`rest`: their design rows summed) plus the drawn units' weighted
// residuals.
double greg_total(const std::vector<double>& rest, const std::vector<std::vector<double>>& rows,
                  const std::vector<double>& y, const std::vector<double>& w,
                  const std::vector<double>& beta) {
  double t = dot(rest, beta);
  for (size_t i = 0; i < rows.size(); ++i) t += w[i] * (y[i] - dot(rows[i], beta));
  return t;
}

}  // namespace

SampleEstimate estimate_greg(const SamplePlan& plan, const std::vector<double>& values,
                             const UnitAuxiliaries& aux, std::vector<double>* residuals_out) {
  if (values.size() != plan.units.size() || aux.units() != plan.population)
    throw std::invalid_argument("estimate_greg: one value per measured unit, auxiliaries for all");
  const size_t p = aux.features + 1;
  size_t n = 0;
  for (const MeasuredUnit& u : plan.units) n += u.certain ? 0 : 1;
  if (n < greg_min_drawn(aux)) return estimate_plan(plan, values, residuals_out);
  std::vector<double> scale(aux.features, 1.0);
  for (size_t j = 0; j < aux.features; ++j) {
    double s = 0;
    for (size_t u = 0; u < aux.units(); ++u) s += std::abs(aux.at(u, j));
    scale[j] = s > 0 ? s / double(aux.units()) : 1.0;
  }
  SampleEstimate e;
  e.population = plan.population;
  e.sampled = values.size();
  std::vector<bool> certain(plan.population, false);
  std::vector<std::vector<double>> rows;  // the drawn units' design rows, values and weights
  std::vector<double> y, w, rest(p, 0.0);
  double drawn_weight = 0;
  for (size_t i = 0; i < plan.units.size(); ++i) {
    const MeasuredUnit& u = plan.units[i];
    if (u.certain) {
      certain[u.index] = true;
      e.total += values[i];
      continue;
    }
    rows.push_back(design_row(aux, u.index, scale));
    y.push_back(values[i]);
    w.push_back(double(u.weight));
    drawn_weight += double(u.weight);
  }
  for (uint64_t u = 0; u < plan.population; ++u)
    if (!certain[u]) {
      const std::vector<double> a = design_row(aux, u, scale);
      for (size_t k = 0; k < p; ++k) rest[k] += a[k];
    }
  std::vector<double> beta;
  if (!fit(rows, y, w, beta)) return estimate_plan(plan, values, residuals_out);
  const double full = greg_total(rest, rows, y, w, beta);
  e.total += full;
  // The delete-one jackknife: each drawn unit left out, the others' weights scaled up to stand for
  // the same units, the fit done again. A unit that steers the fit moves its replicate far.
  std::vector<double> deviations(n);
  for (size_t i = 0; i < n; ++i) {
    std::vector<double> wi(w), bi;
    for (double& x : wi) x *= drawn_weight / (drawn_weight - w[i]);
    wi[i] = 0;
    deviations[i] = (fit(rows, y, wi, bi) ? greg_total(rest, rows, y, wi, bi)
                                          : greg_total(rest, rows, y, wi, beta)) -
                    full;
  }
  e.parameters = p;
  e.ci95 = sum_interval(plan, deviations, n - p);
  if (residuals_out) *residuals_out = std::move(deviations);
  return e;
}

double sum_interval(const SamplePlan& plan, const std::vector<double>& deviations, uint64_t dof) {
  uint64_t drawn_from = 0;
  for (const MeasuredUnit& u : plan.units) drawn_from += u.certain ? 0 : u.weight;
  const size_t n = deviations.size();
  if (n < 2 || dof == 0) return n == drawn_from ? 0.0 : std::numeric_limits<double>::infinity();
  double mean = 0, squares = 0, fourths = 0;
  for (double d : deviations) mean += d / double(n);
  for (double d : deviations) {
    squares += (d - mean) * (d - mean);
    fourths += (d - mean) * (d - mean) * (d - mean) * (d - mean);
  }
  // Satterthwaite's degrees of freedom of a sum of squares whose terms differ: (sum a)^2 / sum
  // a^2 with a = d^2, each a^2 taken as d^4 / 3 (a normal d's fourth moment), so that alike
  // deviations keep `dof` and a few large ones (the units on the geometry) leave fewer.
  if (fourths > 0) dof = std::min<uint64_t>(dof, uint64_t(3.0 * squares * squares / fourths));
  const double fpc = std::max(0.0, 1.0 - double(n) / double(drawn_from));
  return t95(std::max<uint64_t>(dof, 1)) * std::sqrt(fpc * double(n - 1) / double(n) * squares);
}

RatioEstimate paired_ratio(const SamplePlan& plan, double on, double off,
                           const std::vector<double>& on_residuals,
                           const std::vector<double>& off_residuals, uint64_t dof) {
  RatioEstimate r;
  if (off <= 0 || on_residuals.size() != off_residuals.size()) return r;
  r.ratio = on / off;
  std::vector<double> d(on_residuals.size());
  for (size_t i = 0; i < d.size(); ++i) d[i] = on_residuals[i] - r.ratio * off_residuals[i];
  r.ci95 = sum_interval(plan, d, dof) / off;
  return r;
}

UnitAuxiliaries unit_sums(const SamplePlan& plan, const std::vector<model::BatchFeatures>& b,
                          uint64_t (*figure)(const model::BatchFeatures&)) {
  UnitAuxiliaries aux;
  aux.features = 1;
  const size_t per_unit = plan.unit / model::kBatchRays;
  for (uint64_t u = 0; u < plan.population; ++u) {
    double sum = 0;
    for (size_t i = u * per_unit; i < std::min(b.size(), (u + 1) * per_unit); ++i)
      sum += double(figure(b[i]));
    aux.x.push_back(sum);
  }
  return aux;
}

}  // namespace rtsim
