#include "base/header_lists.hpp"

namespace surfdeform {
namespace {

char Lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

// Whether a parameter list ("level=1; q=0.0") weighs its element q=0.
bool WeighsZero(std::string_view parameters) {
  while (!parameters.empty()) {
    const size_t semicolon = parameters.find(';');
    const std::string_view parameter = TrimHttpSpace(parameters.substr(0, semicolon));
    parameters =
        semicolon == std::string_view::npos ? std::string_view() : parameters.substr(semicolon + 1);
    const size_t equals = parameter.find('=');
    if (equals == std::string_view::npos ||
        !EqualsIgnoringCase(TrimHttpSpace(parameter.substr(0, equals)), "q")) {
      continue;
    }
    const std::string_view weight = TrimHttpSpace(parameter.substr(equals + 1));
    // qvalue = ( "0" [ "." 0*3DIGIT ] ) / ( "1" [ "." 0*3("0") ] )
    return !weight.empty() && weight.find_first_not_of("0.") == std::string_view::npos;
  }
  return false;
}

}  // namespace

std::string_view TrimHttpSpace(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool EqualsIgnoringCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (Lower(a[i]) != Lower(b[i])) return false;
  }
  return true;
}

HeaderListItem PopHeaderListItem(std::string_view& header) {
  const size_t comma = header.find(',');
  const std::string_view element = header.substr(0, comma);
  header = comma == std::string_view::npos ? std::string_view() : header.substr(comma + 1);
  const size_t semicolon = element.find(';');
  HeaderListItem item;
  item.value = TrimHttpSpace(element.substr(0, semicolon));
  if (semicolon != std::string_view::npos) {
    item.parameters = TrimHttpSpace(element.substr(semicolon + 1));
    item.refused = WeighsZero(item.parameters);
  }
  return item;
}

}  // namespace surfdeform
