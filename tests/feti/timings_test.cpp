// The solver's time records (feti::Timings, feti::OperatorProfile) add and subtract member by
// member through their tables: every member of the tables is set to its own value, so an adder
// that leaves one out fails by name; and the setup's seconds are not added per QP.
#include <gtest/gtest.h>

#include <iterator>

#include "feti/solver.hpp"

namespace dualcell::feti {
namespace {

OperatorProfile profile_of(double base) {
  OperatorProfile p;
  double v = base;
  for (const OperatorProfileField& field : operator_profile_fields) {
    if (field.seconds) p.*field.seconds = (v += 1);
    if (field.count) p.*field.count = static_cast<long>(v += 1);
    if (field.amount) p.*field.amount = (v += 1);
  }
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
  EXPECT_EQ(std::size(timing_fields), 6u);  // and in_qp, walked by its own table
}

TEST(OperatorProfile, AddsAndSubtractsEveryMember) {
  const OperatorProfile a = profile_of(0), b = profile_of(100);
  OperatorProfile sum = a;
  sum += b;
  const OperatorProfile difference = b - a;
  for (const OperatorProfileField& field : operator_profile_fields) {
    if (field.seconds) {
      EXPECT_EQ(sum.*field.seconds, a.*field.seconds + b.*field.seconds) << field.name;
      EXPECT_EQ(difference.*field.seconds, b.*field.seconds - a.*field.seconds) << field.name;
    }
    if (field.count) {
      EXPECT_EQ(sum.*field.count, a.*field.count + b.*field.count) << field.name;
      EXPECT_EQ(difference.*field.count, b.*field.count - a.*field.count) << field.name;
    }
    if (field.amount) {
      EXPECT_EQ(sum.*field.amount, a.*field.amount + b.*field.amount) << field.name;
      EXPECT_EQ(difference.*field.amount, b.*field.amount - a.*field.amount) << field.name;
    }
  }
}

TEST(Timings, AQpAddsItsOwnSecondsAndNotTheSetups) {
  Timings a, b;
  double v = 0;
  for (const TimingField& field : timing_fields) a.*field.seconds = (v += 1), b.*field.seconds = (v += 10);
  a.in_qp = profile_of(0);
  b.in_qp = profile_of(50);
  Timings sum = a;
  sum.add_qp(b);
  for (const TimingField& field : timing_fields)
    EXPECT_EQ(sum.*field.seconds, field.per_qp ? a.*field.seconds + b.*field.seconds : a.*field.seconds) << field.name;
  for (const OperatorProfileField& field : operator_profile_fields)
    if (field.seconds) {
      EXPECT_EQ(sum.in_qp.*field.seconds, a.in_qp.*field.seconds + b.in_qp.*field.seconds) << field.name;
    }
  EXPECT_EQ(sum.in_qp.exchanges, a.in_qp.exchanges + b.in_qp.exchanges);
}

}  // namespace
}  // namespace dualcell::feti
