#pragma once
// A small clamped box of two materials with a random basis: the reduced-model precompute's test
// subject (tests/reduced/test_reduced_model.cpp, test_shared_precompute.cpp).

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <Eigen/Core>

#include <random>
#include <vector>

namespace khz::test {

using reduced::Basis;
using reduced::box_hex_mesh;
using reduced::box_tet_mesh;
using reduced::FemModel;
using reduced::Material;
using reduced::VoigtMatrix;
using reduced::VolumeMesh;

/// A 1×0.5×0.5 box clamped at x = 0 with two material groups (x < ½: StVK steel-like scaled
/// to 1e6 Pa; x ≥ ½: an anisotropic general material), and a random basis that vanishes at the
/// clamp. Random bases are fine here: the polynomial identity holds for any U.
struct TwoMaterialBox {
  FemModel model;
  Basis basis;

  /// `cells`: the box's cells along x, y, z.
  TwoMaterialBox(bool hexahedra, Eigen::Index r, double stvk_lambda = 4e5,
                 const Eigen::Vector3i& cells = Eigen::Vector3i(4, 2, 2))
      : model(mesh(hexahedra, cells), materials(stvk_lambda)), basis(random_basis(model, r)) {}

  static VolumeMesh mesh(bool hexahedra, const Eigen::Vector3i& cells = Eigen::Vector3i(4, 2, 2)) {
    const Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi(1.0, 0.5, 0.5);
    VolumeMesh volume = hexahedra ? box_hex_mesh(lo, hi, cells) : box_tet_mesh(lo, hi, cells);
    volume.element_groups.resize(volume.elements.rows());
    for (Eigen::Index e = 0; e < volume.elements.rows(); ++e) {
      double x = 0;
      for (Eigen::Index a = 0; a < volume.elements.cols(); ++a) {
        x += volume.vertices(volume.elements(e, a), 0);
      }
      volume.element_groups[e] = x / static_cast<double>(volume.elements.cols()) < 0.5 ? 0 : 1;
    }
    return volume;
  }

  static VoigtMatrix anisotropic_elasticity() {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> entry(-1.0, 1.0);
    VoigtMatrix a;
    for (Eigen::Index i = 0; i < a.size(); ++i) a(i) = entry(random);
    return 2e5 * (a.transpose() * a + 3.0 * VoigtMatrix::Identity());
  }

  static std::vector<Material> materials(double stvk_lambda) {
    return {Material::stvk_lame({stvk_lambda, 3e5}, 1000.0),
            Material::general(anisotropic_elasticity(), 1500.0)};
  }

  static Basis random_basis(const FemModel& model, Eigen::Index r) {
    std::mt19937 random(11);
    std::normal_distribution<double> entry(0.0, 0.1);
    Basis basis;
    basis.vectors.resize(model.num_dofs(), r);
    for (Eigen::Index i = 0; i < basis.vectors.size(); ++i) basis.vectors(i) = entry(random);
    const Eigen::MatrixXd& x = model.mesh().vertices;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      if (x(v, 0) < 1e-9) {
        basis.vectors.middleRows<3>(3 * v).setZero();
        basis.fixed_vertices.push_back(static_cast<int>(v));
      }
    }
    return basis;
  }
};

}  // namespace khz::test
