// mpi_precompute: a reduced model's polynomials precomputed by every rank of an MPI job, each
// summing its share of the elements (khz::mpi, docs/SCALING.md).
//
//   mpiexec -n 2 build/release/examples/mpi_precompute [BASIS_SIZE]
//
// Default r = 20. Rank 0 builds the modal-derivative basis of a clamped beam and writes it to a
// basis file; every rank reads that file (so all hold the same basis, bit for bit), precomputes
// its share of the reduced energy polynomials, and the shares are added; rank 0 prints the
// progress of the whole job and writes mpi_precompute.khzmodel.
#include "cantilever.hpp"
#include "progress_bar.hpp"

#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <utility>
#include <vector>

namespace kr = khz::reduced;

int main(int argc, char** argv) {
  const khz::mpi::Environment mpi(argc, argv);
  try {
    const int r = argc > 1 ? std::atoi(argv[1]) : 20;
    khz::mpi::MpiWorkGroup group;  // every rank of MPI_COMM_WORLD
    const bool root = group.rank() == 0;
    // Every rank builds the same FEM model: a 1 m rubber beam, 9,600 tetrahedra.
    const kr::FemModel fem(kr::box_tet_mesh(Eigen::Vector3d::Zero(), {1.0, 0.1, 0.1}, {40, 4, 10}),
                           {kr::Material::stvk(1e6, 0.45, 1100.0)});

    // The basis: made once, on rank 0, and shared as a file.
    if (root) {
      kr::ModalDerivativeBasisOptions options;
      options.modes.num_modes = 6;
      options.basis_size = r;
      options.progress = khz::examples::print_progress;
      const std::vector<int> clamped = khz::examples::vertices_at_x(fem.mesh().vertices, 0.0);
      kr::write_basis("mpi_precompute.khzbasis", kr::modal_derivative_basis(fem, clamped, options),
                      fem.mesh());
    }
    MPI_Barrier(group.communicator());
    kr::Basis basis = kr::read_basis("mpi_precompute.khzbasis", fem.mesh());

    // The polynomials, shared: each rank sums its share of the elements.
    kr::ReducedModelOptions options;
    options.group = &group;
    if (root) options.progress = khz::examples::print_progress;  // the whole job's count
    const auto start = std::chrono::steady_clock::now();
    const kr::ReducedModel model = kr::ReducedModel::precompute(fem, std::move(basis), options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    if (root) {
      kr::write_reduced_model("mpi_precompute.khzmodel", model, fem.mesh());
      std::cout << "reduced polynomials of r = " << r << " over " << fem.mesh().elements.rows()
                << " tetrahedra on " << group.size() << " ranks: " << seconds
                << " s; wrote mpi_precompute.khzmodel\n";
    }
  } catch (const kr::Error& error) {
    // A failure on one rank reaches every rank, each of which ends here: rank 0 says why.
    if (mpi.rank() == 0) std::cerr << "mpi_precompute: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
