#pragma once
// The one test walk over a record table (core/fields.hpp): set every member of a record to its
// own value, and compare two records member by member, failing by the member's name. A writer,
// reader or JSON walk that leaves a member out (or swaps two) fails here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

#include "core/fields.hpp"

namespace dualcell::testing {

// Every member its own value: numbers base + 0.25·k, counts base + k, flags alternating, texts
// "<name> text", vectors of distinct components. With `unit`, only the fields of that unit.
template <class Table, class Record>
void set_each_field(const Table& table, Record& record, int base = 1, const char* unit = nullptr) {
  int k = base;
  for_each_field(table, record, [&](const auto& field, auto& v) {
    using T = std::remove_cvref_t<decltype(v)>;
    if (unit && std::string(field.unit) != unit) return;
    ++k;
    if constexpr (std::is_same_v<T, bool>)
      v = k % 2 == 0;
    else if constexpr (std::is_integral_v<T>)
      v = static_cast<T>(k);
    else if constexpr (std::is_same_v<T, double>)
      v = base + 0.25 * k;
    else if constexpr (std::is_same_v<T, std::string>)
      v = std::string(field.name) + " text";
    else
      for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = base + 0.25 * k + 0.0625 * static_cast<double>(i);
  });
}

// Equal, NaN as NaN.
inline bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// Every member of `a` equal to b's (with `unit`, those of that unit), each failure naming `where`
// and the member.
template <class Table, class Record>
void expect_same_fields(const Table& table, const Record& a, const Record& b, const std::string& where = "",
                        const char* unit = nullptr) {
  for_each_field(table, a, b, [&](const auto& field, const auto& x, const auto& y) {
    using T = std::remove_cvref_t<decltype(x)>;
    if (unit && std::string(field.unit) != unit) return;
    bool equal = true;
    if constexpr (std::is_same_v<T, double>)
      equal = same_value(x, y);
    else if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, std::string>)
      equal = x == y;
    else
      for (Eigen::Index i = 0; i < x.size(); ++i) equal = equal && same_value(x(i), y(i));
    EXPECT_TRUE(equal) << where << " " << field.name;
  });
}

}  // namespace dualcell::testing
