// No refresh (GT200's, the default; GPGPU-Sim models none).
#include "model/memory/dram_policies.h"

namespace rtsim::model {

namespace {

class NoRefresh final : public DramRefreshPolicy {
 public:
  DramChoice arbitrate(const DramChannel&, const DramChoice& pick) const override { return pick; }
  DramChoice catch_up(const DramChannel&, uint64_t) const override { return {}; }
  uint64_t first_due() const override { return kDramNever; }
};

}  // namespace

void add_no_refresh(DramRefreshPolicies& r) {
  r.add(
      "none", [](const DramConfig&) { return std::make_unique<NoRefresh>(); }, "no refresh");
}

}  // namespace rtsim::model
