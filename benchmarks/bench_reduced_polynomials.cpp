// Reduced internal forces from the energy polynomial (PolynomialForces, thesis §2.6.4) on random
// quartic energies for r = 5 … 60, one thread: K̃ and R̃ together (evaluate), R̃ alone
// (evaluate_forces), and one implicit Newmark Newton iteration (newton_step: evaluate, then
// A = α₁ I + K̃ and the reduced integrators' own dense solve, DenseSymmetricSolver, all in
// preallocated storage). `streaming_limit` compares evaluate() and the Newton iteration, in the
// same process, with a BLAS dgemv over a matrix of as many bytes as the coefficients (the
// memory-streaming limit at that size), with dgemv over an L1-resident matrix repeated to stream
// as many bytes (the arithmetic limit), and with a loop that streams as many bytes doing three FMAs
// per eight doubles (fma_floor: the least arithmetic a Hessian needs per coefficient, see
// quartic_tile_kernels.cpp). evaluate_per_dgemv near 1 means evaluate() runs at the speed of
// memory; fma_floor_per_dgemv is how near this CPU lets it come (issue 23, item 3).
#include "subspace/dense_symmetric_solve.hpp"
#include "subspace/simd_lanes.hpp"

#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/test/random_polynomial.hpp>

#include <benchmark/benchmark.h>
#include <dlfcn.h>
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

// BLAS's Fortran interface (OpenBLAS on Debian, through LAPACK::LAPACK), 32-bit integers.
extern "C" {
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy);
}

namespace {

namespace kr = khz::reduced;

constexpr double kNewmarkAlpha1 = 1e4;  // α₁ = 1/(β Δt²) + …: a 1 kHz step's diagonal shift.

/// Single-threaded BLAS: OpenBLAS's thread count, if it is the BLAS in use (found at run time,
/// so that any BLAS links).
void pin_blas_to_one_thread() {
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) {
    set(1);
  }
  Eigen::setNbThreads(1);
}

/// One model, reduced coordinates and outputs per r.
struct Fixture {
  explicit Fixture(Eigen::Index r)
      : polynomial(khz::test::random_polynomial(r, static_cast<unsigned>(r))),
        model(polynomial),
        q(0.5 * Eigen::VectorXd::Random(r)),
        forces(r),
        stiffness(r, r) {}

  void set_up(benchmark::State& state) const {
    pin_blas_to_one_thread();
    const double canonical =
        static_cast<double>(sizeof(double)) *
        static_cast<double>(polynomial.quadratic.size() + polynomial.cubic.size() +
                            polynomial.quartic.size());
    state.counters["r"] = static_cast<double>(model.dimension());
    state.counters["coefficient_bytes"] = static_cast<double>(model.coefficient_bytes());
    state.counters["canonical_bytes"] = canonical;
  }

  kr::EnergyPolynomial polynomial;
  kr::PolynomialForces model;
  Eigen::VectorXd q;
  Eigen::VectorXd forces;
  Eigen::MatrixXd stiffness;
};

Fixture& fixture(Eigen::Index r) {
  static std::vector<std::unique_ptr<Fixture>> fixtures;
  for (const auto& f : fixtures) {
    if (f->model.dimension() == r) return *f;
  }
  return *fixtures.emplace_back(std::make_unique<Fixture>(r));
}

void evaluate(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  for (auto _ : state) {
    f.model.evaluate(f.q, f.forces, f.stiffness);
    benchmark::DoNotOptimize(f.stiffness.data());
    benchmark::DoNotOptimize(f.forces.data());
  }
  state.SetBytesProcessed(state.iterations() *
                          static_cast<std::int64_t>(f.model.coefficient_bytes()));
}

void evaluate_forces(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  for (auto _ : state) {
    f.model.evaluate_forces(f.q, f.forces);
    benchmark::DoNotOptimize(f.forces.data());
  }
  state.SetBytesProcessed(state.iterations() *
                          static_cast<std::int64_t>(f.model.coefficient_bytes()));
}

/// One Newton iteration of the reduced implicit Newmark step: R̃ and K̃, A = α₁ I + K̃ formed
/// where evaluate() writes K̃, and A x = R̃ solved by the integrators' solver.
struct NewtonStep {
  explicit NewtonStep(Fixture& fixture)
      : f(fixture),
        system(f.model.dimension(), f.model.dimension()),
        solver(f.model.dimension()),
        step(f.model.dimension()) {}
  void operator()() {
    f.model.evaluate(f.q, step, system);
    system.diagonal().array() += kNewmarkAlpha1;
    solver.solve_in_place(system, step);
    benchmark::DoNotOptimize(step.data());
  }
  Fixture& f;
  Eigen::MatrixXd system;
  kr::detail::DenseSymmetricSolver solver;
  Eigen::VectorXd step;
};

