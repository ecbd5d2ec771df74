// Closed page: a request's last burst precharges its bank (auto-precharge) unless another queued
// request hits the same row, which then keeps it open for its own burst(s).
#include "model/memory/dram_policies.h"

namespace rtsim::model {

namespace {

class ClosedPage final : public DramRowPolicy {
 public:
  bool close_after(const DramChannel& ch, size_t done) const override {
    const DramRequest& d = ch.queue[done];
    for (size_t i = 0; i < ch.queue.size(); ++i)
      if (i != done && ch.queue[i].bank == d.bank && ch.queue[i].row == d.row) return false;
    return true;
  }
};

}  // namespace

void add_closed_page(DramRowPolicies& r) {
  r.add(
      "closed", [](const DramConfig&) { return std::make_unique<ClosedPage>(); },
      "a request's last burst precharges its bank unless a queued request hits the row");
}

}  // namespace rtsim::model
