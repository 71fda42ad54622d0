#pragma once
// What the data-driven basis generators (sketch_basis, simulation_data_basis) share: anchor
// lists and the finishing touches on a PCA basis.

#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/errors.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced::detail {

/// The anchors sorted and distinct, each checked against [0, num_vertices).
/// @throws Error "<who>: fixed vertex <v> is outside [0, <num_vertices>)".
inline std::vector<int> sorted_fixed_vertices(std::span<const int> fixed_vertices,
                                              Eigen::Index num_vertices, std::string_view who) {
  std::vector<int> sorted(fixed_vertices.begin(), fixed_vertices.end());
  for (int v : sorted) {
    if (v < 0 || v >= num_vertices) {
      throw Error(std::string(who) + ": fixed vertex " + std::to_string(v) + " is outside [0, " +
                  std::to_string(num_vertices) + ")");
    }
  }
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  return sorted;
}

/// Sets the rows of the fixed vertices' dofs to exactly zero. A PCA basis is a combination of
/// samples that vanish there, but the mass-metric back-substitution leaves round-off.
inline void zero_fixed_rows(Eigen::MatrixXd& vectors, const std::vector<int>& sorted_fixed) {
  for (int v : sorted_fixed) vectors.middleRows(3 * Eigen::Index{v}, 3).setZero();
}

/// "mass PCA", "lumped-mass PCA" or "Euclidean PCA", for recipes.
inline std::string pca_name(PcaMetric metric) {
  switch (metric) {
    case PcaMetric::mass:
      return "mass PCA";
    case PcaMetric::lumped_mass:
      return "lumped-mass PCA";
    case PcaMetric::euclidean:
      return "Euclidean PCA";
  }
  return "PCA";
}

}  // namespace khz::reduced::detail
