#include "service/memory_budget.hpp"

#include <algorithm>

#include "base/format.hpp"

namespace surfdeform {

double ExtraPairsPerSample(int range) {
  const double r = std::max(range, 3);
  return 2.0 * r * (r + 1.0) - 24.0;
}

Status CheckMemory(double bytes, size_t budget, const std::string& what, const std::string& field) {
  if (bytes <= static_cast<double>(budget)) return Status::Ok();
  const double mib = 1024.0 * 1024.0;
  return Status::LimitExceeded(
      Format("%s would take about %.0f MiB, over this server's memory budget of %.0f MiB per "
             "request",
             what.c_str(), bytes / mib, static_cast<double>(budget) / mib),
      field, static_cast<double>(budget), bytes);
}

size_t CountWithin(size_t budget, double bytes_per_unit, size_t limit) {
  const double fits = static_cast<double>(budget) / bytes_per_unit;
  return fits >= static_cast<double>(limit) ? limit : static_cast<size_t>(fits);
}

}  // namespace surfdeform
