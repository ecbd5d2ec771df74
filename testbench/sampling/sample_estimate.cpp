#include "testbench/sampling/sample_estimate.h"

#include <cmath>
#include <stdexcept>

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

}  // namespace rtsim
