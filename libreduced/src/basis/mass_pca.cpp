// Mass-weighted PCA (thesis §2.8.1).
#include <khz/reduced/stage_progress.hpp>
#include "../detail/tall_qr.hpp"

#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>

#include <Eigen/SVD>

#include <optional>
#include <sstream>
#include <string>

namespace khz::reduced {

namespace {

void check_inputs(const Eigen::MatrixXd& samples, const SparseMatrix& mass,
                  const PcaOptions& options) {
  if (samples.cols() == 0) throw Error("principal_components: no samples");
  if (options.basis_size < 1 || options.basis_size > samples.cols()) {
    throw Error("principal_components: basis_size " + std::to_string(options.basis_size) +
                " is outside [1, " + std::to_string(samples.cols()) + "] (the number of samples)");
  }
  if (!(options.rank_tolerance >= 0.0 && options.rank_tolerance < 1.0)) {
    throw Error("principal_components: rank_tolerance must lie in [0, 1)");
  }
  if (options.metric != PcaMetric::euclidean &&
      (mass.rows() != samples.rows() || mass.cols() != samples.rows())) {
    throw Error("principal_components: the mass matrix is " + std::to_string(mass.rows()) + "×" +
                std::to_string(mass.cols()) + ", the samples have " +
                std::to_string(samples.rows()) + " rows");
  }
  for (Eigen::Index c = 0; c < samples.cols(); ++c) {
    if (!samples.col(c).allFinite()) {
      throw Error("principal_components: sample " + std::to_string(c) + " has a non-finite entry");
    }
  }
}

// The metric as a change of coordinates z = T x with xᵀMy = zᵀ(Ty), and its inverse on the
// basis: T = LᵀP for the Cholesky factor, diag(√m) for lumped mass, identity for euclidean.
class MetricCoordinates {
 public:
  MetricCoordinates(const SparseMatrix& mass, PcaMetric metric) : m_metric(metric) {
    if (metric == PcaMetric::mass) {
      m_cholesky.factorize(mass);  // SolverError if M is not positive definite
      m_mass_rows = mass;          // row-major: Eigen runs M·X on all OpenMP threads
    } else if (metric == PcaMetric::lumped_mass) {
      m_sqrt_lumped = Eigen::VectorXd::Zero(mass.rows());
      for (Eigen::Index j = 0; j < mass.outerSize(); ++j) {
        for (SparseMatrix::InnerIterator it(mass, j); it; ++it)
          m_sqrt_lumped(it.row()) += it.value();
      }
      for (Eigen::Index i = 0; i < m_sqrt_lumped.size(); ++i) {
        if (!(m_sqrt_lumped(i) > 0.0)) {
          throw SolverError("lumped mass matrix is not positive definite (row " +
                            std::to_string(i) + " sums to " + std::to_string(m_sqrt_lumped(i)) +
                            ")");
        }
      }
      m_sqrt_lumped = m_sqrt_lumped.cwiseSqrt();
    }
  }

  Eigen::MatrixXd to_metric(const Eigen::MatrixXd& x) const {
    switch (m_metric) {
      case PcaMetric::mass:
        return m_cholesky.solve_lower(Eigen::MatrixXd(m_mass_rows * x));  // L⁻¹P(PᵀLLᵀP)x = LᵀPx
      case PcaMetric::lumped_mass:
        return m_sqrt_lumped.asDiagonal() * x;
      case PcaMetric::euclidean:
        break;
    }
    return x;
  }

  Eigen::MatrixXd from_metric(const Eigen::MatrixXd& z) const {
    switch (m_metric) {
      case PcaMetric::mass:
        return m_cholesky.solve_upper(z);
      case PcaMetric::lumped_mass:
        return m_sqrt_lumped.cwiseInverse().asDiagonal() * z;
      case PcaMetric::euclidean:
        break;
    }
    return z;
  }

 private:
  PcaMetric m_metric;
  SparseCholesky m_cholesky;
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> m_mass_rows;
  Eigen::VectorXd m_sqrt_lumped;
};

// Flips columns so their largest-magnitude entry is positive: a reproducible sign.
void normalize_signs(Eigen::MatrixXd& basis) {
  for (Eigen::Index c = 0; c < basis.cols(); ++c) {
    Eigen::Index largest = 0;
    basis.col(c).cwiseAbs().maxCoeff(&largest);
    if (basis(largest, c) < 0.0) basis.col(c) *= -1.0;
  }
}

}  // namespace

PcaResult principal_components(const Eigen::MatrixXd& samples, const SparseMatrix& mass,
                               const PcaOptions& options) {
  check_inputs(samples, mass, options);
  StageProgress progress(options.progress, "mass PCA", 4);

  const MetricCoordinates coordinates(mass, options.metric);
  const Eigen::MatrixXd z = coordinates.to_metric(samples);
  progress.advance();

  // Z = QR, R = WΣVᵀ: the left singular vectors of Z are QW. Only the small N×N factor goes
  // through the SVD; the tall 3n×N QR is LAPACK's blocked Householder. (More samples than dofs,
  // a toy case, takes the SVD of Z directly.)
  const bool tall = z.rows() >= z.cols();
  std::optional<detail::TallQr> qr;
  if (tall) qr.emplace(z);
  progress.advance();
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(tall ? qr->r() : z, Eigen::ComputeThinU);
  progress.advance();

  PcaResult result;
  result.singular_values = svd.singularValues();
  const Eigen::Index k = result.singular_values.size();
  const int basis_size = options.basis_size;
  const double sigma1 = result.singular_values(0);
  if (basis_size > k ||
      !(result.singular_values(basis_size - 1) > options.rank_tolerance * sigma1)) {
    Eigen::Index rank = 0;
    while (rank < k && result.singular_values(rank) > options.rank_tolerance * sigma1) ++rank;
    std::ostringstream message;
    message << "principal_components: the samples span only " << rank
            << " directions (singular values above " << options.rank_tolerance
            << "·σ₁), fewer than the " << basis_size << " basis vectors asked for";
    throw Error(message.str());
  }

  Eigen::MatrixXd directions = Eigen::MatrixXd::Zero(z.rows(), basis_size);
  directions.topRows(svd.matrixU().rows()) = svd.matrixU().leftCols(basis_size);
  if (tall) qr->apply_q(directions);
  result.basis = coordinates.from_metric(directions);
  normalize_signs(result.basis);
  progress.finish();
  return result;
}

}  // namespace khz::reduced
