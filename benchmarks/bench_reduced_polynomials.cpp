// Reduced internal forces from the energy polynomial (PolynomialForces, thesis §2.6.4) on random
// quartic energies for r = 5 … 60, one thread: K̃ and R̃ together (evaluate), R̃ alone
// (evaluate_forces), and one implicit Newmark Newton iteration (newton_step: evaluate, then
// A = α₁ I + K̃ and a dense LLT solve, both in preallocated storage). `streaming_limit` compares
// evaluate() with a BLAS dgemv over a matrix of as many bytes as the coefficients (the
// memory-streaming limit at that size) and with dgemv over an L1-resident matrix repeated to stream
// as many bytes (the arithmetic limit): evaluate_per_dgemv near 1 means evaluate() runs at the
// speed of memory.
#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/test/random_polynomial.hpp>

#include <benchmark/benchmark.h>
#include <dlfcn.h>
#include <Eigen/Cholesky>
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

void newton_step(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  const Eigen::Index r = f.model.dimension();
  // A = α₁ I + K̃ is formed where evaluate() writes K̃ and factored in place, as an integrator
  // with a preallocated system matrix would.
  Eigen::MatrixXd system = Eigen::MatrixXd::Identity(r, r);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(system);
  Eigen::VectorXd step(r);
  for (auto _ : state) {
    f.model.evaluate(f.q, f.forces, system);
    system.diagonal().array() += kNewmarkAlpha1;
    llt.compute(system);
    step = llt.solve(f.forces);
    benchmark::DoNotOptimize(step.data());
  }
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

void streaming_limit(benchmark::State& state) {
  Fixture& f = fixture(state.range(0));
  f.set_up(state);
  const auto doubles = static_cast<int>(f.model.coefficient_bytes() / sizeof(double));
  const int rows = std::min(256, doubles);
  Gemv same_bytes(rows, (doubles + rows - 1) / rows);
  // 24 KB, half of L1d, repeated to stream as many bytes as the coefficients.
  Gemv cached(64, 48);
  const int cached_repeats = std::max(1, doubles / (64 * 48));
  const int repeats = std::max(1, 20'000'000 / std::max(doubles, 1) / 8);
  const double evaluate_us =
      best_time_us([&] { f.model.evaluate(f.q, f.forces, f.stiffness); }, repeats);
  const double dgemv_us = best_time_us(same_bytes, repeats);
  const double cached_us = best_time_us(cached, repeats * cached_repeats) * cached_repeats;
  for (auto _ : state) {
    f.model.evaluate(f.q, f.forces, f.stiffness);
    benchmark::DoNotOptimize(f.stiffness.data());
  }
  state.counters["evaluate_us"] = evaluate_us;
  state.counters["dgemv_us"] = dgemv_us;
  state.counters["dgemv_l1_us"] = cached_us;
  state.counters["evaluate_per_dgemv"] = evaluate_us / dgemv_us;
  state.counters["evaluate_per_dgemv_l1"] = evaluate_us / cached_us;
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
