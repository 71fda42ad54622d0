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
// tests in tests/reduced/test_modal_derivative_basis.cpp; this one takes about a minute in a
// Debug build (0.6 s in Release). Measured:
//   twist: full 271.1°; derivative basis 211.4°, error 0.23; linear basis 13.0°, error 1.01
//   bend:  full 79.3°;  derivative basis 76.7°,  error 0.047; linear basis 8.1°, error 0.88
// The linear bases lock (a turning fibre cannot shorten its radius, a bent axis cannot shorten);
// the derivative basis follows the full model far into the nonlinear range, as in Fig. 2.14.
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace kr = khz::reduced;

constexpr double degrees = 180.0 / std::numbers::pi;
constexpr double young = 1e6;

struct Beam {
  static constexpr double length = 1.0, width = 0.1, height = 0.08, tolerance = 1e-9;
  explicit Beam(int cells_along) : cells(cells_along) {}
  int cells;
  kr::FemModel model{kr::box_hex_mesh({0, 0, 0}, {length, width, height}, {cells, 2, 2}),
                     {kr::Material::stvk(young, 0.3, 1000.0)}};
  std::vector<int> clamped = face(0.0);
  std::vector<int> tip = face(length);
  kr::SparseMatrix mass = model.mass_matrix();
  kr::FixedDofs dofs{model.mesh().num_vertices(), clamped};

  std::vector<int> face(double x) const {
    return kr::vertices_in_box(
        model.mesh().vertices,
        Eigen::AlignedBox3d(Eigen::Vector3d(x - 1e-9, -1, -1), Eigen::Vector3d(x + 1e-9, 1, 1)));
  }
  Eigen::Vector3d rest(int v) const { return model.mesh().vertices.row(v).transpose(); }
  Eigen::Vector2d centre() const { return {width / 2, height / 2}; }
};

/// f(u) = dead + follower · u.
struct Load {
  Eigen::VectorXd dead;
  kr::SparseMatrix follower;
};

/// τ e_x × (x_v − c) at every tip vertex, x_v the current position: a pure torque about the
/// axis whatever the tip's rotation.
Load follower_torque(const Beam& beam, double torque) {
  double polar = 0.0;
  for (int v : beam.tip) polar += (beam.rest(v).tail<2>() - beam.centre()).squaredNorm();
  const double tau = torque / polar;
  Load load;
  load.dead = Eigen::VectorXd::Zero(beam.model.num_dofs());
  std::vector<Eigen::Triplet<double>> entries;
  for (int v : beam.tip) {
    const Eigen::Vector2d r = beam.rest(v).tail<2>() - beam.centre();
    load.dead[3 * v + 1] = -tau * r.y();
    load.dead[3 * v + 2] = tau * r.x();
    entries.emplace_back(3 * v + 1, 3 * v + 2, -tau);
    entries.emplace_back(3 * v + 2, 3 * v + 1, tau);
  }
  load.follower.resize(beam.model.num_dofs(), beam.model.num_dofs());
  load.follower.setFromTriplets(entries.begin(), entries.end());
  return load;
}

double tip_twist(const Beam& beam, const Eigen::VectorXd& u, double previous) {
  double sum = 0.0;
  int count = 0;
  for (int v : beam.tip) {
    const Eigen::Vector2d r = beam.rest(v).tail<2>() - beam.centre();
    if (r.norm() < 1e-9) continue;
    const Eigen::Vector2d now = r + u.segment<2>(3 * v + 1);
    const double angle = std::atan2(r.x() * now.y() - r.y() * now.x(), r.dot(now));
    sum += previous + std::remainder(angle - previous, 2 * std::numbers::pi);
    ++count;
  }
  return sum / count;
}

double tip_bend(const Beam& beam, const Eigen::VectorXd& u) {
  int bottom = -1, top = -1;
  for (int v : beam.tip) {
    const Eigen::Vector3d x = beam.rest(v);
    if (std::abs(x.y()) < 1e-9 && std::abs(x.z()) < 1e-9) bottom = v;
    if (std::abs(x.y()) < 1e-9 && std::abs(x.z() - beam.height) < 1e-9) top = v;
  }
  const Eigen::Vector3d edge =
      beam.rest(top) + u.segment<3>(3 * top) - beam.rest(bottom) - u.segment<3>(3 * bottom);
  return std::atan2(edge.x(), edge.z());
}

struct Path {
  Eigen::VectorXd displacement;
  double twist = 0.0;
  int iterations = 0;
  std::string failure;
};

