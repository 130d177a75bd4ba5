// Line and token reading for the text mesh formats (OBJ, PLY ascii, STL ascii,
// OFF). Locale-independent number parsing.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>

#include "base/status.hpp"

namespace surfdeform::meshio {

class TextReader {
 public:
  explicit TextReader(std::string_view text) : rest_(text) {}

  // The next line without its end ("\n", "\r\n" or "\r"); false at the end.
  bool NextLine(std::string_view* line) {
    if (rest_.empty()) return false;
    size_t end = 0;
    while (end < rest_.size() && rest_[end] != '\n' && rest_[end] != '\r') ++end;
    *line = rest_.substr(0, end);
    size_t skip = end;
    if (skip < rest_.size() && rest_[skip] == '\r') ++skip;
    if (skip < rest_.size() && rest_[skip] == '\n' && (skip == end || rest_[end] == '\r')) ++skip;
    rest_.remove_prefix(std::min(skip, rest_.size()));
    ++line_number_;
    return true;
  }

  int line_number() const { return line_number_; }
  std::string_view rest() const { return rest_; }

 private:
  std::string_view rest_;
  int line_number_ = 0;
};

// Splits off the next whitespace-separated token; false when none is left.
inline bool NextToken(std::string_view* s, std::string_view* token) {
  size_t i = 0;
  while (i < s->size() && ((*s)[i] == ' ' || (*s)[i] == '\t' || (*s)[i] == '\f')) ++i;
  if (i == s->size()) {
    *s = {};
    return false;
  }
  size_t j = i;
  while (j < s->size() && (*s)[j] != ' ' && (*s)[j] != '\t' && (*s)[j] != '\f') ++j;
  *token = s->substr(i, j - i);
  s->remove_prefix(j);
  return true;
}

inline bool ParseNumber(std::string_view token, double* out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto r = std::from_chars(token.data(), token.data() + token.size(), *out);
  return r.ec == std::errc() && r.ptr == token.data() + token.size();
}

inline bool ParseNumber(std::string_view token, int64_t* out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto r = std::from_chars(token.data(), token.data() + token.size(), *out);
  return r.ec == std::errc() && r.ptr == token.data() + token.size();
}

inline Status LineError(int line, const std::string& what) {
  return InvalidArgument("line " + std::to_string(line) + ": " + what, "mesh");
}

}  // namespace surfdeform::meshio
