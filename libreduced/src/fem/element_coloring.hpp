#pragma once
// Element colouring for race-free parallel assembly. Elements are cut into small spatially
// compact chunks, and the chunks are coloured so that chunks of one colour share no vertex:
// threads can then scatter whole chunks into shared R and K without atomics or private copies.
// Chunks rather than single elements keep neighbouring elements together (their R and K entries
// overlap, so each chunk works in cache) and need far fewer colours, i.e. barriers.

#include <khz/reduced/mesh/volume_mesh.hpp>

#include <vector>

namespace khz::reduced::detail {

/// The assembly schedule: colour c holds chunks [color_offsets[c], color_offsets[c+1]), chunk k
/// the elements order[chunk_offsets[k] .. chunk_offsets[k+1]). Every entry of R and K receives
/// its contributions in this order whatever the number of threads, so results are bit-identical
/// for any thread count.
struct ElementColoring {
  std::vector<int> order;
  std::vector<int> chunk_offsets;  ///< num_chunks() + 1 entries.
  std::vector<int> color_offsets;  ///< num_colors() + 1 entries.

  int num_chunks() const noexcept { return static_cast<int>(chunk_offsets.size()) - 1; }
  int num_colors() const noexcept { return static_cast<int>(color_offsets.size()) - 1; }
};

/// Sorts the elements along a Morton (Z-order) curve through their centroids, cuts the sorted
/// list into chunks of `chunk_size` elements, and colours the chunks greedily: each chunk takes
/// the smallest colour no earlier chunk sharing one of its vertices has.
ElementColoring color_elements(const VolumeMesh& mesh, int chunk_size);

}  // namespace khz::reduced::detail
