#include "model/memory/dram_policies.h"

namespace rtsim::model {

// What each policy's file registers (no header: nothing else calls them).
void add_fr_fcfs_schedulers(DramSchedulers& r);
void add_open_page(DramRowPolicies& r);
void add_closed_page(DramRowPolicies& r);
void add_no_refresh(DramRefreshPolicies& r);
void add_all_bank_refresh(DramRefreshPolicies& r);

namespace {

template <class R, class... Add>
R registry(const char* kind, Add... add) {
  R r(kind);
  (add(r), ...);
  return r;
}

}  // namespace

// The lists: the order is the one `rtsim params` and the errors show, the default first.
const DramSchedulers& dram_schedulers() {
  static const auto r = registry<DramSchedulers>("DRAM scheduler", add_fr_fcfs_schedulers);
  return r;
}

const DramRowPolicies& dram_row_policies() {
  static const auto r =
      registry<DramRowPolicies>("DRAM row policy", add_open_page, add_closed_page);
  return r;
}

const DramRefreshPolicies& dram_refresh_policies() {
  static const auto r =
      registry<DramRefreshPolicies>("DRAM refresh policy", add_no_refresh, add_all_bank_refresh);
  return r;
}

const std::vector<RegisteredName>& dram_scheduler_names() { return dram_schedulers().names(); }
const std::vector<RegisteredName>& dram_row_policy_names() { return dram_row_policies().names(); }
const std::vector<RegisteredName>& dram_refresh_names() { return dram_refresh_policies().names(); }

}  // namespace rtsim::model
