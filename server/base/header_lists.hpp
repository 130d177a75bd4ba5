// HTTP list headers (RFC 9110 section 5.6.1): Accept, Accept-Encoding,
// If-None-Match. One reader of their elements, weights and whitespace for
// content negotiation and conditional requests alike.
#pragma once

#include <string_view>

namespace surfdeform {

// One element of a list header.
struct HeaderListItem {
  std::string_view value;       // before the first ';', without surrounding whitespace
  std::string_view parameters;  // after it, without surrounding whitespace ("" when none)
  bool refused = false;         // weighted q=0 (q=0, q=0.0, ... ; RFC 9110 section 12.4.2)
};

// `s` without leading and trailing spaces and tabs (RFC 9110's OWS).
std::string_view TrimHttpSpace(std::string_view s);

// Whether `a` and `b` are equal ignoring ASCII case (media types, codings).
bool EqualsIgnoringCase(std::string_view a, std::string_view b);

// The element of `header` starting at its front, `header` advanced past it
// and its comma. Empty elements (", ,") come out with an empty value.
HeaderListItem PopHeaderListItem(std::string_view& header);

// f(item) for each element of `header` with a non-empty value, in order,
// until f returns true. True when one did.
template <typename F>
bool AnyHeaderListItem(std::string_view header, F&& f) {
  while (!header.empty()) {
    const HeaderListItem item = PopHeaderListItem(header);
    if (!item.value.empty() && f(item)) return true;
  }
  return false;
}

}  // namespace surfdeform
