#pragma once
// Small reduced force models with exact forces and stiffness, for testing the reduced
// integrators and the reduced static solver without a FEM model.

#include <khz/reduced/subspace/reduced_forces.hpp>

#include <Eigen/Core>

#include <cassert>
#include <limits>
#include <utility>

namespace khz::test {

/// M̃ = I (r×r): the reduced mass of r unit masses, the mass the models below are tested with.
inline Eigen::MatrixXd unit_mass(Eigen::Index r) { return Eigen::MatrixXd::Identity(r, r); }

/// A chain of r equal springs: a wall, then r coordinates (e.g. unit masses with M̃ = I), spring
/// i joining q_{i−1} and q_i (q_0 ≡ 0 is the wall). Spring energy ½k d² + ¼κ d⁴ at elongation
/// d = q_i − q_{i−1}: κ > 0 stiffens, κ < 0 softens (the tension k d + κ d³ then peaks at
/// d = √(k / 3|κ|)), κ = 0 is linear. Evaluation allocates nothing.
class SpringChainForces final : public reduced::ReducedForceModel {
 public:
  SpringChainForces(Eigen::Index r, double k, double kappa) : m_r(r), m_k(k), m_kappa(kappa) {}

  Eigen::Index dimension() const noexcept override { return m_r; }

  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> forces,
                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept override {
    evaluate_forces(q, forces);
    stiffness.setZero();
    for (Eigen::Index i = 0; i < m_r; ++i) {
      const double s = spring_stiffness(elongation(q, i));
      stiffness(i, i) += s;
      if (i > 0) {
        stiffness(i - 1, i - 1) += s;
        stiffness(i - 1, i) -= s;
        stiffness(i, i - 1) -= s;
      }
    }
  }

  void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                       Eigen::Ref<Eigen::VectorXd> forces) noexcept override {
    assert(q.size() == m_r && forces.size() == m_r);
    forces.setZero();
    for (Eigen::Index i = 0; i < m_r; ++i) {
      const double tension = spring_force(elongation(q, i));
      forces(i) += tension;
      if (i > 0) forces(i - 1) -= tension;
    }
  }

  double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept override {
    double sum = 0.0;
    for (Eigen::Index i = 0; i < m_r; ++i) {
      const double d = elongation(q, i);
      sum += 0.5 * m_k * d * d + 0.25 * m_kappa * d * d * d * d;
    }
    return sum;
  }

  /// Tension k d + κ d³ of one spring at elongation d.
  double spring_force(double d) const noexcept { return m_k * d + m_kappa * d * d * d; }
  /// Its derivative k + 3κ d².
  double spring_stiffness(double d) const noexcept { return m_k + 3.0 * m_kappa * d * d; }

 private:
  static double elongation(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Index i) noexcept {
    return i == 0 ? q(0) : q(i) - q(i - 1);
  }

  Eigen::Index m_r;
  double m_k, m_kappa;
};

/// R̃(q) = K q, K̃ = K, E = ½ qᵀK q for a given symmetric K, which may be indefinite or singular.
/// Evaluation allocates nothing.
class LinearReducedForces final : public reduced::ReducedForceModel {
 public:
  explicit LinearReducedForces(Eigen::MatrixXd stiffness) : m_stiffness(std::move(stiffness)) {}

  Eigen::Index dimension() const noexcept override { return m_stiffness.rows(); }

  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> forces,
                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept override {
    evaluate_forces(q, forces);
    stiffness = m_stiffness;
  }

  void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                       Eigen::Ref<Eigen::VectorXd> forces) noexcept override {
    forces.noalias() = m_stiffness * q;
  }

  double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept override {
    double twice = 0.0;
    for (Eigen::Index j = 0; j < q.size(); ++j) twice += q(j) * m_stiffness.col(j).dot(q);
    return 0.5 * twice;
  }

  const Eigen::MatrixXd& stiffness() const noexcept { return m_stiffness; }

 private:
  Eigen::MatrixXd m_stiffness;
};

/// Wraps a model and, while `poison_forces` or `poison_stiffness` is set, returns NaN in the
/// first entry of R̃ or of K̃: a model failing at runtime.
class FaultyForces final : public reduced::ReducedForceModel {
 public:
  explicit FaultyForces(reduced::ReducedForceModel& inner) : m_inner(inner) {}

  bool poison_forces = false;
  bool poison_stiffness = false;

  Eigen::Index dimension() const noexcept override { return m_inner.dimension(); }

  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> forces,
                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept override {
    m_inner.evaluate(q, forces, stiffness);
    if (poison_forces) forces(0) = std::numeric_limits<double>::quiet_NaN();
    if (poison_stiffness) stiffness(0, 0) = std::numeric_limits<double>::quiet_NaN();
  }

  void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                       Eigen::Ref<Eigen::VectorXd> forces) noexcept override {
    m_inner.evaluate_forces(q, forces);
    if (poison_forces) forces(0) = std::numeric_limits<double>::quiet_NaN();
  }

  double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept override {
    return poison_forces ? std::numeric_limits<double>::quiet_NaN() : m_inner.energy(q);
  }

 private:
  reduced::ReducedForceModel& m_inner;
};

}  // namespace khz::test
