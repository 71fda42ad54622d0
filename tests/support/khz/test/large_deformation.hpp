#pragma once
// Large deformations in reduced bases (thesis Fig. 2.14), shared by the test
// tests/reduced/test_modal_derivative_basis.cpp (8 cells, ~90° twist, 45° bend, one load step)
// and the benchmark benchmarks/bench_basis_large_deformation.cpp (20 cells, ~270° twist,
// PL²/EI = 10 bend, many load steps): a 1 m × 0.1 m × 0.08 m rubber beam (E = 1 MPa, ν = 0.3) of
// n × 2 × 2 hexahedra, clamped at x = 0, twisted by a follower torque at the tip or bent by a dead
// tip load. The full nonlinear static solution is the reference; the same static problem
// restricted to u = U q is solved with a small Newton loop, in a modal-derivative basis and in a
// linear-mode basis of the same size (five lowest modes of the deformation's kind).
// Header-only and free of GoogleTest (the benchmark does not link it): failures are reported in
// Path::failure, for the caller to assert on or skip with.

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseLU>

#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

namespace khz::test {

inline constexpr double degrees = 180.0 / std::numbers::pi;  ///< Radians to degrees.

/// The 1 × 0.1 × 0.08 rubber beam of `cells` × 2 × 2 hexahedra, clamped at x = 0.
struct LargeBeam {
  static constexpr double length = 1.0, width = 0.1, height = 0.08;
  static constexpr double young = 1e6, poisson = 0.3, density = 1000.0;
  /// Relative residual at which the Newton loops below stop.
  static constexpr double tolerance = 1e-9;
  explicit LargeBeam(int cells_along) : cells(cells_along) {}
  int cells;
  reduced::FemModel model{reduced::box_hex_mesh({0, 0, 0}, {length, width, height}, {cells, 2, 2}),
                          {reduced::Material::stvk(young, poisson, density)}};
  std::vector<int> clamped = face(0.0);
  std::vector<int> tip = face(length);
  reduced::SparseMatrix mass = model.mass_matrix();
  reduced::FixedDofs dofs{model.mesh().num_vertices(), clamped};

  std::vector<int> face(double x) const {
    return reduced::vertices_in_box(
        model.mesh().vertices,
        Eigen::AlignedBox3d(Eigen::Vector3d(x - 1e-9, -1, -1), Eigen::Vector3d(x + 1e-9, 1, 1)));
  }
  Eigen::Vector3d rest(int v) const { return model.mesh().vertices.row(v).transpose(); }
  /// The beam axis in the (y, z) section.
  Eigen::Vector2d centre() const { return {width / 2, height / 2}; }
  /// EI for bending along z (N·m²).
  static double bending_stiffness() { return young * width * std::pow(height, 3) / 12.0; }
};

/// A static load f(u) = g + A u: g dead, A u the follower part (A constant).
struct Load {
  Eigen::VectorXd dead;
  reduced::SparseMatrix follower;  ///< 3n × 3n.
};

/// Follower torque about the beam axis (y, z) = centre: every tip vertex v off the axis feels
/// τ e_x × (x_v − c), tangential around the axis at its current position x_v = X_v + u_v, so the
/// force stays a pure torque τ Σ|r_v|² however far the tip turns. A dead load with these
/// directions would turn with the tip no further than 90° (its torque falls as cos θ), hence the
/// follower load and the own full Newton solver below instead of solve_static.
inline Load follower_torque(const LargeBeam& beam, double torque) {
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
    // e_x × u = (0, −u_z, u_y)
    entries.emplace_back(3 * v + 1, 3 * v + 2, -tau);
    entries.emplace_back(3 * v + 2, 3 * v + 1, tau);
  }
  load.follower.resize(beam.model.num_dofs(), beam.model.num_dofs());
  load.follower.setFromTriplets(entries.begin(), entries.end());
  return load;
}

