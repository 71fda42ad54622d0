// Linear modal analysis by ARPACK in shift-invert mode (thesis eq. 2.43, §2.8.7).
#include <khz/reduced/stage_progress.hpp>
#include "../detail/thread_limited_call.hpp"
#include "modal_problem.hpp"

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/errors.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

// ARPACK-NG's ISO C bindings (libarpack2). Declared here rather than through <arpack/arpack.h>,
// which also declares the complex variants with C99 _Complex types that C++ does not accept.
// Debian builds ARPACK with 32-bit Fortran integers.
extern "C" {
void dsaupd_c(int* ido, const char* bmat, int n, const char* which, int nev, double tol,
              double* resid, int ncv, double* v, int ldv, int* iparam, int* ipntr, double* workd,
              double* workl, int lworkl, int* info);
void dseupd_c(int rvec, const char* howmny, const int* select, double* d, double* z, int ldz,
              double sigma, const char* bmat, int n, const char* which, int nev, double tol,
              double* resid, int ncv, double* v, int ldv, int* iparam, int* ipntr, double* workd,
              double* workl, int lworkl, int* info);
}

namespace khz::reduced {

namespace {

void check_options(const LinearModesOptions& options) {
  if (options.num_modes < 1) {
    throw Error("num_modes must be at least 1 (got " + std::to_string(options.num_modes) + ")");
  }
  if (!(options.tolerance >= 0.0)) throw Error("tolerance must be ≥ 0");
  if (options.max_restarts < 1) throw Error("max_restarts must be at least 1");
}

struct Eigenpairs {
  Eigen::VectorXd values;   // ascending
  Eigen::MatrixXd vectors;  // M-orthonormal columns
  int solves = 0;
};

// The `count` eigenpairs of K x = λ M x nearest the shift σ (ARPACK mode 3: OP = (K − σM)⁻¹M,
// B = M; Ritz values θ of OP map back to λ = σ + 1/θ).
Eigenpairs lowest_eigenpairs(const detail::ModalProblem& problem, int count,
                             const LinearModesOptions& options) {
  const auto n = static_cast<int>(problem.stiffness().rows());
  const int ncv = std::min(n, std::max(2 * count + 1, 20));
  // Operator applications: ~ncv for the first Lanczos factorization, then ncv − count per
  // restart; a few restarts is typical.
  StageProgress progress(options.progress, "linear modes", 1 + 4 * ncv);
  const SparseCholesky shifted = problem.factorize_shifted();
  progress.advance();

  std::vector<double> resid(static_cast<std::size_t>(n));
  {
    // A fixed start vector: ARPACK's own random start depends on earlier calls in the process.
    std::mt19937_64 generator(20261121);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& r : resid) r = uniform(generator);
  }
  const int lworkl = ncv * (ncv + 8);
  std::vector<double> v(static_cast<std::size_t>(n) * static_cast<std::size_t>(ncv));
  std::vector<double> workd(3 * static_cast<std::size_t>(n));
  std::vector<double> workl(static_cast<std::size_t>(lworkl));
  int iparam[11] = {};
  int ipntr[11] = {};
  iparam[0] = 1;  // exact shifts
  iparam[2] = options.max_restarts;
  iparam[6] = 3;  // shift-invert, generalized
  int ido = 0;
  int info = 1;  // use resid as the start vector

  const auto vector_at = [&](int pointer) {
    return Eigen::Map<Eigen::VectorXd>(workd.data() + pointer - 1, n);  // Fortran index
  };
  Eigen::VectorXd mass_times(n);
  int solves = 0;
  for (;;) {
    // ARPACK's BLAS calls (OpenBLAS threads) held to worker_threads().
    detail::thread_limited([&]() noexcept {
      dsaupd_c(&ido, "G", n, "LM", count, options.tolerance, resid.data(), ncv, v.data(), n, iparam,
               ipntr, workd.data(), workl.data(), lworkl, &info);
    });
    if (ido == -1) {
      mass_times.noalias() = problem.mass() * vector_at(ipntr[0]);
      vector_at(ipntr[1]) = shifted.solve(mass_times);
    } else if (ido == 1) {
      vector_at(ipntr[1]) = shifted.solve(Eigen::VectorXd(vector_at(ipntr[2])));
    } else if (ido == 2) {
      vector_at(ipntr[1]).noalias() = problem.mass() * vector_at(ipntr[0]);
      continue;
    } else {
      break;
    }
    ++solves;
    // More restarts than estimated: keep the bar short of the end until ARPACK is done.
    if (progress.done() + 1 >= progress.total()) progress.raise_total(progress.total() + ncv);
    progress.advance();
  }
  if (info == 1) {
    throw SolverError("ARPACK did not converge in " + std::to_string(options.max_restarts) +
                      " restarts: " + std::to_string(iparam[4]) + " of " + std::to_string(count) +
                      " eigenpairs converged (raise max_restarts or "
                      "tolerance)");
  }
  if (info != 0) throw SolverError("ARPACK dsaupd failed with info = " + std::to_string(info));

