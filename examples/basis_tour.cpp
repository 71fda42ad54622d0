// basis_tour: build a reduced basis for a clamped beam, the automatic way (thesis §2.8.3).
//
//   basis_tour [MODES] [BASIS_SIZE]
//
// Defaults: k = 6 linear modes, r = 15 (the thesis's spoon used k = 6, r = 15). Meshes a
// 1 m × 0.1 m × 0.1 m rubber beam with hexahedra, clamps one end, and then
//   1. computes the lowest k vibration modes (ARPACK shift-invert on CHOLMOD) and prints their
//      frequencies next to Euler–Bernoulli's first bending frequency,
//   2. computes all k(k+1)/2 modal derivatives,
//   3. reduces modes and derivatives to r vectors by mass-PCA (eq. 2.52 weights),
// printing progress bars on the way, and writes basis_tour.khzbasis (Kilohertz's checked
// format), basis_tour.npy (NumPy: numpy.load) and basis_tour.mat (MATLAB: load), and
// basis_tour_modes.vtu with the modes and the first basis vectors as point arrays for ParaView.
#include "cantilever.hpp"
#include "point_array.hpp"
#include "progress_bar.hpp"

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_export.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <string>

namespace {

namespace kr = khz::reduced;

}  // namespace

int main(int argc, char** argv) {
  try {
    const int k = argc > 1 ? std::atoi(argv[1]) : 6;
    const int r = argc > 2 ? std::atoi(argv[2]) : 15;
    const double length = 1.0, side = 0.1;
    const kr::Material rubber = kr::Material::stvk(1e6, 0.45, 1100.0);  // Pa, –, kg/m³
    kr::FemModel model(kr::box_hex_mesh(Eigen::Vector3d::Zero(), {length, side, side}, {40, 4, 4}),
                       {rubber});
    const std::vector<int> clamped = khz::examples::vertices_at_x(model.mesh().vertices, 0.0);
    std::cout << "beam: " << model.mesh().num_vertices() << " vertices, "
              << model.mesh().num_elements() << " hexahedra, " << clamped.size() << " clamped\n";

    const auto start = std::chrono::steady_clock::now();
    kr::LinearModesOptions mode_options;
    mode_options.num_modes = k;
    mode_options.progress = khz::examples::print_progress;
    const kr::LinearModes modes = kr::compute_linear_modes(model, clamped, mode_options);

    // Euler–Bernoulli: f₁ = 1.8751² / (2π L²) · √(EI / ρA), I = a⁴/12, A = a².
    const double young = 1e6, density = 1100.0;
    const double beam_f1 = 1.8751 * 1.8751 / (2 * std::numbers::pi * length * length) *
                           std::sqrt(young * side * side / 12.0 / density);
    std::cout << "frequencies (Hz):";
    for (Eigen::Index i = 0; i < k; ++i)
      std::cout << " " << std::setprecision(4) << modes.frequencies_hz()(i);
    std::cout << "\n  (Euler–Bernoulli first bending: " << beam_f1 << " Hz)\n";

    kr::ModalDerivativesOptions derivative_options;
    derivative_options.progress = khz::examples::print_progress;
    const kr::ModalDerivatives derivatives =
        kr::compute_modal_derivatives(model, modes, derivative_options);

    const kr::SparseMatrix mass = model.mass_matrix();
    kr::PcaOptions pca;
    pca.basis_size = r;
    pca.progress = khz::examples::print_progress;
    const kr::PcaResult reduced =
        kr::principal_components(kr::weighted_modal_samples(modes, derivatives, mass), mass, pca);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    kr::Basis basis;
    basis.vectors = reduced.basis;
    basis.fixed_vertices = modes.fixed_vertices;
    basis.recipe = "basis_tour: k=" + std::to_string(k) + " modes, " +
                   std::to_string(derivatives.vectors.cols()) +
                   " derivatives, mass PCA to r=" + std::to_string(r);
    const double kept =
        reduced.singular_values.head(r).squaredNorm() / reduced.singular_values.squaredNorm();
    std::cout << "basis: r = " << r << " of " << reduced.singular_values.size()
              << " samples, keeping " << std::setprecision(8) << 100.0 * kept
              << " % of their weighted mass norm², in " << std::setprecision(3) << seconds
              << " s\n";

    kr::write_basis("basis_tour.khzbasis", basis, model.mesh());
    kr::write_basis_npy("basis_tour.npy", basis);
    kr::write_basis_mat("basis_tour.mat", basis);
    kr::VtkFields fields;
    for (Eigen::Index i = 0; i < k; ++i) {
      fields.point_data.push_back(
          {"mode" + std::to_string(i + 1), khz::examples::per_vertex(modes.modes.col(i))});
    }
    for (Eigen::Index i = 0; i < std::min<Eigen::Index>(r, 6); ++i) {
      fields.point_data.push_back(
          {"basis" + std::to_string(i + 1), khz::examples::per_vertex(basis.vectors.col(i))});
    }
    kr::write_volume_mesh("basis_tour_modes.vtu", model.mesh(), fields);
    std::cout
        << "wrote basis_tour.khzbasis, basis_tour.npy, basis_tour.mat, basis_tour_modes.vtu\n";
  } catch (const khz::reduced::Error& error) {
    std::cerr << "basis_tour: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
