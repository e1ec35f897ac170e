#pragma once
// A record's members listed once: a table of {name, member pointer} per record type, walked by
// every writer, reader, adder and test (docs/architecture.md, "one record walker"). A member is
// of one of the types its table names; the walkers see it typed (for_each_field), so a file writer
// writes a double as float64, a count or a flag as int64, a vector as its components, and a new
// member of a record is one line in its table.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <type_traits>
#include <variant>

namespace dualcell {

static_assert(std::is_same_v<long, std::int64_t>, "counts are 64-bit longs (LP64)");

// A member of Record of one of Types (the types its table holds: a walker is compiled for those
// alone, so a writer that cannot store one of them fails to build, not to run).
template <class Record, class... Types>
struct Field {
  static_assert(sizeof...(Types) > 0);
  using Member = std::variant<Types Record::*...>;
  const char* name;
  Member member;
  // A count's least value on reading (−1 where "none" is a value: the worst point of a check
  // without points).
  int min_count = 0;
  // What a number measures where the walkers must tell (solution.h5 writes the seconds of a
  // profile and not its bytes): "s" for wall seconds, "bytes", or "" (a count, a ratio, a stress).
  const char* unit = "";

  template <class T>
  bool holds() const {
    return std::holds_alternative<T Record::*>(member);
  }
};

// f(field, member) for each field of `table`, the member as a typed reference into `record`
// (const where the record is).
template <class Table, class Record, class F>
void for_each_field(const Table& table, Record& record, F&& f) {
  for (const auto& field : table) std::visit([&](auto member) { f(field, record.*member); }, field.member);
}

// f(field, a's member, b's member) for each field: adders and comparisons of two records.
template <class Table, class A, class B, class F>
void for_each_field(const Table& table, A& a, B& b, F&& f) {
  for (const auto& field : table) std::visit([&](auto member) { f(field, a.*member, b.*member); }, field.member);
}

// a += b member by member (the numbers of the table; a sum of two records' counts and seconds).
template <class Table, class Record>
void add_fields(const Table& table, Record& a, const Record& b, int sign = 1) {
  for_each_field(table, a, b, [sign](const auto&, auto& x, const auto& y) {
    using T = std::remove_cvref_t<decltype(x)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) x += sign * y;
  });
}

// The number of components of a member of type T as a file stores it (1 for a scalar).
template <class T>
constexpr int components_of() {
  if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) {
    static_assert(T::SizeAtCompileTime > 0, "a record's vector member has a fixed size");
    return static_cast<int>(T::SizeAtCompileTime);
  } else
    return 1;
}

}  // namespace dualcell
