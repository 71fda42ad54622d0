#include "pointshell/repulsion_hash_grid.hpp"

#include "pointshell/split_mix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace khz::contact::detail {

namespace {

// nearest_other() searches this many shells of cells (16³ cells) before it scans every point.
constexpr std::int64_t max_shells = 8;

}  // namespace

RepulsionHashGrid::RepulsionHashGrid(const Eigen::Ref<const PointMatrix>& points,
                                     Eigen::Index count, double cell_size)
    : m_cell_size(cell_size), m_inverse_cell_size(1.0 / cell_size) {
  // Points sorted by (cell key, index): the order, and so every query, is reproducible.
  std::vector<std::pair<std::uint64_t, std::int32_t>> keyed(static_cast<std::size_t>(count));
  Coordinates lowest{}, highest{};
  lowest.fill(std::numeric_limits<std::int64_t>::max());
  highest.fill(std::numeric_limits<std::int64_t>::min());
  for (Eigen::Index s = 0; s < count; ++s) {
    const Coordinates c = cell_of(points.row(s).transpose());
    for (std::size_t axis = 0; axis < 3; ++axis) {
      lowest[axis] = std::min(lowest[axis], c[axis]);
      highest[axis] = std::max(highest[axis], c[axis]);
    }
    keyed[static_cast<std::size_t>(s)] = {key_of(c), static_cast<std::int32_t>(s)};
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t axis = 0; axis < 3 && count > 0; ++axis) {
    m_widest_shell = std::max(m_widest_shell, highest[axis] - lowest[axis]);
  }

  m_slot_points.resize(keyed.size());
  m_slot_positions.resize(keyed.size());
  for (std::size_t s = 0; s < keyed.size(); ++s) {
    m_slot_points[s] = keyed[s].second;
    m_slot_positions[s] = points.row(keyed[s].second).transpose();
    if (s == 0 || keyed[s].first != keyed[s - 1].first) {
      m_cells.push_back({cell_of(m_slot_positions[s]), {static_cast<std::int32_t>(s), 0}});
    }
    m_cells.back().slots.end = static_cast<std::int32_t>(s + 1);
  }
  std::size_t size = 16;
  while (size < 2 * m_cells.size()) size *= 2;
  m_mask = size - 1;
  m_keys.assign(size, 0);
  m_entries.assign(size, -1);
  for (std::size_t cell = 0; cell < m_cells.size(); ++cell) {
    const std::uint64_t key = key_of(m_cells[cell].coordinates);
    std::uint64_t entry = split_mix(key) & m_mask;
    while (m_entries[entry] >= 0) entry = (entry + 1) & m_mask;
    m_keys[entry] = key;
    m_entries[entry] = static_cast<std::int32_t>(cell);
  }
}

RepulsionHashGrid::Coordinates RepulsionHashGrid::cell_of(const Eigen::Vector3d& p) const noexcept {
  Coordinates c{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    // Clamped so that the conversion is defined for any finite coordinate.
    const double scaled = std::floor(p[static_cast<Eigen::Index>(axis)] * m_inverse_cell_size);
    c[axis] = static_cast<std::int64_t>(std::clamp(scaled, -4e18, 4e18));
  }
  return c;
}

std::uint64_t RepulsionHashGrid::key_of(const Coordinates& c) noexcept {
  constexpr std::uint64_t bits = (std::uint64_t{1} << 21) - 1;
  return (static_cast<std::uint64_t>(c[0]) & bits) |
         ((static_cast<std::uint64_t>(c[1]) & bits) << 21) |
         ((static_cast<std::uint64_t>(c[2]) & bits) << 42);
}

std::int32_t RepulsionHashGrid::find(const Coordinates& c) const noexcept {
  const std::uint64_t key = key_of(c);
  for (std::uint64_t entry = split_mix(key) & m_mask;; entry = (entry + 1) & m_mask) {
    const std::int32_t cell = m_entries[entry];
    if (cell < 0 || m_keys[entry] == key) return cell;
  }
}

