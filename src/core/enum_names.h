// Enum <-> name tables: one table per enum, read both ways (ToString, and parsing a config's or a
// flag's name with an error that lists the choices).
//
//   inline constexpr EnumName<RootHandling> kRootHandlingNames[] = {
//       {RootHandling::kRelativeDrop, "relative_drop"}, {RootHandling::kRelative, "relative"}};
//   NameOf(RootHandling::kRelative, kRootHandlingNames)   -> "relative"
//   ValueNamed("relative", kRootHandlingNames)            -> RootHandling::kRelative
//   NameChoices(kRootHandlingNames)                       -> "'relative_drop' or 'relative'"
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>

namespace motionfork {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

// value's name in table (the first, when it has several); "?" when it has none.
template <typename E, std::size_t N>
const char* NameOf(E value, const EnumName<E> (&table)[N]) {
  for (const EnumName<E>& e : table) {
    if (e.value == value) return e.name;
  }
  return "?";
}

// The value called `name` in table; nothing when no entry has that name.
template <typename E, std::size_t N>
std::optional<E> ValueNamed(const std::string& name, const EnumName<E> (&table)[N]) {
  for (const EnumName<E>& e : table) {
    if (name == e.name) return e.value;
  }
  return std::nullopt;
}

// The names for a message: "'a', 'b' or 'c'" (quote "" gives "a, b or c").
template <typename E, std::size_t N>
std::string NameChoices(const EnumName<E> (&table)[N], const std::string& quote = "'") {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    out += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + quote + table[i].name + quote;
  }
  return out;
}

// The value called `name`; otherwise std::invalid_argument "<what>: expected 'a' or 'b', got
// '<name>'".
template <typename E, std::size_t N>
E ParseEnumName(const std::string& name, const EnumName<E> (&table)[N], const std::string& what) {
  if (const std::optional<E> v = ValueNamed(name, table)) return *v;
  throw std::invalid_argument(what + ": expected " + NameChoices(table) + ", got '" + name + "'");
}

}  // namespace motionfork
