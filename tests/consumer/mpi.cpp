// Links only Kilohertz::mpi from an install prefix and runs under mpiexec: a reduced model of a
// box precomputed over the ranks equals the one each rank computes alone.
#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <cmath>
#include <iostream>

int main(int argc, char** argv) {
  namespace kr = khz::reduced;
  const khz::mpi::Environment mpi(argc, argv);
  const kr::FemModel model(kr::box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.2, 0.2),
                                            Eigen::Vector3i(20, 4, 4)),
                           {kr::Material::stvk(1e6, 0.3, 1000.0)});
  kr::Basis basis;
  basis.vectors.resize(model.num_dofs(), 4);  // the same on every rank
  for (Eigen::Index j = 0; j < basis.vectors.cols(); ++j) {
    for (Eigen::Index i = 0; i < basis.vectors.rows(); ++i) {
      basis.vectors(i, j) = 0.01 * std::sin(0.1 * static_cast<double>(i * (j + 1)));
    }
  }
  const kr::ReducedModel alone = kr::ReducedModel::precompute(model, basis);
  khz::mpi::MpiWorkGroup group;
  kr::ReducedModelOptions options;
  options.group = &group;
  const kr::ReducedModel shared = kr::ReducedModel::precompute(model, basis, options);
  const Eigen::VectorXd& a = alone.groups()[0].parts[1].quartic;
  const Eigen::VectorXd& b = shared.groups()[0].parts[1].quartic;
  const double difference = (a - b).norm() / a.norm();
  if (!(difference < 1e-13)) {
    std::cerr << "rank " << group.rank() << ": the shared precompute differs by " << difference
              << "\n";
    return 1;
  }
  if (group.rank() == 0) {
    std::cout << "Kilohertz::mpi: a reduced model shared over " << group.size()
              << " ranks equals one rank's to " << difference << "\n";
  }
  return 0;
}
