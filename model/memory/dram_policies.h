// The DRAM controller's policies by name: one registry per interface (dram_scheduler.h,
// dram_row_policy.h, dram_refresh.h), each filled from one list in dram_policies.cpp with what the
// policies' own files register (common/registry.h says why the list is explicit). A new policy is
// a class in its own file with an `add_...` function, and one line in that list.
#pragma once

#include "common/registry.h"
#include "model/memory/dram_refresh.h"
#include "model/memory/dram_row_policy.h"
#include "model/memory/dram_scheduler.h"

namespace rtsim::model {

using DramSchedulers = Registry<DramScheduler, const DramConfig&>;
using DramRowPolicies = Registry<DramRowPolicy, const DramConfig&>;
using DramRefreshPolicies = Registry<DramRefreshPolicy, const DramConfig&>;

const DramSchedulers& dram_schedulers();
const DramRowPolicies& dram_row_policies();
const DramRefreshPolicies& dram_refresh_policies();

}  // namespace rtsim::model