RepulsionHashGrid::Neighbourhood RepulsionHashGrid::neighbourhood(std::size_t cell) const noexcept {
  Neighbourhood around;
  const Coordinates& centre = m_cells[cell].coordinates;
  for (std::int64_t k = -1; k <= 1; ++k) {
    for (std::int64_t j = -1; j <= 1; ++j) {
      for (std::int64_t i = -1; i <= 1; ++i) {
        const std::int32_t found = find({centre[0] + i, centre[1] + j, centre[2] + k});
        if (found >= 0) {
          around.ranges[static_cast<std::size_t>(around.count++)] =
              m_cells[static_cast<std::size_t>(found)].slots;
        }
      }
    }
  }
  return around;
}

bool RepulsionHashGrid::has_point_within(const Eigen::Vector3d& position,
                                         double radius) const noexcept {
  const Coordinates centre = cell_of(position);
  const double radius_squared = radius * radius;
  const auto any_in = [&](const Coordinates& c) {
    const std::int32_t cell = find(c);
    if (cell < 0) return false;
    const Range slots = m_cells[static_cast<std::size_t>(cell)].slots;
    for (std::int32_t slot = slots.begin; slot < slots.end; ++slot) {
      if ((m_slot_positions[static_cast<std::size_t>(slot)] - position).squaredNorm() <
          radius_squared) {
        return true;
      }
    }
    return false;
  };
  // The position's own cell first: where a point within the radius most likely lies.
  if (any_in(centre)) return true;
  for (std::int64_t k = -1; k <= 1; ++k) {
    for (std::int64_t j = -1; j <= 1; ++j) {
      for (std::int64_t i = -1; i <= 1; ++i) {
        if ((i != 0 || j != 0 || k != 0) && any_in({centre[0] + i, centre[1] + j, centre[2] + k})) {
          return true;
        }
      }
    }
  }
  return false;
}

std::pair<Eigen::Index, double> RepulsionHashGrid::nearest_other(
    Eigen::Index point, const Eigen::Vector3d& position) const noexcept {
  const Coordinates centre = cell_of(position);
  double best_squared = std::numeric_limits<double>::infinity();
  Eigen::Index best = -1;
  const auto consider = [&](std::int32_t slot) {
    const auto s = static_cast<std::size_t>(slot);
    if (m_slot_points[s] == point) return;
    const double squared = (m_slot_positions[s] - position).squaredNorm();
    if (squared < best_squared || (squared == best_squared && m_slot_points[s] < best)) {
      best_squared = squared;
      best = m_slot_points[s];
    }
  };
  for (std::int64_t shell = 0; shell <= std::min(m_widest_shell, max_shells); ++shell) {
    // The cells whose largest coordinate offset from the centre is exactly `shell`.
    for (std::int64_t k = -shell; k <= shell; ++k) {
      for (std::int64_t j = -shell; j <= shell; ++j) {
        const bool on_face = std::abs(k) == shell || std::abs(j) == shell;
        const std::int64_t step = on_face || shell == 0 ? 1 : 2 * shell;
        for (std::int64_t i = -shell; i <= shell; i += step) {
          const std::int32_t cell = find({centre[0] + i, centre[1] + j, centre[2] + k});
          if (cell < 0) continue;
          const Range slots = m_cells[static_cast<std::size_t>(cell)].slots;
          for (std::int32_t slot = slots.begin; slot < slots.end; ++slot) consider(slot);
        }
      }
    }
    // Cells beyond this shell are at least shell · cell_size away from the position.
    const double reach = static_cast<double>(shell) * m_cell_size;
    if (best >= 0 && best_squared <= reach * reach) return {best, std::sqrt(best_squared)};
  }
  // An isolated point (shells grow as their cube): every point, once.
  if (m_widest_shell > max_shells) {
    for (std::size_t slot = 0; slot < m_slot_points.size(); ++slot) {
      consider(static_cast<std::int32_t>(slot));
    }
  }
  return {best, std::sqrt(best_squared)};
}

}  // namespace khz::contact::detail