/// Newton with load steps, no line search (backtracking on ‖R − f‖ stalls on this beam: the
/// first iterate of a step stretches the turning fibres). basis == nullopt: the full problem on
/// the free dofs (SparseLU: the follower tangent is not symmetric); otherwise u = U q.
Path newton(const Beam& beam, const Load& load, const std::optional<Eigen::MatrixXd>& basis,
            int steps) {
  const kr::FemModel& model = beam.model;
  Path path;
  path.displacement = Eigen::VectorXd::Zero(model.num_dofs());
  Eigen::VectorXd q = basis ? Eigen::VectorXd::Zero(basis->cols()) : Eigen::VectorXd();
  kr::SparseMatrix stiffness = model.stiffness_pattern();
  Eigen::VectorXd forces;
  Eigen::VectorXd& u = path.displacement;
  for (int step = 1; step <= steps; ++step) {
    const double s = static_cast<double>(step) / steps;
    for (int iteration = 0;; ++iteration) {
      if (basis) u = *basis * q;
      model.forces_and_stiffness(u, forces, stiffness);
      const Eigen::VectorXd full_residual = forces - s * (load.dead + load.follower * u);
      if (basis) {
        const Eigen::VectorXd r = basis->transpose() * full_residual;
        if (r.norm() <= beam.tolerance * s * (basis->transpose() * load.dead).norm()) break;
        if (iteration == 30) {
          path.failure = "reduced Newton: no convergence at step " + std::to_string(step);
          return path;
        }
        const Eigen::MatrixXd jacobian = basis->transpose() * (stiffness * *basis) -
                                         s * (basis->transpose() * (load.follower * *basis));
        q += jacobian.partialPivLu().solve(-r);
      } else {
        const Eigen::VectorXd r = beam.dofs.restrict_vector(full_residual);
        if (r.norm() <= beam.tolerance * beam.dofs.restrict_vector(s * load.dead).norm()) break;
        if (iteration == 30) {
          path.failure = "full Newton: no convergence at step " + std::to_string(step);
          return path;
        }
        const kr::SparseMatrix jacobian =
            beam.dofs.restrict_matrix(stiffness) - s * beam.dofs.restrict_matrix(load.follower);
        const Eigen::SparseLU<kr::SparseMatrix> lu(jacobian);
        Eigen::VectorXd du;
        beam.dofs.expand_vector(lu.solve(-r), du);
        u += du;
      }
      ++path.iterations;
    }
    path.twist = tip_twist(beam, u, path.twist);
  }
  return path;
}

/// Whether mode ψ is mostly section-wise rotation about the axis (torsion) or section-wise
/// deflection along z (bending): share of its lumped kinetic energy above ½.
bool is_kind(const Beam& beam, const Eigen::VectorXd& psi, bool torsion) {
  const kr::SparseMatrix lumped = beam.model.mass_matrix(kr::MassLumping::lumped);
  std::vector<double> mass(beam.cells + 1, 0.0), deflection(beam.cells + 1, 0.0),
      moment(beam.cells + 1, 0.0), inertia(beam.cells + 1, 0.0);
  double total = 0.0;
  for (int v = 0; v < beam.model.mesh().num_vertices(); ++v) {
    const Eigen::Vector3d x = beam.rest(v);
    const auto s = static_cast<std::size_t>(std::lround(x.x() / (beam.length / beam.cells)));
    const double m = lumped.coeff(3 * v, 3 * v);
    const Eigen::Vector2d r = x.tail<2>() - beam.centre();
    mass[s] += m;
    deflection[s] += m * psi[3 * v + 2];
    moment[s] += m * (-r.y() * psi[3 * v + 1] + r.x() * psi[3 * v + 2]);
    inertia[s] += m * r.squaredNorm();
    total += m * psi.segment<3>(3 * v).squaredNorm();
  }
  double share = 0.0;
  for (std::size_t s = 0; s < mass.size(); ++s) {
    if (torsion && inertia[s] > 0) share += moment[s] * moment[s] / inertia[s];
    if (!torsion) share += deflection[s] * deflection[s] / mass[s];
  }
  return share / total > 0.5;
}

struct Bases {
  Eigen::MatrixXd derivative, linear;
};

