#include "model/memory/dram_controller.h"

#include "model/memory/dram_policies.h"

#include <algorithm>
#include <stdexcept>

namespace rtsim::model {

namespace {

const DramConfig& validated(const DramConfig& c) {
  c.validate();
  return c;
}

}  // namespace

double DramStats::row_hit_rate() const {
  const uint64_t n = row_hits + row_misses + row_conflicts;
  return n ? double(row_hits) / double(n) : 0.0;
}

double DramStats::bandwidth_gbps() const {
  if (last_completion_ps <= first_arrival_ps) return 0.0;
  // bytes/ps -> GB/s
  return double(bytes) * 1000.0 / double(last_completion_ps - first_arrival_ps);
}

double DramStats::avg_latency_ns() const {
  return reads ? double(latency_sum_ps) / double(reads) / 1000.0 : 0.0;
}

DramController::DramController(const DramConfig& config)
    : config_(validated(config)),
      mapping_(config_.address_mapping, config_.channels),
      scheduler_(dram_schedulers().make(config_.scheduler, config_)),
      row_policy_(dram_row_policies().make(config_.row_policy, config_)),
      refresh_(dram_refresh_policies().make(config_.refresh, config_)),
      refreshing_(refresh_->first_due() != kDramNever) {
  add_rules();
  channels_.resize(config_.channels);
  picks_.resize(config_.channels);
  open_banks_.assign(config_.channels, 0);
  open_since_.assign(config_.channels, 0);
  stretch_end_.assign(config_.channels, 0);
  counted_until_.assign(config_.channels, 0);
  next_.resize(config_.channels);
  for (Channel& ch : channels_) {
    ch.banks.resize(config_.banks);
    ch.queue.reserve(config_.queue_size);
    ch.refresh_due = refresh_->first_due();
  }
  stats_.channel_reads.assign(config_.channels, 0);
}

void DramController::add_rules() {
  using C = Command;
  const uint32_t burst = config_.burst_cycles();
  std::vector<TimingRule> rules = {
      {C::kActivate, C::kRead, Scope::kBank, config_.tRCD},
      {C::kActivate, C::kWrite, Scope::kBank, config_.activate_to_write()},
      {C::kActivate, C::kPrecharge, Scope::kBank, config_.tRAS},
      {C::kActivate, C::kActivate, Scope::kBank, config_.tRC},
      {C::kActivate, C::kActivate, Scope::kChannel, config_.tRRD},
      {C::kPrecharge, C::kActivate, Scope::kBank, config_.tRP},
      {C::kRead, C::kRead, Scope::kChannel, config_.tCCD},
      {C::kRead, C::kRead, Scope::kChannel, burst},  // the data bus holds one burst at a time
      {C::kRead, C::kPrecharge, Scope::kBank, config_.read_to_precharge()},  // READ to PRECHARGE
      {C::kRead, C::kWrite, Scope::kChannel, config_.tCCD},
      {C::kRead, C::kWrite, Scope::kChannel, config_.read_to_write()},
      {C::kWrite, C::kWrite, Scope::kChannel, config_.tCCD},
      {C::kWrite, C::kWrite, Scope::kChannel, burst},  // the data bus, as for reads
      {C::kWrite, C::kRead, Scope::kChannel, config_.tCCD},
      {C::kWrite, C::kRead, Scope::kChannel, config_.write_to_read()},
      {C::kWrite, C::kPrecharge, Scope::kBank, config_.write_to_precharge()},
  };
  if (config_.bank_groups > 1) {
    rules.push_back({C::kActivate, C::kActivate, Scope::kBankGroup, config_.rrd_same_group()});
    for (C prev : {C::kRead, C::kWrite})
      for (C next : {C::kRead, C::kWrite})
        rules.push_back({prev, next, Scope::kBankGroup, config_.ccd_same_group()});
  }
  // REF is all-bank: its constraints are the channel's. Without refresh no REF issues, and these
  // rules would only cost host time.
  if (refreshing_) {
    rules.push_back({C::kActivate, C::kRefresh, Scope::kChannel, config_.tRC});
    rules.push_back({C::kPrecharge, C::kRefresh, Scope::kChannel, config_.tRP});
    rules.push_back({C::kRefresh, C::kActivate, Scope::kChannel, config_.tRFC});
  }
  // Rules with the same (prev, next, scope) fold into one with the largest delay: stamp() then
  // stamps each target once (the stamps are maxima, so this changes no timing).
  for (const TimingRule& r : rules) {
    auto& by_prev = r.scope == Scope::kBankGroup ? group_rules_by_prev_ : rules_by_prev_;
    std::vector<TimingRule>& after = by_prev[size_t(r.prev)];
    const auto same = std::find_if(after.begin(), after.end(), [&r](const TimingRule& o) {
      return o.next == r.next && o.scope == r.scope;
    });
    if (same == after.end())
      after.push_back(r);
    else
      same->cycles = std::max(same->cycles, r.cycles);
  }
}

void DramController::enqueue(uint64_t addr, Tick now, uint64_t id, bool write) {
  const Tick arrival = std::max(now, now_);
  const DramAddress a = mapping_.decode(addr & ~uint64_t(config_.request_bytes - 1));
  const DramRequest r{arrival,     (arrival + config_.tCK_ps - 1) / config_.tCK_ps,
                      a.row,       a.bank,
                      0,           write,
                      false,       id,
                      next_seq_++, a.column};
  const bool first = stats_.requests + stats_.write_requests == 0;
  stats_.first_arrival_ps = first ? arrival : std::min(stats_.first_arrival_ps, arrival);
  ++(write ? stats_.write_requests : stats_.requests);
  Channel& ch = channels_[a.channel];
  if (!has_room(ch)) throw std::logic_error("DramController: a request to a full channel");
  if (refreshing_ && ch.queue.empty()) catch_up_refresh(a.channel, r.arrival_cycle);
  if (ch.queue.size() < config_.queue_size) {
    ch.queue.push_back(r);
    // A refresh caught up above leaves an empty queue's pick (none) as it was.
    rechoose_added(a.channel, ch.queue.size() - 1);
  } else {
    ch.overflow.push_back(r);  // invisible to the scheduler until it enters the queue
    ++stats_.queue_full_events;
  }
}

void DramController::catch_up_refresh(uint32_t channel_index, uint64_t until) {
  Channel& ch = channels_[channel_index];
  for (Choice c = refresh_->catch_up(ch, until); c.cycle != kDramNever;
       c = refresh_->catch_up(ch, until))
    issue_refresh(channel_index, c);
}

void DramController::stamp(Channel& ch, uint32_t bank, Command cmd, uint64_t cycle) {
  DramBank& b = ch.banks[bank];
  for (const TimingRule& rule : rules_by_prev_[size_t(cmd)]) {
    DramStamps& s = rule.scope == Scope::kBank ? b.earliest : ch.earliest;
    uint64_t& e = s[size_t(rule.next)];
    e = std::max(e, cycle + rule.cycles);
  }
  for (const TimingRule& rule : group_rules_by_prev_[size_t(cmd)])
    for (uint32_t k = config_.bank_group(bank); k < ch.banks.size(); k += config_.bank_groups) {
      uint64_t& e = ch.banks[k].earliest[size_t(rule.next)];
      e = std::max(e, cycle + rule.cycles);
    }
}

void DramController::issue_refresh(uint32_t channel_index, const Choice& c) {
  Channel& ch = channels_[channel_index];
  stamp(ch, c.bank, c.command, c.cycle);
  ch.free_from = c.cycle + 1;
  DramBank& b = ch.banks[c.bank];
  record(c.cycle, channel_index, c.bank, c.command, c.command == Command::kPrecharge ? b.row : 0, 0,
         kNoRequest);
  if (c.command == Command::kPrecharge) {
    b.open = false;
    bank_closed(channel_index, c.cycle);
    ++stats_.precharges;
  } else {
    ++stats_.refreshes;
    ch.refresh_due += config_.tREFI;
  }
}

void DramController::issue(uint32_t channel_index, const Choice& c) {
  if (c.index == kDramNoRequest) return issue_refresh(channel_index, c);
  Channel& ch = channels_[channel_index];
  DramRequest& r = ch.queue[c.index];
  DramBank& b = ch.banks[r.bank];

  if (!r.classified) {
    r.classified = true;
    if (is_column(c.command))
      ++stats_.row_hits;
    else if (c.command == Command::kActivate)
      ++stats_.row_misses;
    else
      ++stats_.row_conflicts;
  }
  stamp(ch, r.bank, c.command, c.cycle);
  ch.free_from = c.cycle + 1;
  record(c.cycle, channel_index, r.bank, c.command, r.row,
         is_column(c.command) ? r.column + r.bursts_issued : 0, r.id);

  switch (c.command) {
    case Command::kActivate:
      b.open = true;
      b.row = r.row;
      bank_opened(channel_index, c.cycle);
      ++stats_.activates;
      break;
    case Command::kPrecharge:
      b.open = false;
      bank_closed(channel_index, c.cycle);
      ++stats_.precharges;
      break;
    case Command::kRefresh: break;  // only issue_refresh issues REF
    case Command::kRead:
    case Command::kWrite:
      ++r.bursts_issued;
      ++(r.write ? stats_.write_bursts : stats_.bursts);
      stats_.data_bus_busy_ps += config_.burst_cycles() * config_.tCK_ps;
      if (r.bursts_issued == config_.bursts_per_request()) complete(channel_index, c);
      break;
  }
}

// After the last burst of ch.queue[c.index].
void DramController::complete(uint32_t channel_index, const Choice& c) {
  Channel& ch = channels_[channel_index];
  const DramRequest& r = ch.queue[c.index];
  // A read's data are ready after CL plus its burst; a write's last beat is in after WL plus its
  // burst (tWR then only holds the bank's PRE back).
  const uint32_t latency = r.write ? config_.WL : config_.CL;
  const Tick ready = (c.cycle + latency + config_.burst_cycles()) * config_.tCK_ps;
  completions_.push(Pending{ready, r.seq, r.id, channel_index, r.arrival, r.write});
  if (row_policy_->close_after(ch, c.index)) {
    // Auto-precharge: at the earliest cycle the bank's PRE rules allow, without a command cycle.
    DramBank& b = ch.banks[r.bank];
    const size_t pre = size_t(Command::kPrecharge);
    const uint64_t cycle = std::max(b.earliest[pre], ch.earliest[pre]);
    stamp(ch, r.bank, Command::kPrecharge, cycle);
    record(cycle, channel_index, r.bank, Command::kPrecharge, r.row, 0, r.id);
    b.open = false;
    bank_closed(channel_index, cycle);
    ++stats_.precharges;
  }
  ch.queue.erase(ch.queue.begin() + std::ptrdiff_t(c.index));
  if (!ch.overflow.empty()) {
    ch.queue.push_back(ch.overflow.front());
    ch.overflow.pop_front();
  }
}

void DramController::advance(Tick now, std::vector<Completion>& done) {
  now_ = std::max(now_, now);
  const uint64_t last = now / config_.tCK_ps;  // the last command cycle at or before now
  for (uint32_t i = 0; i < channels_.size(); ++i) {
    Channel& ch = channels_[i];
    // next_[i] is the choice made after the channel last changed (a command or a request): it
    // stands until the channel changes, and one beyond `last` waits for a later call.
    if (ch.next_cycle > last) continue;
    while (next_[i].cycle != kDramNever && next_[i].cycle <= last) {
      const Choice c = next_[i];  // issue() changes the channel, then its choice is made again
      issue(i, c);
      rechoose(i);
    }
  }
  while (!completions_.empty() && completions_.top().time <= now) {
    const Pending p = completions_.top();
    completions_.pop();
    done.push_back(Completion{p.id, p.time, p.write});
    if (p.write) {
      ++stats_.writes;
      stats_.bytes_written += config_.request_bytes;
      stats_.last_write_completion_ps = std::max(stats_.last_write_completion_ps, p.time);
      continue;
    }
    ++stats_.reads;
    ++stats_.channel_reads[p.channel];
    stats_.bytes += config_.request_bytes;
    stats_.latency_sum_ps += p.time - p.arrival;
    stats_.last_completion_ps = std::max(stats_.last_completion_ps, p.time);
  }
}

void DramController::bank_opened(uint32_t channel, uint64_t cycle) {
  if (open_banks_[channel]++ > 0) return;
  open_since_[channel] = std::max(cycle, counted_until_[channel]);
  stretch_end_[channel] = 0;
}

void DramController::bank_closed(uint32_t channel, uint64_t cycle) {
  stretch_end_[channel] = std::max(stretch_end_[channel], cycle);
  if (--open_banks_[channel] > 0) return;
  const uint64_t end = stretch_end_[channel];
  if (end > open_since_[channel]) stats_.active_cycles += end - open_since_[channel];
  counted_until_[channel] = std::max(counted_until_[channel], end);
}

void DramController::settle_active(Tick now) {
  const uint64_t cycle = now / config_.tCK_ps;
  for (uint32_t i = 0; i < channels_.size(); ++i) {
    if (open_banks_[i] == 0 || cycle <= open_since_[i]) continue;
    stats_.active_cycles += cycle - open_since_[i];
    open_since_[i] = cycle;
    counted_until_[i] = std::max(counted_until_[i], cycle);
  }
}

std::string DramController::state() const {
  std::string s = "DRAM at " + std::to_string(now_) +
                  " ps: " + std::to_string(completions_.size()) + " completions due";
  for (size_t i = 0; i < channels_.size(); ++i) {
    const Channel& ch = channels_[i];
    if (ch.queue.empty() && ch.overflow.empty()) continue;
    s += "; ch" + std::to_string(i) + " " + std::to_string(ch.queue.size()) + " queued + " +
         std::to_string(ch.overflow.size()) + " waiting, next command at cycle " +
         (ch.next_cycle == kDramNever ? std::string("never") : std::to_string(ch.next_cycle));
  }
  return s;
}

Tick DramController::next_event_time() const {
  Tick t = completions_.empty() ? kUnknown : completions_.top().time;
  for (const Channel& ch : channels_)
    if (ch.next_cycle != kDramNever) t = std::min(t, ch.next_cycle * config_.tCK_ps);
  return t;
}

void DramController::register_stats(StatsRegistry& reg, const std::string& prefix) const {
  StatsRegistrar v(reg, prefix);
  describe_stats(v, stats_, config_.channels, refreshing_);
}

}  // namespace rtsim::model