/// Dead tip load P = `load_ratio` · EI/L² along −z, split evenly over the tip vertices (no
/// follower part). A dead load bends the tip to 90° only in the limit P → ∞.
inline Load dead_tip_bend(const LargeBeam& beam, double load_ratio) {
  Load load;
  load.dead = Eigen::VectorXd::Zero(beam.model.num_dofs());
  const double force =
      load_ratio * LargeBeam::bending_stiffness() / (LargeBeam::length * LargeBeam::length);
  for (int v : beam.tip) load.dead[3 * v + 2] = -force / static_cast<double>(beam.tip.size());
  load.follower.resize(beam.model.num_dofs(), beam.model.num_dofs());
  return load;
}

/// Rotation (rad) of the tip about the beam axis, unwrapped from `previous`: the mean over the
/// off-axis tip vertices of the angle their (y, z) offset from the axis has turned.
inline double tip_twist(const LargeBeam& beam, const Eigen::VectorXd& u, double previous) {
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

/// Rotation (rad) of the tip face about y under a −z load: the vertical tip edge at y = 0 turns
/// from e_z towards +x.
inline double tip_bend(const LargeBeam& beam, const Eigen::VectorXd& u) {
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
  Eigen::VectorXd displacement;  ///< Final u.
  double twist = 0.0;            ///< Final tip twist (rad), unwrapped along the load path.
  int iterations = 0;            ///< Newton iterations over all load steps.
  std::string failure;           ///< Empty, or why Newton stopped early.
};

/// Full Newton for R(u) = s (g + A u), s = 1/steps … 1, on the free dofs, with SparseLU for the
/// non-symmetric tangent K(u) − s A. No line search: on this slender beam the first Newton step
/// of a load step (the linear response, which stretches the rotated fibres) raises ‖R − f‖ by
/// orders of magnitude before converging quadratically, so backtracking on ‖R − f‖ stalls.
inline Path full_solve(const LargeBeam& beam, const Load& load, int steps) {
  const reduced::FemModel& model = beam.model;
  Path path;
  path.displacement = Eigen::VectorXd::Zero(model.num_dofs());
  Eigen::VectorXd& u = path.displacement;
  reduced::SparseMatrix stiffness = model.stiffness_pattern();
  Eigen::VectorXd forces;
  const reduced::SparseMatrix follower_free = beam.dofs.restrict_matrix(load.follower);
  for (int step = 1; step <= steps; ++step) {
    const double s = static_cast<double>(step) / steps;
    const double scale = beam.dofs.restrict_vector(s * load.dead).norm();
    for (int iteration = 0;; ++iteration) {
      model.forces_and_stiffness(u, forces, stiffness);
      const Eigen::VectorXd r =
          beam.dofs.restrict_vector(forces - s * (load.dead + load.follower * u));
      if (r.norm() <= beam.tolerance * scale) break;
      if (iteration == 30) {
        path.failure = "full Newton: no convergence at step " + std::to_string(step) + ", |r| " +
                       std::to_string(r.norm());
        return path;
      }
      const reduced::SparseMatrix jacobian =
          beam.dofs.restrict_matrix(stiffness) - s * follower_free;
      const Eigen::SparseLU<reduced::SparseMatrix> lu(jacobian);
      Eigen::VectorXd du;
      beam.dofs.expand_vector(lu.solve(-r), du);
      u += du;
      ++path.iterations;
    }
    path.twist = tip_twist(beam, u, path.twist);
  }
  return path;
}

/// The full reference for a dead load (Load::follower zero) from the library's solve_static, in
/// `steps` load steps, without line search (see full_solve). Leaves Path::twist at 0; throws
/// SolverError if Newton does not converge.
inline Path full_dead_load_solve(const LargeBeam& beam, const Load& load, int steps) {
  reduced::StaticSolveOptions options;
  options.load_steps = steps;
  options.line_search = false;
  const reduced::StaticSolution solution =
      reduced::solve_static(beam.model, beam.clamped, load.dead, options);
  Path path;
  path.displacement = solution.displacement;
  path.iterations = solution.iterations;
  return path;
}

/// The same load path restricted to u = U q (U with zero rows at the clamp): reduced residual
/// Uᵀ(R(Uq) − s(g + A Uq)), reduced tangent Uᵀ(K(Uq) − s A)U, dense LU, plain Newton.
inline Path reduced_solve(const LargeBeam& beam, const Load& load, const Eigen::MatrixXd& basis,
                          int steps) {
  const reduced::FemModel& model = beam.model;
  Path path;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(basis.cols());
  reduced::SparseMatrix stiffness = model.stiffness_pattern();
  Eigen::VectorXd forces;
  const Eigen::MatrixXd follower_reduced = basis.transpose() * (load.follower * basis);
  const Eigen::VectorXd dead_reduced = basis.transpose() * load.dead;
  for (int step = 1; step <= steps && path.failure.empty(); ++step) {
    const double s = static_cast<double>(step) / steps;
    for (int iteration = 0;; ++iteration) {
      model.forces_and_stiffness(basis * q, forces, stiffness);
      const Eigen::VectorXd r =
          basis.transpose() * forces - s * (dead_reduced + follower_reduced * q);
      if (r.norm() <= beam.tolerance * s * dead_reduced.norm()) break;
      if (iteration == 30) {
        path.failure = "reduced Newton: no convergence at step " + std::to_string(step) + ", |r| " +
                       std::to_string(r.norm());
        break;
      }
      const Eigen::MatrixXd jacobian =
          basis.transpose() * (stiffness * basis) - s * follower_reduced;
      q += jacobian.partialPivLu().solve(-r);
      ++path.iterations;
    }
    path.twist = tip_twist(beam, basis * q, path.twist);
  }
  path.displacement = basis * q;
  return path;
}

/// Mass-orthonormal basis of the span of `vectors` (mass-PCA keeping everything).
inline Eigen::MatrixXd orthonormal_span(const Eigen::MatrixXd& vectors,
                                        const reduced::SparseMatrix& mass) {
  reduced::PcaOptions options;
  options.basis_size = static_cast<int>(vectors.cols());
  return reduced::principal_components(vectors, mass, options).basis;
}

/// Shares of a mode's lumped kinetic energy in section-wise bending along z and section-wise
/// rotation about the axis (as in test_linear_modes.cpp).
struct Shares {
  double bending_z = 0, torsion = 0;
};

inline Shares mode_shares(const LargeBeam& beam, const Eigen::VectorXd& psi) {
  const reduced::SparseMatrix lumped = beam.model.mass_matrix(reduced::MassLumping::lumped);
  const int sections = beam.cells + 1;
  std::vector<double> mass(sections, 0.0), deflection(sections, 0.0), moment(sections, 0.0),
      inertia(sections, 0.0);
  double total = 0.0;
  for (Eigen::Index v = 0; v < beam.model.mesh().num_vertices(); ++v) {
    const Eigen::Vector3d x = beam.rest(static_cast<int>(v));
    const int s = static_cast<int>(std::lround(x.x() / (beam.length / beam.cells)));
    const double m = lumped.coeff(3 * v, 3 * v);
    const Eigen::Vector2d r = x.tail<2>() - beam.centre();
    mass[s] += m;
    deflection[s] += m * psi[3 * v + 2];
    moment[s] += m * (-r.y() * psi[3 * v + 1] + r.x() * psi[3 * v + 2]);
    inertia[s] += m * r.squaredNorm();
    total += m * psi.segment<3>(3 * v).squaredNorm();
  }
  Shares shares;
  for (int s = 0; s < sections; ++s) {
    shares.bending_z += deflection[s] * deflection[s] / mass[s];
    if (inertia[s] > 0) shares.torsion += moment[s] * moment[s] / inertia[s];
  }
  shares.bending_z /= total;
  shares.torsion /= total;
  return shares;
}

/// Whether mode ψ is mostly section-wise rotation about the axis (torsion) or section-wise
/// deflection along z (bending): its share of the given kind exceeds ½.
inline bool is_kind(const LargeBeam& beam, const Eigen::VectorXd& psi, bool torsion) {
  const Shares shares = mode_shares(beam, psi);
  return (torsion ? shares.torsion : shares.bending_z) > 0.5;
}

/// Indices of the modes of the given kind (is_kind), lowest first.
inline std::vector<int> modes_of_kind(const LargeBeam& beam, const reduced::LinearModes& modes,
                                      bool torsion) {
  std::vector<int> result;
  for (int i = 0; i < modes.modes.cols(); ++i) {
    if (is_kind(beam, modes.modes.col(i), torsion)) result.push_back(i);
  }
  return result;
}

/// The derivative basis of two modes a, b (thesis Fig. 2.14: Ψ4, Ψ9, Φ44, Φ49, Φ99) and a basis
/// of the first five linear modes of the same kind.
struct BasisPair {
  Eigen::MatrixXd derivative, linear;
};

/// Derivative basis span{Ψa, Ψb, Φaa, Φab, Φbb} of the two lowest modes of the kind (torsion, or
/// bending along z) and linear basis of the five lowest, both M-orthonormal, r = 5; both empty
/// if fewer than five of the lowest 30 modes are of the kind.
inline BasisPair large_deformation_bases(const LargeBeam& beam, bool torsion) {
  reduced::LinearModesOptions options;
  options.num_modes = 30;
  const reduced::LinearModes modes =
      reduced::compute_linear_modes(beam.model, beam.clamped, options);
  // 8 cells: torsion modes 4 8 12 15 18 …, z-bending modes 0 2 6 9 13 … (0-based).
  const std::vector<int> kind = modes_of_kind(beam, modes, torsion);
  if (kind.size() < 5) return {};
  // Derivatives of the two lowest modes of the kind only: a LinearModes of those two columns.
  reduced::LinearModes chosen;
  // Not from a Vector2d temporary: that trips GCC 12's -Warray-bounds with AVX-512.
  chosen.eigenvalues.resize(2);
  chosen.eigenvalues << modes.eigenvalues[kind[0]], modes.eigenvalues[kind[1]];
  chosen.modes.resize(modes.modes.rows(), 2);
  chosen.modes << modes.modes.col(kind[0]), modes.modes.col(kind[1]);
  chosen.fixed_vertices = modes.fixed_vertices;
  const reduced::ModalDerivatives derivatives =
      reduced::compute_modal_derivatives(beam.model, chosen);
  BasisPair bases;
  Eigen::MatrixXd vectors(modes.modes.rows(), 5);
  vectors << chosen.modes, derivatives.vectors;
  bases.derivative = orthonormal_span(vectors, beam.mass);
  for (int c = 0; c < 5; ++c) vectors.col(c) = modes.modes.col(kind[c]);
  bases.linear = orthonormal_span(vectors, beam.mass);
  return bases;
}

/// ‖value − reference‖_M / ‖reference‖_M.
inline double relative_mass_error(const reduced::SparseMatrix& mass, const Eigen::VectorXd& value,
                                  const Eigen::VectorXd& reference) {
  const Eigen::VectorXd difference = value - reference;
  return std::sqrt(difference.dot(mass * difference)) / std::sqrt(reference.dot(mass * reference));
}

/// The full reference solve, the reduced solves in both bases, and the reduced solves' relative
/// mass-norm errors against the reference.
struct Comparison {
  Path full, derivative, linear;
  double derivative_error = 0.0, linear_error = 0.0;
  /// The first Path::failure, or empty when every solve converged.
  std::string failure() const {
    for (const Path* path : {&full, &derivative, &linear}) {
      if (!path->failure.empty()) return path->failure;
    }
    return {};
  }
};

/// Solves `load` in `steps` load steps in full and in both bases. The reference is full_solve
/// for a follower load (solve_static takes dead loads only) and the library's solve_static
/// (full_dead_load_solve) for a dead one.
inline Comparison compare_solves(const LargeBeam& beam, const Load& load, const BasisPair& bases,
                                 int steps) {
  Comparison comparison;
  comparison.full = load.follower.nonZeros() > 0 ? full_solve(beam, load, steps)
                                                 : full_dead_load_solve(beam, load, steps);
  comparison.derivative = reduced_solve(beam, load, bases.derivative, steps);
  comparison.linear = reduced_solve(beam, load, bases.linear, steps);
  comparison.derivative_error = relative_mass_error(beam.mass, comparison.derivative.displacement,
                                                    comparison.full.displacement);
  comparison.linear_error =
      relative_mass_error(beam.mass, comparison.linear.displacement, comparison.full.displacement);
  return comparison;
}

}  // namespace khz::test
