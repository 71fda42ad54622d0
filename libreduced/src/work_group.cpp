#include <khz/reduced/errors.hpp>
#include <khz/reduced/work_group.hpp>

#include <string>

namespace khz::reduced {

WorkGroup::~WorkGroup() = default;

GroupStatus combine_statuses(std::span<const GroupStatus> statuses) {
  GroupStatus group;
  for (std::size_t rank = 0; rank < statuses.size(); ++rank) {
    const GroupStatus& status = statuses[rank];
    group.done += status.done;
    if (status.state > group.state) {
      group.state = status.state;
      group.message = status.message;
      group.rank = static_cast<int>(rank);
    }
  }
  return group;
}

void stop_unless_running(const GroupStatus& group, int rank, int size, std::string_view what,
                         const std::exception_ptr& own_failure) {
  const std::string where =
      " on rank " + std::to_string(group.rank) + " of " + std::to_string(size);
  switch (group.state) {
    case GroupStatus::State::running:
      return;
    case GroupStatus::State::failed:
      if (group.rank == rank && own_failure) std::rethrow_exception(own_failure);
      throw Error(std::string(what) + " failed" + where + ": " + group.message);
    case GroupStatus::State::cancelled:
      if (group.rank == rank) throw Cancelled(group.message);
      throw Cancelled(std::string(what) + " cancelled" + where);
  }
}

}  // namespace khz::reduced
