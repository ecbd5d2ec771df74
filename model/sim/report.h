// How the model reports errors: through sc_report (SC_REPORT_ERROR) with message types of ours,
// so a virtual platform that embeds the model sees them like any other SystemC block's, and the
// testbench maps each type to its own message and exit code (testbench/run/simulate.cpp). Warnings
// (SC_REPORT_WARNING) say that a run goes on but its figures are not what one may expect.
#pragma once

#include <string>

namespace rtsim::model {

inline constexpr const char* kReportConfig = "rtsim/config";      // a configuration out of range
inline constexpr const char* kReportWatchdog = "rtsim/watchdog";  // a run that stopped moving
inline constexpr const char* kReportMemory = "rtsim/memory";      // an access outside the memory
inline constexpr const char* kReportTlm = "rtsim/tlm";            // a TLM-2.0 protocol violation
inline constexpr const char* kReportDevice = "rtsim/device";      // a program the device refused
inline constexpr const char* kReportTrace = "rtsim/trace";        // a trace that cannot be written
inline constexpr const char* kReportInternal = "rtsim/internal";  // a broken invariant: a bug
inline constexpr const char* kReportSerialised =
    "rtsim/serialised";  // warning: one access at a time

// SC_REPORT_ERROR(type, message). The default action throws the sc_report; a handler that returns
// instead cannot let the model continue, so this then throws std::runtime_error.
[[noreturn]] void report_error(const char* type, const std::string& message);

// SC_REPORT_WARNING(type, message): the default actions print it and the run goes on.
void report_warning(const char* type, const std::string& message);

}  // namespace rtsim::model
