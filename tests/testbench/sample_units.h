// What the sampling estimators' tests share (test_sample_plan, test_sample_regression): the values
// a plan measures of a synthetic frame's units.
#pragma once

#include "testbench/sampling/sample_plan.h"

#include <vector>

namespace rtsim::test {

// `y` (one value per unit of the frame) at the plan's measured units, in its order.
inline std::vector<double> measured(const SamplePlan& plan, const std::vector<double>& y) {
  std::vector<double> v;
  for (const MeasuredUnit& u : plan.units) v.push_back(y[u.index]);
  return v;
}

}  // namespace rtsim::test
