#pragma once
// A clamped hexahedral beam: the classic check of a FEM model against Euler–Bernoulli theory.

#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <Eigen/Geometry>

#include <vector>

namespace khz::test {

/// A square-section beam [0, length] × [0, side]² of hexahedra, clamped at x = 0.
struct Cantilever {
  double length, side;
  reduced::FemModel model;
  std::vector<int> clamped;  ///< Vertices on the x = 0 face.
  std::vector<int> tip;      ///< Vertices on the x = length face.

  /// `across` cells through the side, length/side·across along the beam.
  Cantilever(double beam_length, double beam_side, int across, const reduced::Material& material)
      : length(beam_length),
        side(beam_side),
        model(reduced::box_hex_mesh(
                  Eigen::Vector3d::Zero(), Eigen::Vector3d(beam_length, beam_side, beam_side),
                  Eigen::Vector3i(static_cast<int>(across * beam_length / beam_side), across,
                                  across)),
              {material}),
        clamped(face(0.0)),
        tip(face(beam_length)) {}

  /// Full force vector: total `force` (N) split evenly over the tip vertices.
  Eigen::VectorXd tip_load(const Eigen::Vector3d& force) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
    for (int v : tip) f.segment<3>(3 * v) += force / static_cast<double>(tip.size());
    return f;
  }

  /// Mean displacement of the tip vertices.
  Eigen::Vector3d tip_displacement(const Eigen::VectorXd& u) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int v : tip) sum += u.segment<3>(3 * v);
    return sum / static_cast<double>(tip.size());
  }

 private:
  std::vector<int> face(double x) const {
    const double eps = 1e-9 * length;
    const Eigen::AlignedBox3d box(Eigen::Vector3d(x - eps, -eps, -eps),
                                  Eigen::Vector3d(x + eps, side + eps, side + eps));
    return reduced::vertices_in_box(model.mesh().vertices, box);
  }
};

}  // namespace khz::test
