// The solver's time records (feti::Timings, feti::OperatorProfile) add and subtract member by
// member through their tables (core/fields.hpp): every member of the tables is set to its own
// value, so an adder that leaves one out fails by name; and the setup's seconds are not added per
// QP.
#include <gtest/gtest.h>

#include <iterator>
#include <type_traits>
#include <variant>

#include "feti/solver.hpp"

namespace dualcell::feti {
namespace {

// Every member of the table its own value, base + 1, base + 2, ...
template <class Table, class Record>
void set_each(const Table& table, Record& r, double base) {
  for_each_field(table, r, [&](const auto&, auto& member) {
    member = static_cast<std::remove_cvref_t<decltype(member)>>(base += 1);
  });
}

OperatorProfile profile_of(double base) {
  OperatorProfile p;
  set_each(operator_profile_fields, p, base);
  return p;
}

// A member added to a record without a row in its table breaks the build here: the structured
// bindings name every member, and each table has a row per member.
TEST(Timings, EveryMemberHasItsRow) {
  auto [F, Q, preconditioner, communication, exchanges, bytes_received] = OperatorProfile{};
  auto [assembly, factorisation, explicit_operators, dual_setup, qp, recovery, in_qp] = Timings{};
  (void)F, (void)Q, (void)preconditioner, (void)communication, (void)exchanges, (void)bytes_received;
  (void)assembly, (void)factorisation, (void)explicit_operators, (void)dual_setup, (void)qp, (void)recovery,
      (void)in_qp;
  EXPECT_EQ(std::size(operator_profile_fields), 6u);
  // And in_qp, walked by its own table.
  EXPECT_EQ(std::size(setup_timing_fields) + std::size(qp_timing_fields), 6u);
}

TEST(OperatorProfile, AddsAndSubtractsEveryMember) {
  const OperatorProfile a = profile_of(0), b = profile_of(100);
  OperatorProfile sum = a;
  sum += b;
  const OperatorProfile difference = b - a;
  for (const auto& field : operator_profile_fields)
    std::visit(
        [&](auto m) {
          EXPECT_EQ(sum.*m, a.*m + b.*m) << field.name;
          EXPECT_EQ(difference.*m, b.*m - a.*m) << field.name;
        },
        field.member);
}

TEST(Timings, AQpAddsItsOwnSecondsAndNotTheSetups) {
  Timings a, b;
  set_each(setup_timing_fields, a, 0);
  set_each(qp_timing_fields, a, 10);
  set_each(setup_timing_fields, b, 20);
  set_each(qp_timing_fields, b, 30);
  a.in_qp = profile_of(0);
  b.in_qp = profile_of(50);
  Timings sum = a;
  sum.add_qp(b);
  for (const auto& field : setup_timing_fields)
    std::visit([&](auto m) { EXPECT_EQ(sum.*m, a.*m) << field.name; }, field.member);
  for (const auto& field : qp_timing_fields)
    std::visit([&](auto m) { EXPECT_EQ(sum.*m, a.*m + b.*m) << field.name; }, field.member);
  for (const auto& field : operator_profile_fields)
    std::visit([&](auto m) { EXPECT_EQ(sum.in_qp.*m, a.in_qp.*m + b.in_qp.*m) << field.name; }, field.member);
}

}  // namespace
}  // namespace dualcell::feti
