#pragma once
// How an object's signed distance field is computed (and, for a reduced object, deformed).

#include <Eigen/Core>

#include <cstdint>

namespace khz::scene {

/// JSON object.field: the distance field of an object with the distance_field role, and the
/// level-set field a repulsion pointshell is fitted on (thesis §3.8.1, §3.11, §3.12). The JSON
/// keys are the member names.
struct FieldDescription {
  /// Cells per axis of the cube around the mesh, in [1, 32768] (the grid's memory budget,
  /// 1 GiB by default, is checked when the field is computed); DistanceFieldOptions::cells.
  int cells = 128;
  /// Edge of the cube over the mesh's longest side, ≥ 1; DistanceFieldOptions::box_expansion.
  double box_expansion = 1.5;
  /// Nodes within this many cell spacings of the mesh are exact, ≥ √3;
  /// DistanceFieldOptions::exact_band.
  double exact_band = 3.0;
  /// The mesh is a polygon soup (open, non-manifold, self-intersecting): the field is signed by
  /// an offset surface (contact::polygon_soup_field) instead of the mesh itself
  /// (signed_distance_field).
  bool soup = false;
  /// σ (m) of the soup's offset surface, ≥ 0, 0 for 1.4 grid spacings; soups only;
  /// PolygonSoupFieldOptions::offset.
  double offset = 0.0;

  // --- a reduced object's deformed field (contact::DeformedFieldOptions, same names) ---
  /// Proxies fitted by particle repulsion, ≥ neighbours.
  Eigen::Index proxies = 40;
  /// k, the nearest proxies blended per lookup, in [2, 16].
  int neighbours = 5;
  /// Seed of the proxies' starting positions.
  std::uint64_t seed = 0;
};

}  // namespace khz::scene
