#pragma once
// A spatial hash grid over particles: the neighbour search of particle repulsion (thesis §3.8.1:
// "we accelerate it using a hash table").

#include <khz/contact/common.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace khz::contact::detail {

/// Cubic cells of a given side; only the occupied ones are stored, found through an
/// open-addressing hash table, so memory grows with the points, not with the volume they span.
/// Immutable after construction; const queries are thread-safe and allocate nothing.
///
/// Cells list their points by index and are visited in a fixed order, so every query sees the
/// points in an order that depends only on their coordinates and indices: sums over neighbours
/// come out bit for bit the same on any thread count.
class RepulsionHashGrid {
 public:
  /// A run of slots: the points of one cell.
  struct Range {
    std::int32_t begin = 0;
    std::int32_t end = 0;
  };
  /// The (up to) 27 cells around a cell, itself included: all points within cell_size() of any
  /// point of the cell, and some farther ones.
  struct Neighbourhood {
    std::array<Range, 27> ranges;
    int count = 0;
  };

  /// The grid over rows [0, count) of `points`. Preconditions (the callers check them):
  /// count < 2³¹, finite points, cell_size > 0.
  RepulsionHashGrid(const Eigen::Ref<const PointMatrix>& points, Eigen::Index count,
                    double cell_size);

  double cell_size() const noexcept { return m_cell_size; }
  /// Occupied cells, numbered 0 … cell_count() − 1.
  std::size_t cell_count() const noexcept { return m_cells.size(); }
  /// The slots of occupied cell `cell`.
  Range cell_slots(std::size_t cell) const noexcept { return m_cells[cell].slots; }
  /// The occupied cells around occupied cell `cell`, in a fixed order.
  Neighbourhood neighbourhood(std::size_t cell) const noexcept;

  /// The point index and position in a slot.
  std::int32_t slot_point(std::int32_t slot) const noexcept {
    return m_slot_points[static_cast<std::size_t>(slot)];
  }
  const Eigen::Vector3d& slot_position(std::int32_t slot) const noexcept {
    return m_slot_positions[static_cast<std::size_t>(slot)];
  }

  /// Whether some point lies closer than `radius` to `position`; radius ≤ cell_size().
  bool has_point_within(const Eigen::Vector3d& position, double radius) const noexcept;

  /// The point other than `point` nearest to `position` (the position of `point`), and its
  /// distance; (−1, +∞) if the grid holds no other point. Searches shells of cells outwards
  /// until no unvisited cell can hold a nearer point, or scans all points if that takes more
  /// than 8 shells.
  std::pair<Eigen::Index, double> nearest_other(Eigen::Index point,
                                                const Eigen::Vector3d& position) const noexcept;

 private:
  using Coordinates = std::array<std::int64_t, 3>;
  struct Cell {
    Coordinates coordinates{};
    Range slots;
  };

  Coordinates cell_of(const Eigen::Vector3d& p) const noexcept;
  /// 21 bits per coordinate; coordinates beyond ±2²⁰ cells wrap around, which only adds far
  /// points to a query (every caller measures the distances).
  static std::uint64_t key_of(const Coordinates& c) noexcept;
  /// The number of the occupied cell at `c`, or −1.
  std::int32_t find(const Coordinates& c) const noexcept;

  double m_cell_size;
  double m_inverse_cell_size;
  std::vector<std::int32_t> m_slot_points;        ///< Point indices, cell after cell.
  std::vector<Eigen::Vector3d> m_slot_positions;  ///< Their positions, for locality.
  std::vector<Cell> m_cells;                      ///< Occupied cells in key order.
  std::vector<std::uint64_t> m_keys;              ///< Hash table: key per entry …
  std::vector<std::int32_t> m_entries;            ///< … and cell number, −1 when empty.
  std::uint64_t m_mask = 0;
  std::int64_t m_widest_shell = 0;  ///< Beyond this shell around any point no cell is occupied.
};

}  // namespace khz::contact::detail
