#include <khz/mpi/mpi_work_group.hpp>

#include "mpi_error.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace khz::mpi {

using reduced::GroupStatus;

MpiWorkGroup::MpiWorkGroup(MPI_Comm communicator) {
  int initialized = 0;
  detail::check(MPI_Initialized(&initialized), "MPI_Initialized");
  if (!initialized) {
    throw reduced::Error(
        "MpiWorkGroup: MPI is not initialized (call MPI_Init, or make a khz::mpi::Environment, "
        "first)");
  }
  detail::check(MPI_Comm_dup(communicator, &m_communicator), "MPI_Comm_dup");
  // From here on a failed call returns its code, which check() turns into an exception.
  MPI_Comm_set_errhandler(m_communicator, MPI_ERRORS_RETURN);
  detail::check(MPI_Comm_rank(m_communicator, &m_rank), "MPI_Comm_rank");
  detail::check(MPI_Comm_size(m_communicator, &m_size), "MPI_Comm_size");
}

MpiWorkGroup::~MpiWorkGroup() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized && m_communicator != MPI_COMM_NULL) MPI_Comm_free(&m_communicator);
}

void MpiWorkGroup::sum(std::span<double> values) {
  constexpr std::size_t piece = std::size_t{1} << 28;  // MPI counts are ints
  for (std::size_t first = 0; first < values.size(); first += piece) {
    const std::size_t count = std::min(piece, values.size() - first);
    detail::check(MPI_Allreduce(MPI_IN_PLACE, values.data() + first, static_cast<int>(count),
                                MPI_DOUBLE, MPI_SUM, m_communicator),
                  "MPI_Allreduce");
  }
}

GroupStatus MpiWorkGroup::checkpoint(const GroupStatus& mine) {
  const std::array<std::int64_t, 2> brought{static_cast<std::int64_t>(mine.state), mine.done};
  std::vector<std::int64_t> everyone(2 * static_cast<std::size_t>(m_size));
  detail::check(MPI_Allgather(brought.data(), 2, MPI_INT64_T, everyone.data(), 2, MPI_INT64_T,
                              m_communicator),
                "MPI_Allgather");
  std::vector<GroupStatus> statuses(static_cast<std::size_t>(m_size));  // without messages
  for (std::size_t rank = 0; rank < statuses.size(); ++rank) {
    statuses[rank].state = static_cast<GroupStatus::State>(everyone[2 * rank]);
    statuses[rank].done = everyone[2 * rank + 1];
  }
  GroupStatus group = combine_statuses(statuses);
  if (group.state == GroupStatus::State::running) return group;
  // The message of the rank the state comes from, to every rank.
  std::string message = group.rank == m_rank ? mine.message : std::string();
  auto length = static_cast<int>(std::min<std::size_t>(message.size(), INT_MAX));
  detail::check(MPI_Bcast(&length, 1, MPI_INT, group.rank, m_communicator), "MPI_Bcast");
  message.resize(static_cast<std::size_t>(length));
  detail::check(MPI_Bcast(message.data(), length, MPI_CHAR, group.rank, m_communicator),
                "MPI_Bcast");
  group.message = std::move(message);
  return group;
}

}  // namespace khz::mpi
