#include "model/memory/dram_command_trace.h"

#include "model/sim/report.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <system_error>

namespace rtsim::model {

namespace {

constexpr std::array<const char*, kDramCommands> kNames = {"ACT", "PRE", "REF", "RD", "WR"};
static_assert(size_t(DramCommand::kActivate) == 0 && size_t(DramCommand::kPrecharge) == 1 &&
                  size_t(DramCommand::kRefresh) == 2 && size_t(DramCommand::kRead) == 3 &&
                  size_t(DramCommand::kWrite) == 4,
              "kNames follows DramCommand");

void put(std::string& s, uint64_t v) {
  char digits[24];
  const auto end = std::to_chars(digits, digits + sizeof digits, v).ptr;
  s.append(digits, end);
}

}  // namespace

DramCommandTrace::DramCommandTrace(const TraceRequest& request, const Clock& clock)
    : request_(request), clock_(clock), part_(request.file + ".part") {
  buffer_.reserve(kDrainAt);
  open();
}

DramCommandTrace::~DramCommandTrace() {
  if (closed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(part_, ec);
}

void DramCommandTrace::open() {
  out_.close();
  out_.clear();
  out_.open(part_, std::ios::binary | std::ios::trunc);
  if (!out_) report_error(kReportTrace, "cannot write " + request_.file);
  out_ << "time_ps,channel,bank,command,row,column,request\n";
}

void DramCommandTrace::write(const Record& r) {
  const uint64_t cycle = clock_.to_cycles(r.time);
  if (cycle < request_.start_cycle || cycle >= request_.end_cycle) return;
  put(text_, r.time);
  text_ += ',';
  put(text_, r.channel);
  text_ += ',';
  put(text_, r.bank);
  text_ += ',';
  text_ += kNames[size_t(r.command)];
  text_ += ',';
  if (r.command != DramCommand::kRefresh) put(text_, r.row);
  text_ += ',';
  if (dram_is_column(r.command)) put(text_, r.column);
  text_ += ',';
  if (r.id != DramController::kNoRequest) put(text_, r.id);
  text_ += '\n';
}

void DramCommandTrace::release(std::vector<Record>& held, Tick until) {
  size_t n = 0;
  while (n < held.size() && held[n].time <= until) write(held[n++]);
  held.erase(held.begin(), held.begin() + std::ptrdiff_t(n));
}

void DramCommandTrace::drain() {
  text_.clear();
  for (const Record& r : buffer_) {
    if (r.channel >= held_.size()) held_.resize(r.channel + 1);
    std::vector<Record>& held = held_[r.channel];
    if (r.command != DramCommand::kPrecharge) {
      release(held, r.time);
      write(r);
      continue;
    }
    // In time order, after those of the same time (issue order). A PRE releases none: its time
    // may be ahead of the channel's (an auto-precharge).
    const auto at = std::upper_bound(held.begin(), held.end(), r.time,
                                     [](Tick t, const Record& h) { return t < h.time; });
    held.insert(at, r);
  }
  buffer_.clear();
  out_.write(text_.data(), std::streamsize(text_.size()));
}

void DramCommandTrace::restart() {
  if (closed_) return;
  buffer_.clear();
  held_.clear();
  open();
}

void DramCommandTrace::close() {
  if (closed_) return;
  drain();
  text_.clear();
  for (std::vector<Record>& held : held_) release(held, kUnknown);
  out_.write(text_.data(), std::streamsize(text_.size()));
  out_.close();
  closed_ = true;
  std::error_code ec;
  if (!out_.fail()) std::filesystem::rename(part_, request_.file, ec);
  if (out_.fail() || ec) {
    std::filesystem::remove(part_, ec);
    report_error(kReportTrace, "cannot write " + request_.file);
  }
}

}  // namespace rtsim::model
