#include <khz/mpi/mumps_factorization.hpp>

#include "mpi_error.hpp"

#include <khz/reduced/errors.hpp>

#include <dmumps_c.h>

#include <string>
#include <vector>

namespace khz::mpi {
namespace {

static_assert(sizeof(MUMPS_INT) == sizeof(int),
              "MUMPS built with 32-bit integers, sent as MPI_INT");

// MUMPS's job codes and the ICNTL fields set here (1-based in its manual).
constexpr MUMPS_INT job_initialize = -1, job_terminate = -2, job_analyse_and_factorize = 4,
                    job_solve = 3;
constexpr int icntl_error_stream = 1, icntl_diagnostic_stream = 2, icntl_global_stream = 3,
              icntl_print_level = 4, icntl_null_pivot_detection = 24, cntl_null_pivot_threshold = 3,
              infog_null_pivots = 28;

}  // namespace

struct MumpsFactorization::Mumps {
  DMUMPS_STRUC_C id{};
  MPI_Comm communicator = MPI_COMM_NULL;
  int rank = 0;
  MUMPS_INT n = 0;
  // Rank 0's matrix in coordinates, 1-based, lower triangle: MUMPS keeps pointers to them.
  std::vector<MUMPS_INT> rows, columns;
  std::vector<double> values;

  void run(MUMPS_INT job, const char* what) {
    id.job = job;
    dmumps_c(&id);
    if (id.infog[0] < 0) {
      throw reduced::SolverError("MUMPS " + std::string(what) +
                                 " failed: INFOG(1) = " + std::to_string(id.infog[0]) +
                                 ", INFOG(2) = " + std::to_string(id.infog[1]) +
                                 (id.infog[0] == -10 ? " (the matrix is numerically singular)"
                                  : id.infog[0] == -9 || id.infog[0] == -13 ? " (not enough memory)"
                                                                            : ""));
    }
  }
};

MumpsFactorization::MumpsFactorization(const reduced::SparseMatrix& a, MPI_Comm communicator)
    : m_mumps(std::make_unique<Mumps>()) {
  Mumps& m = *m_mumps;
  detail::check(MPI_Comm_dup(communicator, &m.communicator), "MPI_Comm_dup");
  detail::check(MPI_Comm_rank(m.communicator, &m.rank), "MPI_Comm_rank");
  m.id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(m.communicator));
  m.id.par = 1;  // rank 0 works too
  m.id.sym = 2;  // symmetric (LDLᵀ with pivoting: the null-pivot detection works there)
  m.run(job_initialize, "initialization");
  for (const int field : {icntl_error_stream, icntl_diagnostic_stream, icntl_global_stream}) {
    m.id.icntl[field - 1] = -1;  // silent: errors come back as SolverError
  }
  m.id.icntl[icntl_print_level - 1] = 0;
  // A singular matrix (e.g. K with a rigid motion left free) never gives an exactly zero pivot
  // in floating point: count pivots below n·ε·‖A‖ as null, as SparseCholesky rejects a pivot
  // ratio below n·ε, and refuse the factorization if there are any.
  m.id.icntl[icntl_null_pivot_detection - 1] = 1;
  const auto end_instance = [&m] {
    m.id.job = job_terminate;
    dmumps_c(&m.id);
    MPI_Comm_free(&m.communicator);
  };
  m.n = m.rank == 0 && a.rows() == a.cols() ? static_cast<MUMPS_INT>(a.rows()) : -1;
  detail::check(MPI_Bcast(&m.n, 1, MPI_INT, 0, m.communicator), "MPI_Bcast");
  if (m.n < 0) {  // on every rank, so that none waits in MUMPS for the others
    end_instance();
    throw reduced::Error("MumpsFactorization: rank 0's matrix is not square");
  }
  if (m.rank == 0) {
    for (Eigen::Index column = 0; column < a.outerSize(); ++column) {
      for (reduced::SparseMatrix::InnerIterator it(a, column); it; ++it) {
        if (it.row() < column) continue;
        m.rows.push_back(static_cast<MUMPS_INT>(it.row() + 1));
        m.columns.push_back(static_cast<MUMPS_INT>(column + 1));
        m.values.push_back(it.value());
      }
    }
    m.id.n = m.n;
    m.id.nnz = static_cast<MUMPS_INT8>(m.values.size());
    m.id.irn = m.rows.data();
    m.id.jcn = m.columns.data();
    m.id.a = m.values.data();
  }
  m.id.cntl[cntl_null_pivot_threshold - 1] = static_cast<double>(m.n) * 2.2e-16;
  try {
    m.run(job_analyse_and_factorize, "factorization");
    if (m.id.infog[infog_null_pivots - 1] > 0) {
      throw reduced::SolverError("MUMPS factorization: the matrix is singular (" +
                                 std::to_string(m.id.infog[infog_null_pivots - 1]) +
                                 " null pivots; INFOG(28))");
    }
  } catch (...) {
    end_instance();
    throw;
  }
}

MumpsFactorization::~MumpsFactorization() {
  m_mumps->id.job = job_terminate;
  dmumps_c(&m_mumps->id);
  MPI_Comm_free(&m_mumps->communicator);
}

Eigen::MatrixXd MumpsFactorization::solve(const Eigen::MatrixXd& rhs) {
  Mumps& m = *m_mumps;
  long columns = m.rank == 0 ? static_cast<long>(rhs.cols()) : 0;
  int rows_fit = m.rank != 0 || rhs.rows() == m.n ? 1 : 0;
  detail::check(MPI_Bcast(&rows_fit, 1, MPI_INT, 0, m.communicator), "MPI_Bcast");
  if (!rows_fit) {
    throw reduced::Error("MumpsFactorization::solve: the right-hand sides have " +
                         std::to_string(rhs.rows()) + " rows on rank 0, the matrix " +
                         std::to_string(m.n));
  }
  detail::check(MPI_Bcast(&columns, 1, MPI_LONG, 0, m.communicator), "MPI_Bcast");
  Eigen::MatrixXd solution(m.n, columns);
  if (columns == 0) return solution;
  if (m.rank == 0) {
    solution = rhs;  // MUMPS overwrites the right-hand sides with the solution
    m.id.rhs = solution.data();
    m.id.nrhs = static_cast<MUMPS_INT>(columns);
    m.id.lrhs = m.n;
  }
  m.run(job_solve, "solve");
  detail::check(
      MPI_Bcast(solution.data(), static_cast<int>(solution.size()), MPI_DOUBLE, 0, m.communicator),
      "MPI_Bcast");
  return solution;
}

reduced::Factorize MumpsFactorization::factorize(MPI_Comm communicator) {
  return [communicator](const reduced::SparseMatrix& a) {
    return std::make_unique<MumpsFactorization>(a, communicator);
  };
}

}  // namespace khz::mpi
