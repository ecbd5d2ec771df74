#include "model/sim/report.h"

#include <systemc>

#include <stdexcept>

namespace rtsim::model {

void report_error(const char* type, const std::string& message) {
  SC_REPORT_ERROR(type, message.c_str());
  throw std::runtime_error(std::string(type) + ": " + message);
}

void report_warning(const char* type, const std::string& message) {
  SC_REPORT_WARNING(type, message.c_str());
}

}  // namespace rtsim::model
