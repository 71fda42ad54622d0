#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>

#include "quartic_tile_kernels.hpp"
#include "quartic_tile_layout.hpp"

#include <cassert>
#include <string>

namespace khz::reduced {

struct PolynomialForces::State {
  explicit State(Eigen::Index r)
      : layout(r),
        coefficients(layout.size()),
        scratch(layout),
        q(Eigen::VectorXd::Zero(detail::padded_length(layout.coordinates()))),
        halves(q.size(), layout.coordinates()),
        gradient(q.size()) {
    q[r] = 1.0;  // The homogenizing coordinate; the padding stays zero.
  }

  /// q̂ = (q, 1): the first r entries of the padded buffer.
  void set_coordinates(const Eigen::Ref<const Eigen::VectorXd>& coordinates) noexcept {
    q.head(coordinates.size()) = coordinates;
  }

  detail::QuarticTileLayout layout;
  Eigen::VectorXd coefficients;  ///< layout.size() doubles in layout order.
  detail::QuarticScratch scratch;
  Eigen::VectorXd q;         ///< q̂ padded with zeros to whole 8-lane tiles.
  Eigen::MatrixXd halves;    ///< M with Ĥ = M + Mᵀ, padded rows.
  Eigen::VectorXd gradient;  ///< ∇Ê, padded.
};

PolynomialForces::PolynomialForces(const EnergyPolynomial& polynomial) {
  if (polynomial.dimension() < 1)
    throw Error("PolynomialForces: the polynomial has no coordinates");
  polynomial.validate();
  m_state = std::make_unique<State>(polynomial.dimension());
  m_state->layout.fill(polynomial, m_state->coefficients.data());
}

PolynomialForces::~PolynomialForces() = default;
PolynomialForces::PolynomialForces(PolynomialForces&&) noexcept = default;
PolynomialForces& PolynomialForces::operator=(PolynomialForces&&) noexcept = default;

void PolynomialForces::set_polynomial(const EnergyPolynomial& polynomial) {
  polynomial.validate();
  if (polynomial.dimension() != dimension()) {
    throw Error("PolynomialForces::set_polynomial: the polynomial has " +
                std::to_string(polynomial.dimension()) + " coordinates, the model " +
                std::to_string(dimension()));
  }
  m_state->layout.fill(polynomial, m_state->coefficients.data());
}

Eigen::Index PolynomialForces::dimension() const noexcept {
  return m_state->layout.coordinates() - 1;
}

void PolynomialForces::evaluate(const Eigen::Ref<const Eigen::VectorXd>& q,
                                Eigen::Ref<Eigen::VectorXd> forces,
                                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept {
  State& s = *m_state;
  assert(q.size() == dimension() && forces.size() == dimension() &&
         stiffness.rows() == dimension() && stiffness.cols() == dimension());
  s.set_coordinates(q);
  detail::hessian_halves(s.layout, s.coefficients.data(), s.q.data(), s.halves.data(), s.scratch);
  detail::symmetrize_halves(s.layout, s.halves.data(), s.q.data(), stiffness.data(),
                            stiffness.outerStride(), forces.data(), s.scratch);
}

void PolynomialForces::evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                                       Eigen::Ref<Eigen::VectorXd> forces) noexcept {
  State& s = *m_state;
  assert(q.size() == dimension() && forces.size() == dimension());
  s.set_coordinates(q);
  detail::homogenized_gradient(s.layout, s.coefficients.data(), s.q.data(), s.gradient.data(),
                               s.scratch);
  forces = s.gradient.head(dimension());
}

double PolynomialForces::energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept {
  State& s = *m_state;
  assert(q.size() == dimension());
  s.set_coordinates(q);
  return detail::homogenized_energy(s.layout, s.coefficients.data(), s.q.data(), s.scratch);
}

std::size_t PolynomialForces::coefficient_bytes() const noexcept {
  return static_cast<std::size_t>(m_state->layout.size()) * sizeof(double);
}

}  // namespace khz::reduced
