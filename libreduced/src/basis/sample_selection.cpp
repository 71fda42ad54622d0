#include <khz/reduced/basis/sample_selection.hpp>
#include <khz/reduced/errors.hpp>

#include <khz/reduced/stage_progress.hpp>
#include "detail/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace khz::reduced {
namespace {

/// Densities within this relative difference are a tie (broken by index).
constexpr double density_tie = 1e-12;
/// Columns per sparse product in mass_distances(): one progress unit.
constexpr Eigen::Index distance_block = 32;

/// The radial kernel exp(−(d/h)²), and its limit (1 at d = 0, else 0) for h = 0.
double kernel(double distance, double width) noexcept {
  if (width == 0.0) return distance == 0.0 ? 1.0 : 0.0;
  const double x = distance / width;
  return std::exp(-x * x);
}

void check_non_negative(double value, const char* name) {
  if (!std::isfinite(value) || value < 0.0) {
    throw Error(std::string("SeparationOptions: ") + name +
                " must be finite and non-negative, got " + detail::number_text(value));
  }
}

}  // namespace

void SeparationOptions::validate() const {
  check_non_negative(separation, "separation");
  check_non_negative(kernel_width, "kernel_width");
}

// Thesis §2.8.2: "a greedy approach that iteratively removes force samples which are too close
// to other samples, with the removal prioritized based on local density of the samples as
// defined under some radial kernel". The same selection thins the static deformations by mass
// distance.
SampleSelection select_separated_samples(const Eigen::MatrixXd& distances,
                                         const SeparationOptions& options) {
  options.validate();
  if (distances.rows() != distances.cols()) {
    throw Error("select_separated_samples: the distance matrix is " +
                std::to_string(distances.rows()) + " × " + std::to_string(distances.cols()) +
                ", not square");
  }
  const Eigen::Index n = distances.rows();
  const double delta = options.separation;
  const double width = options.kernel_width > 0.0 ? options.kernel_width : delta;

  // ρᵢ over all samples, and the number of samples closer than δ to each.
  Eigen::VectorXd density = Eigen::VectorXd::Ones(n);
  std::vector<int> close(static_cast<std::size_t>(n), 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      const double d = distances(i, j);
      if (!std::isfinite(d) || d < 0.0) {
        throw Error("select_separated_samples: distance (" + std::to_string(i) + ", " +
                    std::to_string(j) + ") is " + detail::number_text(d) +
                    "; distances must be finite and non-negative");
      }
      const double k = kernel(d, width);
      density[i] += k;
      density[j] += k;
      if (d < delta) {
        ++close[static_cast<std::size_t>(i)];
        ++close[static_cast<std::size_t>(j)];
      }
    }
  }

  SampleSelection selection;
  selection.initial_density = density;
  std::vector<char> retained(static_cast<std::size_t>(n), 1);
  for (;;) {
    double highest = -1.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (retained[static_cast<std::size_t>(i)] && close[static_cast<std::size_t>(i)] > 0) {
        highest = std::max(highest, density[i]);
      }
    }
    if (highest < 0.0) break;  // no retained sample has a neighbour closer than δ
    Eigen::Index removed = -1;
    for (Eigen::Index i = n - 1; i >= 0; --i) {
      if (retained[static_cast<std::size_t>(i)] && close[static_cast<std::size_t>(i)] > 0 &&
          density[i] >= highest * (1.0 - density_tie)) {
        removed = i;
        break;
      }
    }
    retained[static_cast<std::size_t>(removed)] = 0;
    selection.removed.push_back(static_cast<int>(removed));
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!retained[static_cast<std::size_t>(j)]) continue;
      const double d = j < removed ? distances(j, removed) : distances(removed, j);
      density[j] -= kernel(d, width);
      if (d < delta) --close[static_cast<std::size_t>(j)];
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (retained[static_cast<std::size_t>(i)]) selection.kept.push_back(static_cast<int>(i));
  }
  return selection;
}

Eigen::MatrixXd distances_from_gram(const Eigen::MatrixXd& gram) {
  if (gram.rows() != gram.cols()) {
    throw Error("distances_from_gram: the Gram matrix is " + std::to_string(gram.rows()) + " × " +
                std::to_string(gram.cols()) + ", not square");
  }
  if (!gram.triangularView<Eigen::Upper>().toDenseMatrix().allFinite()) {
    throw Error("distances_from_gram: the Gram matrix has non-finite entries");
  }
  const Eigen::Index n = gram.rows();
  Eigen::MatrixXd distances = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      const double d = std::sqrt(std::max(0.0, gram(i, i) + gram(j, j) - 2.0 * gram(i, j)));
      distances(i, j) = d;
      distances(j, i) = d;
    }
  }
  return distances;
}

Eigen::MatrixXd mass_distances(const Eigen::MatrixXd& samples, const SparseMatrix& mass,
                               const ProgressCallback& progress) {
  if (mass.rows() != samples.rows() || mass.cols() != samples.rows()) {
    throw Error("mass_distances: the samples have " + std::to_string(samples.rows()) +
                " rows but the mass matrix is " + std::to_string(mass.rows()) + " × " +
                std::to_string(mass.cols()));
  }
  for (Eigen::Index j = 0; j < samples.cols(); ++j) {
    if (!samples.col(j).allFinite()) {
      throw Error("mass_distances: sample " + std::to_string(j) + " is not finite");
    }
  }
  const Eigen::Index n = samples.cols();
  const std::int64_t blocks = (n + distance_block - 1) / distance_block;
  StageProgress progress_stage(progress, "mass distances", blocks);
  // The upper triangle of G = XᵀMX, a block of columns at a time.
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index start = 0; start < n; start += distance_block) {
    const Eigen::Index width = std::min(distance_block, n - start);
    const Eigen::MatrixXd weighted = mass * samples.middleCols(start, width);
    gram.block(0, start, start + width, width).noalias() =
        samples.leftCols(start + width).transpose() * weighted;
    progress_stage.advance();
  }
  progress_stage.finish();
  return distances_from_gram(gram);
}

}  // namespace khz::reduced
