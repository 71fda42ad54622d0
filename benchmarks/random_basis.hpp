#pragma once
// A random basis for the precompute benchmarks: the polynomials' cost depends on r and the mesh,
// not on the basis's values. The seed is fixed, so every run and every MPI rank gets the same.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/fem/fem_model.hpp>

#include <random>

namespace khz::bench {

/// n × r standard normal entries (n = model.num_dofs()), no fixed vertices.
inline reduced::Basis random_basis(const reduced::FemModel& model, Eigen::Index r) {
  std::mt19937 random(1);
  std::normal_distribution<double> entry(0.0, 1.0);
  reduced::Basis basis;
  basis.vectors.resize(model.num_dofs(), r);
  for (Eigen::Index i = 0; i < basis.vectors.size(); ++i) basis.vectors(i) = entry(random);
  return basis;
}

}  // namespace khz::bench
