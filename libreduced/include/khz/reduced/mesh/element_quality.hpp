#pragma once
// Per-element volume and shape quality of a volume mesh, and the validity check FEM relies on.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

#include <iosfwd>
#include <vector>

namespace khz::reduced {

/// Volume and shape quality of every element of a VolumeMesh, plus summary statistics.
///
/// volume[e] (mesh units³): tetrahedra their signed volume (x1−x0)·((x2−x0)×(x3−x0))/6;
/// hexahedra Σ det J over the 2×2×2 Gauss points (weights 1), exact for the trilinear map.
///
/// quality[e] (dimensionless, larger is better, ≤ 0 means inverted or degenerate):
/// - tetrahedra: the smallest of the six dihedral angles in radians (arccos(1/3) ≈ 1.231 for
///   the regular tetrahedron, → 0 for slivers and needles), negated if the element is inverted;
/// - hexahedra: the minimum scaled Jacobian over the eight corners, det J / (|J₁|·|J₂|·|J₃|)
///   with J = ∂x/∂ξ at the corner and J_k its columns (so det J over the product of the three
///   edge vectors leaving the corner, up to the factor 8 both share): 1 for a cuboid, ≤ 0 for
///   an element inverted or collapsed at some corner.
///
/// Classification uses one determinant per element, d = the signed volume (tetrahedra) or the
/// minimum corner det J (hexahedra), against tolerance = 1e-12 · diagonal³, diagonal the length
/// of the bounding-box diagonal of all mesh vertices: an element is degenerate if |d| ≤
/// tolerance and inverted if d < −tolerance.
struct QualityReport {
  ElementType element_type = ElementType::tetrahedron;
  std::vector<double> volume;   ///< Per element, see above (mesh units³).
  std::vector<double> quality;  ///< Per element, see above (radians for tetrahedra).

  double total_volume = 0.0;  ///< Σ volume.
  double min_volume = 0.0;    ///< 0 for an empty mesh, as are all statistics below.
  double max_volume = 0.0;
  double min_quality = 0.0;
  double max_quality = 0.0;
  double mean_quality = 0.0;

  double tolerance = 0.0;  ///< The degeneracy tolerance described above (mesh units³).
  Eigen::Index num_inverted = 0;
  Eigen::Index num_degenerate = 0;
  /// Lowest-indexed inverted or degenerate element, or −1 if every element is valid.
  Eigen::Index first_bad_element = -1;
};

/// Computes the volume and quality of every element of `mesh`. O(#E).
/// @throws MeshError if the mesh fails validate().
KHZ_REDUCED_API QualityReport analyze_elements(const VolumeMesh& mesh);

/// Human-readable multi-line summary: counts, volume and quality ranges, invalid elements.
KHZ_REDUCED_API std::ostream& operator<<(std::ostream& out, const QualityReport& report);

/// Checks that `mesh` passes validate() and has no inverted or degenerate element (rule as in
/// QualityReport), the precondition of FEM assembly.
/// @throws MeshError with element() set to the first offending element and a message naming it
///         and its volume (and minimum corner Jacobian determinant for hexahedra), e.g.
///         "element 17 is inverted (signed volume -2.1e-09 m³)".
KHZ_REDUCED_API void require_valid_elements(const VolumeMesh& mesh);

}  // namespace khz::reduced
