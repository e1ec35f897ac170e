// The ranks of a run (par/parallel.hpp) as the serial solver sees them: a default Group is this
// process alone, and every collective is then the identity, without communicating; the shared
// work counter hands out 0, 1, 2, … once each; an agreed input error is this process's own. The
// same calls over several ranks are exercised by tests/apps/*_mpi_test.cpp under mpiexec.
#include "par/parallel.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace dualcell::par {
namespace {

TEST(Parallel, AGroupOfOneIsTheIdentity) {
  const Group alone;
  EXPECT_EQ(alone.rank(), 0);
  EXPECT_EQ(alone.size(), 1);
  EXPECT_EQ(alone.max(2.5), 2.5);
  EXPECT_EQ(alone.max(7L), 7L);
  EXPECT_EQ(alone.broadcast(42L, 0), 42L);
  const std::vector<double> mine = {1.0, -2.0, 3.5};
  EXPECT_EQ(alone.gather(mine), mine);
  std::vector<double> all(3, 0.0);
  alone.gather(mine.data(), all.data(), {3}, {0});
  EXPECT_EQ(all, mine);
  // In place: mine is all + displs[rank()].
  alone.gather(all.data(), all.data(), {3}, {0});
  EXPECT_EQ(all, mine);
  // A split of one is one again.
  const Group part = alone.split(5);
  EXPECT_EQ(part.size(), 1);
  EXPECT_EQ(part.max(-1.0), -1.0);
}

TEST(Parallel, TheSharedCounterHandsOutEachIndexOnce) {
  SharedCounter counter;
  for (long expected = 0; expected < 5; ++expected) EXPECT_EQ(counter.next(), expected);
}

TEST(Parallel, AnAgreedErrorIsThisProcesssOwn) {
  EXPECT_NO_THROW(agree_on_error(""));
  try {
    agree_on_error("scene.toml:3: bad value");
    FAIL() << "no error thrown";
  } catch (const CollectiveInputError& e) {
    EXPECT_EQ(std::string(e.what()), "scene.toml:3: bad value");
  }
  EXPECT_EQ(sum(3L), 3L);
  EXPECT_GT(peak_rss_bytes(), 0);
}

}  // namespace
}  // namespace dualcell::par
