#include <khz/test/thread_work_group.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

namespace khz::test {

class ThreadWorkGroup::Member final : public reduced::WorkGroup {
 public:
  Member(ThreadWorkGroup& group, int rank) : m_group(group), m_rank(rank) {}

  int rank() const noexcept override { return m_rank; }
  int size() const noexcept override { return m_group.m_size; }

  void sum(std::span<double> values) override {
    auto& mine = m_group.m_values[static_cast<std::size_t>(m_rank)];
    mine.assign(values.begin(), values.end());
    arrive(values.size());  // every contribution is in
    for (std::size_t i = 0; i < values.size(); ++i) {
      double total = 0.0;
      for (const auto& contribution : m_group.m_values) total += contribution[i];
      values[i] = total;
    }
    m_group.m_barrier.arrive_and_wait();  // every member has read them
  }

  reduced::GroupStatus checkpoint(const reduced::GroupStatus& status) override {
    m_group.m_statuses[static_cast<std::size_t>(m_rank)] = status;
    arrive(std::string::npos);
    reduced::GroupStatus all = reduced::combine_statuses(m_group.m_statuses);
    m_group.m_barrier.arrive_and_wait();
    return all;
  }

 private:
  // Waits for every member at the start of a collective and checks they all make this one.
  void arrive(std::size_t call) {
    m_group.m_calls[static_cast<std::size_t>(m_rank)] = call;
    m_group.m_barrier.arrive_and_wait();
    for (const std::size_t other : m_group.m_calls) {
      if (other != call) {
        std::fprintf(stderr,
                     "ThreadWorkGroup: rank %d entered %s while another rank entered %s: the "
                     "processes' collectives are out of step\n",
                     m_rank, describe(call).c_str(), describe(other).c_str());
        std::abort();
      }
    }
  }

  static std::string describe(std::size_t call) {
    return call == std::string::npos ? "checkpoint()" : "sum() of " + std::to_string(call);
  }

  ThreadWorkGroup& m_group;
  int m_rank;
};

ThreadWorkGroup::ThreadWorkGroup(int size)
    : m_size(size),
      m_barrier(size),
      m_values(static_cast<std::size_t>(size)),
      m_statuses(static_cast<std::size_t>(size)),
      m_calls(static_cast<std::size_t>(size)) {
  for (int rank = 0; rank < size; ++rank)
    m_members.push_back(std::make_unique<Member>(*this, rank));
}

ThreadWorkGroup::~ThreadWorkGroup() = default;

reduced::WorkGroup& ThreadWorkGroup::member(int rank) {
  return *m_members[static_cast<std::size_t>(rank)];
}

void ThreadWorkGroup::run(const std::function<void(int, reduced::WorkGroup&)>& body) {
  std::vector<std::jthread> threads;
  for (int rank = 0; rank < m_size; ++rank) {
    threads.emplace_back([&, rank] { body(rank, member(rank)); });
  }
}

}  // namespace khz::test
