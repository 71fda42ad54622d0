#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/energy_polynomial.hpp>

#include <string>

namespace khz::reduced {

namespace {

// C(n + k − 1, k): the number of sorted k-tuples of indices below n, for k = 2, 3, 4.
Eigen::Index pairs_below(Eigen::Index n) noexcept { return n * (n + 1) / 2; }
Eigen::Index triples_below(Eigen::Index n) noexcept { return n * (n + 1) * (n + 2) / 6; }
Eigen::Index quadruples_below(Eigen::Index n) noexcept {
  return n * (n + 1) * (n + 2) * (n + 3) / 24;
}

}  // namespace

EnergyPolynomial EnergyPolynomial::zero(Eigen::Index r) {
  if (r < 0) throw Error("EnergyPolynomial: negative dimension " + std::to_string(r));
  return {Eigen::MatrixXd::Zero(r, r), Eigen::VectorXd::Zero(cubic_size(r)),
          Eigen::VectorXd::Zero(quartic_size(r))};
}

Eigen::Index EnergyPolynomial::cubic_size(Eigen::Index r) noexcept { return triples_below(r); }
Eigen::Index EnergyPolynomial::quartic_size(Eigen::Index r) noexcept { return quadruples_below(r); }

Eigen::Index EnergyPolynomial::cubic_index(int a, int b, int c) noexcept {
  return triples_below(c) + pairs_below(b) + a;
}

Eigen::Index EnergyPolynomial::quartic_index(int a, int b, int c, int d) noexcept {
  return quadruples_below(d) + cubic_index(a, b, c);
}

void EnergyPolynomial::validate() const {
  const Eigen::Index r = quadratic.rows();
  if (quadratic.cols() != r) {
    throw Error("EnergyPolynomial: the quadratic part is " + std::to_string(quadratic.rows()) +
                "×" + std::to_string(quadratic.cols()) + ", not square");
  }
  if (cubic.size() != cubic_size(r) || quartic.size() != quartic_size(r)) {
    throw Error("EnergyPolynomial: r = " + std::to_string(r) + " needs " +
                std::to_string(cubic_size(r)) + " cubic and " + std::to_string(quartic_size(r)) +
                " quartic coefficients, got " + std::to_string(cubic.size()) + " and " +
                std::to_string(quartic.size()));
  }
  if (!quadratic.allFinite() || !cubic.allFinite() || !quartic.allFinite()) {
    throw Error("EnergyPolynomial: a coefficient is not finite");
  }
  if (r == 0) return;
  const double scale = quadratic.cwiseAbs().maxCoeff();
  if ((quadratic - quadratic.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw Error("EnergyPolynomial: the quadratic part is not symmetric");
  }
}

EnergyPolynomial EnergyPolynomial::truncated(Eigen::Index r) const {
  if (r < 0 || r > dimension()) {
    throw Error("EnergyPolynomial: cannot truncate " + std::to_string(dimension()) +
                " coordinates to " + std::to_string(r));
  }
  return {quadratic.topLeftCorner(r, r), cubic.head(cubic_size(r)), quartic.head(quartic_size(r))};
}

void EnergyPolynomial::add_scaled(double weight, const EnergyPolynomial& other) {
  if (other.dimension() != dimension()) {
    throw Error("EnergyPolynomial: cannot add a polynomial in " +
                std::to_string(other.dimension()) + " coordinates to one in " +
                std::to_string(dimension()));
  }
  quadratic += weight * other.quadratic;
  cubic += weight * other.cubic;
  quartic += weight * other.quartic;
}

double EnergyPolynomial::energy(const Eigen::VectorXd& q) const {
  const Eigen::Index r = dimension();
  if (q.size() != r) {
    throw Error("EnergyPolynomial::energy: q has " + std::to_string(q.size()) +
                " entries, expected " + std::to_string(r));
  }
  double total = 0.5 * q.dot(quadratic * q);
  Eigen::Index cubic_at = 0, quartic_at = 0;
  for (int d = 0; d < r; ++d) {
    for (int c = 0; c <= d; ++c) {
      for (int b = 0; b <= c; ++b) {
        const double qbcd = q[b] * q[c] * q[d];
        for (int a = 0; a <= b; ++a) total += quartic[quartic_at++] * q[a] * qbcd;
      }
    }
  }
  for (int c = 0; c < r; ++c) {
    for (int b = 0; b <= c; ++b) {
      for (int a = 0; a <= b; ++a) total += cubic[cubic_at++] * q[a] * q[b] * q[c];
    }
  }
  return total;
}

}  // namespace khz::reduced
