#include "model/memory/dram_row_policy.h"

namespace rtsim::model {

namespace {

class OpenPage final : public DramRowPolicy {
 public:
  bool close_after(const DramChannel&, size_t) const override { return false; }
};

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

std::unique_ptr<DramRowPolicy> make_dram_row_policy(const DramConfig& config) {
  if (config.row_policy == RowPolicy::kClosedPage) return std::make_unique<ClosedPage>();
  return std::make_unique<OpenPage>();
}

}  // namespace rtsim::model
