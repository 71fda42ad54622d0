// Large deformations in a modal-derivative basis vs linear modes (thesis Fig. 2.14): a
// 1 m × 0.1 m × 0.08 m rubber beam (E = 1 MPa, ν = 0.3) of 20 × 2 × 2 hexahedra, clamped at
// x = 0, twisted by ~270° with a follower torque at the tip and bent by a dead tip load with
// PL²/EI = 10 (~80°; a dead load bends the tip to 90° only in the limit P → ∞). The full nonlinear
// static solution is the reference; the same static problem restricted to u = U q is solved in
//   derivative: span{Ψa, Ψb, Φaa, Φab, Φbb} of the two lowest modes of the deformation's kind
//               (torsion, or bending along z),
//   linear:     the five lowest linear modes of that kind (same size r = 5).
// Counters: tip rotation (degrees) of each solution and the relative mass-norm error
// ‖u_reduced − u_full‖_M / ‖u_full‖_M. The light versions (8 cells, ~90° twist, 45° bend) are
// tests in tests/reduced/test_modal_derivative_basis.cpp; both share the beam, loads, solvers
// and bases of tests/support/khz/test/large_deformation.hpp. This one takes about a minute in a
// Debug build (0.6 s in Release). Measured:
//   twist: full 271.1°; derivative basis 211.4°, error 0.23; linear basis 13.0°, error 1.01
//   bend:  full 79.3°;  derivative basis 76.7°,  error 0.047; linear basis 8.1°, error 0.88
// The linear bases lock (a turning fibre cannot shorten its radius, a bent axis cannot shorten);
// the derivative basis follows the full model far into the nonlinear range, as in Fig. 2.14.
#include <khz/test/large_deformation.hpp>

#include <benchmark/benchmark.h>

#include <string>

namespace {

namespace kt = khz::test;

void report(benchmark::State& state, const kt::LargeBeam& beam, const kt::Comparison& run,
            bool twist) {
  if (const std::string failure = run.failure(); !failure.empty()) {
    state.SkipWithError(failure.c_str());
  }
  auto angle = [&](const kt::Path& path) {
    return (twist ? path.twist : kt::tip_bend(beam, path.displacement)) * kt::degrees;
  };
  state.counters["full_deg"] = angle(run.full);
  state.counters["derivative_deg"] = angle(run.derivative);
  state.counters["derivative_error"] = run.derivative_error;
  state.counters["linear_deg"] = angle(run.linear);
  state.counters["linear_error"] = run.linear_error;
  state.counters["newton_full"] = run.full.iterations;
}

void BM_Twist270Degrees(benchmark::State& state) {
  const kt::LargeBeam beam(20);
  const kt::BasisPair bases = kt::large_deformation_bases(beam, true);
  if (bases.derivative.cols() != 5) {
    state.SkipWithError("fewer than 5 torsion modes among the lowest 30");
    return;
  }
  const kt::Load load = kt::follower_torque(beam, 19.0);  // N·m; tuned: the full model turns 271°
  const int steps = 27;                                   // 10° per step
  for (auto _ : state) report(state, beam, kt::compare_solves(beam, load, bases, steps), true);
}

// The dead load's reference is the library's solve_static in as many load steps.
void BM_BendPL2OverEI10(benchmark::State& state) {
  const kt::LargeBeam beam(20);
  const kt::BasisPair bases = kt::large_deformation_bases(beam, false);
  if (bases.derivative.cols() != 5) {
    state.SkipWithError("fewer than 5 z-bending modes among the lowest 30");
    return;
  }
  const kt::Load load = kt::dead_tip_bend(beam, 10.0);
  const int steps = 20;
  for (auto _ : state) report(state, beam, kt::compare_solves(beam, load, bases, steps), false);
}

BENCHMARK(BM_Twist270Degrees)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_BendPL2OverEI10)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
