// qp::Counters: the adder adds every counter of its table (qp::counter_fields), and the table
// names every counter once.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "qp/result.hpp"

namespace dualcell::qp {
namespace {

TEST(Counters, TheAdderAddsEveryCounterOfTheTable) {
  Counters a, b;
  long k = 1;
  for_each_field(counter_fields, a, b, [&](const auto&, long& x, long& y) { x = k, y = 100 * k, ++k; });
  a += b;
  k = 1;
  for_each_field(counter_fields, a, [&](const auto& field, long x) { EXPECT_EQ(x, 101 * k++) << field.name; });
}

TEST(Counters, TheTableNamesEveryCounterOnce) {
  // Every member of Counters is a long: as many table rows as longs in the struct.
  EXPECT_EQ(std::size(counter_fields) * sizeof(long), sizeof(Counters));
  std::set<std::string> names;
  for (const auto& field : counter_fields) names.insert(field.name);
  EXPECT_EQ(names.size(), std::size(counter_fields));
  for (const auto& a : counter_fields)
    for (const auto& b : counter_fields) EXPECT_TRUE(&a == &b || a.member != b.member) << a.name << " " << b.name;
}

}  // namespace
}  // namespace dualcell::qp
