#pragma once
// The finite-radius repulsion kernel of thesis §3.8.1.

namespace khz::contact::detail {

/// g(x) = 2x³ − 3x² + 1 for x = d/R < 1, else 0: the magnitude of the push between two
/// particles at distance d — 1 when they touch, falling to 0 with zero slope at R, so that a
/// neighbour crossing R changes nothing abruptly. It is the (negated) derivative of the pair
/// potential R(½ − x + x³ − ½x⁴).
constexpr double repulsion_force(double x) noexcept {
  return x < 1.0 ? (2.0 * x - 3.0) * x * x + 1.0 : 0.0;
}

}  // namespace khz::contact::detail