void newton_step(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  NewtonStep newton(f);
  for (auto _ : state) newton();
}

/// Shortest mean time of `repeats` calls over several rounds, in µs.
template <typename Call>
double best_time_us(Call&& call, int repeats) {
  double best = 1e300;
  for (int round = 0; round < 9; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < repeats; ++k) call();
    const std::chrono::duration<double, std::micro> elapsed =
        std::chrono::steady_clock::now() - start;
    best = std::min(best, elapsed.count() / repeats);
  }
  return best;
}

/// y = Aᵀx for a column-major rows × columns A (dot products down the columns: the form in
/// which OpenBLAS streams a matrix fastest).
struct Gemv {
  Gemv(int rows, int columns)
      : m(rows),
        n(columns),
        a(Eigen::MatrixXd::Random(rows, columns)),
        x(Eigen::VectorXd::Random(rows)),
        y(columns) {}
  void operator()() {
    const char trans = 'T';
    const double one = 1.0, zero = 0.0;
    const int increment = 1;
    dgemv_(&trans, &m, &n, &one, a.data(), &m, x.data(), &increment, &zero, y.data(), &increment);
    benchmark::DoNotOptimize(y.data());
  }
  int m, n;
  Eigen::MatrixXd a;
  Eigen::VectorXd x, y;
};

/// Streams `doubles` doubles (rounded up to a multiple of 32) doing three independent FMAs on
/// each vector of eight, in the kernels' own lanes and in four chains so that latency does not
/// bound it: the Hessian kernel's arithmetic without its bookkeeping.
struct FmaFloor {
  // Aligned like the coefficients (Eigen aligns to the widest vector).
  explicit FmaFloor(int doubles) : data(Eigen::VectorXd::Constant((doubles + 31) / 32 * 32, 0.5)) {}
  void operator()() {
    namespace d = kr::detail;
    d::Lanes sums[4][3];
    for (auto& chain : sums) {
      for (d::Lanes& s : chain) s = d::zero_lanes();
    }
    const d::Lanes w[3] = {d::broadcast(1.1), d::broadcast(0.9), d::broadcast(1.3)};
    for (Eigen::Index i = 0; i < data.size(); i += 32) {
      for (int chain = 0; chain < 4; ++chain) {
        const d::Lanes x = d::load(&data[i + 8 * chain]);
        for (int k = 0; k < 3; ++k) sums[chain][k] = d::fma(x, w[k], sums[chain][k]);
      }
    }
    benchmark::DoNotOptimize(sums);
  }
  Eigen::VectorXd data;
};

void streaming_limit(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  const auto doubles = static_cast<int>(f.model.coefficient_bytes() / sizeof(double));
  const int rows = std::min(256, doubles);
  Gemv same_bytes(rows, (doubles + rows - 1) / rows);
  // 24 KB, half of L1d, repeated to stream as many bytes as the coefficients.
  Gemv cached(64, 48);
  FmaFloor fma_floor(doubles);
  NewtonStep newton(f);
  const int cached_repeats = std::max(1, doubles / (64 * 48));
  const int repeats = std::max(1, 20'000'000 / std::max(doubles, 1) / 8);
  const double evaluate_us =
      best_time_us([&] { f.model.evaluate(f.q, f.forces, f.stiffness); }, repeats);
  const double newton_us = best_time_us(newton, repeats);
  const double dgemv_us = best_time_us(same_bytes, repeats);
  const double cached_us = best_time_us(cached, repeats * cached_repeats) * cached_repeats;
  const double fma_floor_us = best_time_us(fma_floor, repeats);
  for (auto _ : state) {
    f.model.evaluate(f.q, f.forces, f.stiffness);
    benchmark::DoNotOptimize(f.stiffness.data());
  }
  state.counters["evaluate_us"] = evaluate_us;
  state.counters["newton_us"] = newton_us;
  state.counters["dgemv_us"] = dgemv_us;
  state.counters["dgemv_l1_us"] = cached_us;
  state.counters["fma_floor_us"] = fma_floor_us;
  state.counters["evaluate_per_dgemv"] = evaluate_us / dgemv_us;
  state.counters["evaluate_per_dgemv_l1"] = evaluate_us / cached_us;
  state.counters["newton_per_dgemv"] = newton_us / dgemv_us;
  state.counters["fma_floor_per_dgemv"] = fma_floor_us / dgemv_us;
}

void dimensions(benchmark::internal::Benchmark* benchmark) {
  for (const int r : {5, 10, 15, 20, 30, 45, 60}) benchmark->Arg(r);
  benchmark->Unit(benchmark::kMicrosecond);
}

BENCHMARK(evaluate)->Apply(dimensions);
BENCHMARK(evaluate_forces)->Apply(dimensions);
BENCHMARK(newton_step)->Apply(dimensions);
BENCHMARK(streaming_limit)->Apply(dimensions);

}  // namespace
