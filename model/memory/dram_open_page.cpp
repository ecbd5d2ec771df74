// Open page (GT200's, the default): rows stay open; only a conflict's PRE closes them.
#include "model/memory/dram_policies.h"

namespace rtsim::model {

namespace {

class OpenPage final : public DramRowPolicy {
 public:
  bool close_after(const DramChannel&, size_t) const override { return false; }
};

}  // namespace

void add_open_page(DramRowPolicies& r) {
  r.add(
      "open", [](const DramConfig&) { return std::make_unique<OpenPage>(); },
      "rows stay open until a conflict");
}

}  // namespace rtsim::model
