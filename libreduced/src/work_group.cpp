#include <khz/reduced/errors.hpp>
#include <khz/reduced/work_group.hpp>

#include <string>

namespace khz::reduced {

WorkGroup::~WorkGroup() = default;

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
