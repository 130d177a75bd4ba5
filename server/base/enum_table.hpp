// One table per enum: each value with its name (as the API spells it) and a
// description. Parsing, printing, GET /v1/info and the CLI's choices all read
// the same table, so a name is written once.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace surfdeform {

template <typename E>
struct EnumEntry {
  E value;
  std::string_view name;
  std::string_view description;
};

// The name of `value` in `table` ("" when it has none).
template <typename E>
constexpr std::string_view NameOf(std::span<const EnumEntry<E>> table, E value) {
  for (const EnumEntry<E>& e : table) {
    if (e.value == value) return e.name;
  }
  return {};
}

// The value named `name`, if any.
template <typename E>
constexpr std::optional<E> ValueOf(std::span<const EnumEntry<E>> table, std::string_view name) {
  for (const EnumEntry<E>& e : table) {
    if (e.name == name) return e.value;
  }
  return std::nullopt;
}

// Every name, in the table's order.
template <typename E>
std::vector<std::string> NamesOf(std::span<const EnumEntry<E>> table) {
  std::vector<std::string> names;
  for (const EnumEntry<E>& e : table) names.emplace_back(e.name);
  return names;
}

// Every name, in the table's order, as a list for a message: "a, b or c".
template <typename E>
std::string OneOf(std::span<const EnumEntry<E>> table) {
  std::string out;
  for (size_t k = 0; k < table.size(); ++k) {
    if (k > 0) out += k + 1 == table.size() ? " or " : ", ";
    out += table[k].name;
  }
  return out;
}

}  // namespace surfdeform
