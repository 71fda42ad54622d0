#pragma once
// Thinning a set of samples to a separation distance, densest first (thesis §2.8.2): used on
// recorded force loads (Euclidean force norm) and on static deformations (mass norm) before
// they reach the expensive solves and mass-PCA.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::reduced {

/// Options of select_separated_samples(). Both lengths are in the units of the distances.
struct KHZ_REDUCED_API SeparationOptions {
  /// δ ≥ 0: the retained samples are pairwise at least this far apart. 0 keeps every sample.
  double separation = 0.0;
  /// h ≥ 0, width of the radial kernel exp(−(d/h)²) that measures local density; 0 means
  /// h = δ. A wider kernel makes the density, and so the removal order, more global.
  double kernel_width = 0.0;

  /// @throws Error naming the first value that is negative or not finite.
  void validate() const;
};

/// Result of select_separated_samples().
struct SampleSelection {
  /// Indices of the retained samples, increasing.
  std::vector<int> kept;
  /// Indices of the removed samples in the order they were removed.
  std::vector<int> removed;
  /// Local density ρᵢ = Σⱼ exp(−(dᵢⱼ/h)²) of every sample among all N (j = i included, so
  /// ρᵢ ≥ 1), before any removal; N entries. With h = 0 (δ = 0 and no width given) the kernel's
  /// limit is used: ρᵢ counts the samples at distance 0 from sample i.
  Eigen::VectorXd initial_density;
};

/// Greedy separation (thesis §2.8.2): while some retained sample has a retained neighbour
/// closer than δ, remove the one of highest local density among such samples, the density
/// being taken over the samples still retained (it drops as neighbours go). Densities equal
/// to a relative 1e-12 count as equal and the higher index is removed, so the lowest index of a
/// cluster of identical samples is the one kept and the result does not depend on round-off
/// in the distances. At the end every retained pair is at least δ apart, and every removed
/// sample lay closer than δ to a sample retained at the time it was removed.
///
/// O(N²) time and O(N) memory beyond the distance matrix, for N up to a few thousand.
///
/// @param distances N × N pairwise distances (N ≥ 0); only the strict upper triangle
///                  (i < j) is read: the matrix is taken to be symmetric with zero diagonal.
/// @throws Error if `distances` is not square, a read entry is negative or not finite, or the
///         options are invalid.
KHZ_REDUCED_API SampleSelection select_separated_samples(const Eigen::MatrixXd& distances,
                                                         const SeparationOptions& options);

/// Pairwise distances from a Gram matrix G of inner products: dᵢⱼ = √max(0, Gᵢᵢ + Gⱼⱼ − 2Gᵢⱼ).
/// Cancellation limits the absolute accuracy to about √ε·max‖xᵢ‖ (1e-8 relative to the
/// largest sample): separations should be well above that.
/// @param gram N × N symmetric; only the upper triangle and diagonal are read.
/// @throws Error if it is not square or not finite.
KHZ_REDUCED_API Eigen::MatrixXd distances_from_gram(const Eigen::MatrixXd& gram);

/// Pairwise mass distances ‖uᵢ − uⱼ‖_M = √((uᵢ − uⱼ)ᵀM(uᵢ − uⱼ)) (thesis eq. 2.40; m·√kg for
/// displacements in metres and M in kg) of the columns of `samples`, through the Gram matrix
/// G = XᵀMX (see distances_from_gram()): one sparse product per column instead of N².
/// Reports stage "mass distances" in blocks of columns; cancel by returning false.
/// @param samples 3n × N displacements (columns).
/// @param mass    3n × 3n symmetric mass matrix (kg), e.g. FemModel::mass_matrix().
/// @throws Error if the sizes disagree or a sample is not finite; Cancelled.
KHZ_REDUCED_API Eigen::MatrixXd mass_distances(const Eigen::MatrixXd& samples,
                                               const SparseMatrix& mass,
                                               const ProgressCallback& progress = {});

}  // namespace khz::reduced