Bases make_bases(const Beam& beam, bool torsion) {
  kr::LinearModesOptions options;
  options.num_modes = 30;
  const kr::LinearModes modes = kr::compute_linear_modes(beam.model, beam.clamped, options);
  std::vector<int> kind;
  for (int i = 0; i < modes.modes.cols(); ++i) {
    if (is_kind(beam, modes.modes.col(i), torsion)) kind.push_back(i);
  }
  if (kind.size() < 5) return {};
  kr::LinearModes chosen;
  // Not from a Vector2d temporary: that trips GCC 12's -Warray-bounds with AVX-512.
  chosen.eigenvalues.resize(2);
  chosen.eigenvalues << modes.eigenvalues[kind[0]], modes.eigenvalues[kind[1]];
  chosen.modes.resize(modes.modes.rows(), 2);
  chosen.modes << modes.modes.col(kind[0]), modes.modes.col(kind[1]);
  chosen.fixed_vertices = modes.fixed_vertices;
  const kr::ModalDerivatives derivatives = kr::compute_modal_derivatives(beam.model, chosen);
  Eigen::MatrixXd vectors(modes.modes.rows(), 5);
  vectors << chosen.modes, derivatives.vectors;
  kr::PcaOptions pca;
  pca.basis_size = 5;
  Bases bases;
  bases.derivative = kr::principal_components(vectors, beam.mass, pca).basis;
  for (int c = 0; c < 5; ++c) vectors.col(c) = modes.modes.col(kind[c]);
  bases.linear = kr::principal_components(vectors, beam.mass, pca).basis;
  return bases;
}

double mass_error(const Beam& beam, const Eigen::VectorXd& value, const Eigen::VectorXd& full) {
  const Eigen::VectorXd difference = value - full;
  return std::sqrt(difference.dot(beam.mass * difference) / full.dot(beam.mass * full));
}

void report(benchmark::State& state, const Beam& beam, const Path& full, const Path& derivative,
            const Path& linear, bool twist) {
  for (const Path* path : {&full, &derivative, &linear}) {
    if (!path->failure.empty()) state.SkipWithError(path->failure.c_str());
  }
  auto angle = [&](const Path& path) {
    return (twist ? path.twist : tip_bend(beam, path.displacement)) * degrees;
  };
  state.counters["full_deg"] = angle(full);
  state.counters["derivative_deg"] = angle(derivative);
  state.counters["derivative_error"] = mass_error(beam, derivative.displacement, full.displacement);
  state.counters["linear_deg"] = angle(linear);
  state.counters["linear_error"] = mass_error(beam, linear.displacement, full.displacement);
  state.counters["newton_full"] = full.iterations;
}

void BM_Twist270Degrees(benchmark::State& state) {
  const Beam beam(20);
  const Bases bases = make_bases(beam, true);
  if (bases.derivative.cols() != 5) {
    state.SkipWithError("fewer than 5 torsion modes among the lowest 30");
    return;
  }
  const Load load = follower_torque(beam, 19.0);  // N·m; tuned: the full model turns 271°
  const int steps = 27;                           // 10° per step
  for (auto _ : state) {
    const Path full = newton(beam, load, std::nullopt, steps);
    const Path derivative = newton(beam, load, bases.derivative, steps);
    const Path linear = newton(beam, load, bases.linear, steps);
    report(state, beam, full, derivative, linear, true);
  }
}

void BM_BendPL2OverEI10(benchmark::State& state) {
  const Beam beam(20);
  const Bases bases = make_bases(beam, false);
  if (bases.derivative.cols() != 5) {
    state.SkipWithError("fewer than 5 z-bending modes among the lowest 30");
    return;
  }
  const double bending_stiffness = young * beam.width * std::pow(beam.height, 3) / 12.0;
  Load load;
  load.dead = Eigen::VectorXd::Zero(beam.model.num_dofs());
  for (int v : beam.tip) {
    load.dead[3 * v + 2] = -10.0 * bending_stiffness / static_cast<double>(beam.tip.size());
  }
  load.follower.resize(beam.model.num_dofs(), beam.model.num_dofs());
  const int steps = 20;
  for (auto _ : state) {
    kr::StaticSolveOptions options;
    options.load_steps = steps;
    options.line_search = false;
    const kr::StaticSolution solution =
        kr::solve_static(beam.model, beam.clamped, load.dead, options);
    Path full;
    full.displacement = solution.displacement;
    full.iterations = solution.iterations;
    const Path derivative = newton(beam, load, bases.derivative, steps);
    const Path linear = newton(beam, load, bases.linear, steps);
    report(state, beam, full, derivative, linear, false);
  }
}

BENCHMARK(BM_Twist270Degrees)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_BendPL2OverEI10)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