  std::vector<int> select(static_cast<std::size_t>(ncv));
  Eigenpairs result;
  result.solves = solves;
  Eigen::VectorXd values(count);
  Eigen::MatrixXd vectors(n, count);
  detail::thread_limited([&]() noexcept {
    dseupd_c(1, "A", select.data(), values.data(), vectors.data(), n, problem.shift(), "G", n, "LM",
             count, options.tolerance, resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(),
             workl.data(), lworkl, &info);
  });
  if (info != 0) throw SolverError("ARPACK dseupd failed with info = " + std::to_string(info));
  progress.finish();

  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values(a) < values(b); });
  result.values.resize(count);
  result.vectors.resize(n, count);
  for (int c = 0; c < count; ++c) {
    result.values(c) = values(order[static_cast<std::size_t>(c)]);
    result.vectors.col(c) = vectors.col(order[static_cast<std::size_t>(c)]);
  }
  return result;
}

// Checks that the lowest `rigid_count` eigenpairs are the rigid motions (§2.8.7): eigenvalue
// ≈ 0 next to the first deformation mode, and the eigenvector inside the span of the analytic
// rigid fields.
void require_rigid(const Eigenpairs& pairs, Eigen::Index rigid_count, const VolumeMesh& mesh,
                   const SparseMatrix& mass) {
  const double first_deformation = pairs.values(rigid_count);
  for (Eigen::Index i = 0; i < rigid_count; ++i) {
    if (!(std::abs(pairs.values(i)) <= 1e-6 * first_deformation)) {
      throw SolverError("expected " + std::to_string(rigid_count) +
                        " rigid modes (6 per connected part) but eigenvalue " + std::to_string(i) +
                        " is " + std::to_string(pairs.values(i)) + ", not ≈ 0 next to " +
                        std::to_string(first_deformation));
    }
  }
  // M-orthonormal basis of the rigid fields: R (RᵀMR)^{-1/2} via Cholesky.
  const Eigen::MatrixXd rigid = detail::rigid_motions(mesh);
  const Eigen::MatrixXd gram = rigid.transpose() * (mass * rigid);
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  const Eigen::MatrixXd orthonormal =
      llt.matrixU().solve<Eigen::OnTheRight>(rigid);  // R U⁻¹, UᵀU = RᵀMR
  for (Eigen::Index i = 0; i < rigid_count; ++i) {
    const Eigen::VectorXd mode = pairs.vectors.col(i);
    const Eigen::VectorXd outside = mode - orthonormal * (orthonormal.transpose() * (mass * mode));
    const double residual = std::sqrt(outside.dot(mass * outside));  // ‖mode‖_M = 1
    if (!(residual <= 1e-6)) {
      throw SolverError("mode " + std::to_string(i) + " has eigenvalue ≈ 0 but is not a rigid " +
                        "motion (M-norm distance " + std::to_string(residual) + ")");
    }
  }
}

}  // namespace

Eigen::VectorXd LinearModes::frequencies_hz() const {
  return eigenvalues.cwiseMax(0.0).cwiseSqrt() / (2.0 * std::numbers::pi);
}

LinearModes compute_linear_modes(const FemModel& model, std::span<const int> fixed_vertices,
                                 const LinearModesOptions& options) {
  check_options(options);
  const detail::ModalProblem problem(model, fixed_vertices, options.mass);
  const Eigen::Index rigid_count =
      problem.unconstrained() ? 6 * detail::count_components(model.mesh()) : 0;
  const Eigen::Index count = options.num_modes + rigid_count;
  if (count >= problem.dofs().num_free_dofs()) {
    throw Error(std::to_string(options.num_modes) + " modes" +
                (rigid_count > 0 ? " plus " + std::to_string(rigid_count) + " rigid modes" : "") +
                " need more than the " + std::to_string(problem.dofs().num_free_dofs()) +
                " free dofs of the mesh" +
                (problem.dofs().num_free_dofs() == 0 ? " (every vertex is fixed)" : ""));
  }
  const Eigenpairs pairs = lowest_eigenpairs(problem, static_cast<int>(count), options);
  if (rigid_count > 0) require_rigid(pairs, rigid_count, model.mesh(), problem.mass());

  LinearModes result;
  result.fixed_vertices = problem.fixed_vertices();
  result.mass = options.mass;
  result.solves = pairs.solves;
  result.eigenvalues = pairs.values.tail(options.num_modes);
  result.modes = problem.dofs().expand_rows(pairs.vectors.rightCols(options.num_modes));
  result.rigid_eigenvalues = pairs.values.head(rigid_count);
  result.rigid_modes = problem.dofs().expand_rows(pairs.vectors.leftCols(rigid_count));
  return result;
}

}  // namespace khz::reduced
