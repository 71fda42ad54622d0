#pragma once
// The regions of a signed distance field's grid beyond the exact band, and the side (inside or
// outside) each one lies on.
//
// A node beyond the band is farther than √3 spacings from the mesh, so the segment to any of its
// neighbours never crosses the surface: 6-connected sets of such nodes lie on one side. Each
// region's side is the majority of its nodes' own guesses (the sides the sweeps carried from
// the band), so that a band node signed wrongly (a closest point on a self-intersection, say)
// cannot flip a streak of nodes behind it.

#include <cstdint>
#include <span>
#include <vector>

namespace khz::contact::detail {

/// Regions of the non-exact nodes of a cubic grid, kept as runs along x.
class BandRegions {
 public:
  /// A maximal run of non-exact nodes [begin, end) in one grid row.
  struct Run {
    int begin;
    int end;
    int inside_votes;  ///< Nodes of the run whose own guess is inside.
  };

  /// @param nodes_per_axis n; the grid has n³ nodes, x fastest.
  explicit BandRegions(int nodes_per_axis);

  /// Records the runs of plane k from its n² node words (x fastest): a node is exact when its
  /// word has `exact_bit`, and guesses inside when it has `inside_bit`. Different planes may be
  /// scanned concurrently.
  void scan_plane(int k, const std::uint32_t* words, std::uint32_t exact_bit,
                  std::uint32_t inside_bit);

  /// Joins runs of adjacent rows that overlap into regions and decides each region's side by
  /// majority (a tie counts as outside). Call once, after every plane was scanned.
  void resolve();

  /// The runs of row (j, k), in order of x.
  std::span<const Run> runs(int j, int k) const noexcept;
  /// Whether the r-th run of row (j, k) is inside (after resolve()).
  bool inside(int j, int k, std::size_t r) const noexcept;

 private:
  int find(int run) noexcept;

  int m_n;
  std::vector<std::vector<Run>> m_plane_runs;       // per plane k
  std::vector<std::vector<int>> m_plane_row_start;  // per plane k: n + 1 offsets into its runs
  std::vector<std::int64_t> m_plane_offset;         // first global run id of each plane
  std::vector<int> m_parent;                        // union-find over global run ids
  std::vector<std::uint8_t> m_inside;               // per global run id, after resolve()
};

}  // namespace khz::contact::detail
