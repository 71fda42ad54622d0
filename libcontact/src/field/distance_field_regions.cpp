#include "field/distance_field_regions.hpp"

#include <cassert>

namespace khz::contact::detail {

BandRegions::BandRegions(int nodes_per_axis)
    : m_n(nodes_per_axis),
      m_plane_runs(static_cast<std::size_t>(nodes_per_axis)),
      m_plane_row_start(static_cast<std::size_t>(nodes_per_axis)) {}

void BandRegions::scan_plane(int k, const std::uint32_t* words, std::uint32_t exact_bit,
                             std::uint32_t inside_bit) {
  std::vector<Run>& runs = m_plane_runs[static_cast<std::size_t>(k)];
  std::vector<int>& row_start = m_plane_row_start[static_cast<std::size_t>(k)];
  runs.clear();
  row_start.assign(static_cast<std::size_t>(m_n) + 1, 0);
  for (int j = 0; j < m_n; ++j) {
    row_start[static_cast<std::size_t>(j)] = static_cast<int>(runs.size());
    const std::uint32_t* row = words + static_cast<std::ptrdiff_t>(j) * m_n;
    for (int i = 0; i < m_n;) {
      if ((row[i] & exact_bit) != 0) {
        ++i;
        continue;
      }
      Run run{i, i, 0};
      for (; i < m_n && (row[i] & exact_bit) == 0; ++i)
        run.inside_votes += (row[i] & inside_bit) != 0;
      run.end = i;
      runs.push_back(run);
    }
  }
  row_start[static_cast<std::size_t>(m_n)] = static_cast<int>(runs.size());
}

std::span<const BandRegions::Run> BandRegions::runs(int j, int k) const noexcept {
  const auto& row_start = m_plane_row_start[static_cast<std::size_t>(k)];
  const auto begin = static_cast<std::size_t>(row_start[static_cast<std::size_t>(j)]);
  const auto end = static_cast<std::size_t>(row_start[static_cast<std::size_t>(j) + 1]);
  return std::span<const Run>(m_plane_runs[static_cast<std::size_t>(k)])
      .subspan(begin, end - begin);
}

int BandRegions::find(int run) noexcept {
  while (m_parent[static_cast<std::size_t>(run)] != run) {
    const int grandparent =
        m_parent[static_cast<std::size_t>(m_parent[static_cast<std::size_t>(run)])];
    m_parent[static_cast<std::size_t>(run)] = grandparent;  // path halving
    run = grandparent;
  }
  return run;
}

void BandRegions::resolve() {
  m_plane_offset.assign(static_cast<std::size_t>(m_n) + 1, 0);
  for (int k = 0; k < m_n; ++k) {
    m_plane_offset[static_cast<std::size_t>(k) + 1] =
        m_plane_offset[static_cast<std::size_t>(k)] +
        static_cast<std::int64_t>(m_plane_runs[static_cast<std::size_t>(k)].size());
  }
  const auto total = static_cast<std::size_t>(m_plane_offset.back());
  m_parent.resize(total);
  for (std::size_t r = 0; r < total; ++r) m_parent[r] = static_cast<int>(r);
  const auto id = [&](int j, int k, std::size_t r) {
    const auto& row_start = m_plane_row_start[static_cast<std::size_t>(k)];
    return static_cast<int>(m_plane_offset[static_cast<std::size_t>(k)] +
                            row_start[static_cast<std::size_t>(j)] + static_cast<std::int64_t>(r));
  };
  // Runs of face-adjacent rows that share an x are 6-connected.
  const auto join_rows = [&](int j0, int k0, int j1, int k1) {
    const auto a = runs(j0, k0), b = runs(j1, k1);
    std::size_t x = 0, y = 0;
    while (x < a.size() && y < b.size()) {
      if (a[x].begin < b[y].end && b[y].begin < a[x].end) {
        const int rx = find(id(j0, k0, x)), ry = find(id(j1, k1, y));
        if (rx != ry) m_parent[static_cast<std::size_t>(rx)] = ry;
      }
      if (a[x].end < b[y].end) {
        ++x;
      } else {
        ++y;
      }
    }
  };
  for (int k = 0; k < m_n; ++k) {
    for (int j = 0; j < m_n; ++j) {
      if (j + 1 < m_n) join_rows(j, k, j + 1, k);
      if (k + 1 < m_n) join_rows(j, k, j, k + 1);
    }
  }
  std::vector<std::int64_t> balance(total, 0);  // inside votes minus outside votes per root
  for (int k = 0; k < m_n; ++k) {
    for (int j = 0; j < m_n; ++j) {
      const auto row = runs(j, k);
      for (std::size_t r = 0; r < row.size(); ++r) {
        const std::int64_t length = row[r].end - row[r].begin;
        balance[static_cast<std::size_t>(find(id(j, k, r)))] += 2 * row[r].inside_votes - length;
      }
    }
  }
  m_inside.resize(total);
  for (std::size_t r = 0; r < total; ++r) {
    m_inside[r] = balance[static_cast<std::size_t>(find(static_cast<int>(r)))] > 0;
  }
}

bool BandRegions::inside(int j, int k, std::size_t r) const noexcept {
  assert(!m_inside.empty());
  const auto& row_start = m_plane_row_start[static_cast<std::size_t>(k)];
  const auto id = static_cast<std::size_t>(m_plane_offset[static_cast<std::size_t>(k)] +
                                           row_start[static_cast<std::size_t>(j)]) +
                  r;
  return m_inside[id] != 0;
}

}  // namespace khz::contact::detail
