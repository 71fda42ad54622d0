// The rules every WorkGroup shares: how statuses combine, how a shared computation stops, and
// how units are shared out (khz/reduced/work_group.hpp).
#include <khz/reduced/errors.hpp>
#include <khz/reduced/work_group.hpp>

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace {

using khz::reduced::Cancelled;
using khz::reduced::combine_statuses;
using khz::reduced::Error;
using khz::reduced::GroupStatus;
using State = GroupStatus::State;

GroupStatus status(State state, std::int64_t done, std::string message = {}) {
  GroupStatus s;
  s.state = state;
  s.done = done;
  s.message = std::move(message);
  return s;
}

TEST(CombineStatuses, RunningGroupSumsTheUnits) {
  const std::vector<GroupStatus> all{status(State::running, 3), status(State::running, 4)};
  const GroupStatus group = combine_statuses(all);
  EXPECT_EQ(group.state, State::running);
  EXPECT_EQ(group.done, 7);
  EXPECT_EQ(group.rank, -1);
  EXPECT_TRUE(group.message.empty());
}

TEST(CombineStatuses, FailureOutranksCancelAndTheLowestRankSpeaks) {
  const std::vector<GroupStatus> all{status(State::cancelled, 1, "stop"),
                                     status(State::failed, 2, "first failure"),
                                     status(State::failed, 0, "second failure")};
  const GroupStatus group = combine_statuses(all);
  EXPECT_EQ(group.state, State::failed);
  EXPECT_EQ(group.rank, 1);
  EXPECT_EQ(group.message, "first failure");
  EXPECT_EQ(group.done, 3);
}

TEST(StopUnlessRunning, EachRankThrowsWhatItShould) {
  GroupStatus group = status(State::failed, 0, "bad mesh");
  group.rank = 1;
  const auto own = std::make_exception_ptr(std::runtime_error("own failure"));
  EXPECT_THROW(khz::reduced::stop_unless_running(group, 1, 2, "preparing", own),
               std::runtime_error);
  try {
    khz::reduced::stop_unless_running(group, 0, 2, "preparing", nullptr);
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(), "preparing failed on rank 1 of 2: bad mesh");
  }
  group.state = State::cancelled;
  group.message = "user";
  EXPECT_THROW(khz::reduced::stop_unless_running(group, 0, 2, "preparing", nullptr), Cancelled);
  group.state = State::running;
  EXPECT_NO_THROW(khz::reduced::stop_unless_running(group, 0, 2, "preparing", nullptr));
}

TEST(ShareOf, SharesAreContiguousAndDifferByAtMostOne) {
  std::int64_t next = 0;
  for (int rank = 0; rank < 3; ++rank) {
    const auto [begin, end] = khz::reduced::share_of(10, rank, 3);
    EXPECT_EQ(begin, next);
    EXPECT_GE(end - begin, 3);
    EXPECT_LE(end - begin, 4);
    next = end;
  }
  EXPECT_EQ(next, 10);
}

}  // namespace
