// printf-style formatting into a std::string, for messages that carry
// numbers as people write them ("1e-300", "4294967295"), which
// std::to_string does not ("0.000000", "4294967295.000000").
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace surfdeform {

__attribute__((format(printf, 1, 2))) inline std::string Format(const char* format, ...) {
  va_list args;
  va_start(args, format);
  char small[256];
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(small, sizeof small, format, args);
  va_end(args);
  std::string out;
  if (n < 0) {
    out = format;
  } else if (static_cast<size_t>(n) < sizeof small) {
    out.assign(small, static_cast<size_t>(n));
  } else {
    out.resize(static_cast<size_t>(n) + 1);
    std::vsnprintf(out.data(), out.size(), format, again);
    out.resize(static_cast<size_t>(n));
  }
  va_end(again);
  return out;
}

// A number as people write it, to `digits` significant digits ("0.01",
// "1e+15"): what `std::ostream << x` writes at that precision.
inline std::string Num(double x, int digits = 6) { return Format("%.*g", digits, x); }

}  // namespace surfdeform
