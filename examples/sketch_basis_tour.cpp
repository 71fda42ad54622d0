// sketch_basis_tour: build a reduced basis from sketched force loads (thesis §2.8.2).
//
//   sketch_basis_tour [LOADS.csv] [BASIS_SIZE]
//
// Meshes a 1 m × 0.1 m × 0.1 m rubber beam with hexahedra and clamps one end. Without a load
// file it "records" a sketch the way an interactive session would: the tip dragged down, to
// the side and diagonally, sampled every frame, so consecutive loads are nearly equal; it
// writes them to sketch_basis_tour_loads.csv (the recorded-load format: load,vertex,fx,fy,fz)
// and reads them back. Then sketch_basis() thins the loads, solves each remaining one on the
// full nonlinear model, thins the deformations by mass distance and reduces them by mass-PCA
// to r vectors (default 6), with progress bars. Finally it checks the basis on a load that
// was not sketched and writes sketch_basis_tour.vtu with the basis vectors as point arrays.
#include "point_array.hpp"
#include "progress_bar.hpp"

#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

namespace {

namespace kr = khz::reduced;

// Total force `total` (N) spread evenly over the given vertices.
kr::ForceLoad spread_load(const std::vector<int>& vertices, const Eigen::Vector3d& total) {
  kr::ForceLoad load;
  for (int v : vertices) load.forces.push_back({v, total / static_cast<double>(vertices.size())});
  return load;
}

// What a user dragging the tip with the mouse would record: for each direction, 60 frames of
// a force growing from 0 to `peak` newtons.
std::vector<kr::ForceLoad> recorded_drags(const std::vector<int>& tip, double peak) {
  const double angles_deg[] = {-90.0, 0.0, -45.0};  // down, sideways (+y), diagonal
  std::vector<kr::ForceLoad> loads;
  for (double angle : angles_deg) {
    const double a = angle * std::numbers::pi / 180.0;
    const Eigen::Vector3d direction(0.0, std::cos(a), std::sin(a));
    for (int frame = 1; frame <= 60; ++frame) {
      loads.push_back(spread_load(tip, peak * frame / 60.0 * direction));
    }
  }
  return loads;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const int r = argc > 2 ? std::atoi(argv[2]) : 6;
    const double length = 1.0, side = 0.1;
    const kr::Material rubber = kr::Material::stvk(1e6, 0.45, 1100.0);  // Pa, –, kg/m³
    kr::FemModel model(kr::box_hex_mesh(Eigen::Vector3d::Zero(), {length, side, side}, {20, 2, 2}),
                       {rubber});
    const auto end_face = [&](double x) {
      return kr::vertices_in_box(
          model.mesh().vertices,
          Eigen::AlignedBox3d(Eigen::Vector3d(x - 1e-9, -1, -1), Eigen::Vector3d(x + 1e-9, 1, 1)));
    };
    const std::vector<int> clamped = end_face(0.0);
    const std::vector<int> tip = end_face(length);
    std::cout << "beam: " << model.mesh().num_vertices() << " vertices, "
              << model.mesh().num_elements() << " hexahedra, " << clamped.size() << " clamped\n";

    // Rubber beam: EI = 8.3 N·m², so a 10 N tip load bends it by about a third of its length
    // (linear theory would say 0.4 m): well into the nonlinear range.
    std::filesystem::path load_file = "sketch_basis_tour_loads.csv";
    if (argc > 1) {
      load_file = argv[1];
    } else {
      kr::write_force_loads(load_file, recorded_drags(tip, 10.0));
    }
    const std::vector<kr::ForceLoad> loads =
        kr::read_force_loads(load_file, model.mesh().num_vertices());
    std::cout << "read " << loads.size() << " recorded loads from " << load_file << "\n";

    kr::SketchBasisOptions options;
    options.force_separation = 1.0;          // N; a 10 N tip load has norm 10/√9 here
    options.deformation_separation = 0.005;  // m·√kg; the beam weighs 11 kg
    options.static_solve.load_steps = 10;
    // Plain Newton: on this bending problem the residual-norm line search cuts nearly every
    // step and Newton crawls (a 3.5 N load failed to converge in 50 iterations of its first
    // load step with it, and took 39 iterations in all without it).
    options.static_solve.line_search = false;
    options.basis_size = r;
    options.progress = khz::examples::print_progress;
    const auto start = std::chrono::steady_clock::now();
    kr::SketchReport report;
    const kr::Basis basis = kr::sketch_basis(model, clamped, loads, options, report);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    int iterations = 0;
    for (int count : report.static_iterations) iterations += std::max(count, 0);
    std::cout << basis.recipe << "\n  " << report.selected_loads.size() << " static solves ("
              << iterations << " Newton iterations), " << report.failures.size() << " failed, "
              << std::setprecision(3) << seconds << " s\n  singular values / σ₁:";
    for (Eigen::Index i = 0; i < report.singular_values.size(); ++i) {
      std::cout << " " << report.singular_values[i] / report.singular_values[0];
    }
    std::cout << "\n";

    // A load that was not sketched: 7 N pointing down at 30° from the side.
    const double a = -30.0 * std::numbers::pi / 180.0;
    const Eigen::VectorXd force =
        spread_load(tip, 7.0 * Eigen::Vector3d(0, std::cos(a), std::sin(a)))
            .to_vector(model.mesh().num_vertices());
    const kr::StaticSolution check = kr::solve_static(model, clamped, force, options.static_solve);
    const kr::SparseMatrix mass = model.mass_matrix();
    const Eigen::VectorXd& u = check.displacement;
    const Eigen::VectorXd residual = u - basis.vectors * (basis.vectors.transpose() * (mass * u));
    std::cout << "new 7 N load at -30°: the basis represents its static shape to "
              << std::setprecision(3)
              << 100.0 * std::sqrt(residual.dot(mass * residual) / u.dot(mass * u))
              << " % (relative mass-norm error)\n";

    kr::VtkFields fields;
    for (Eigen::Index i = 0; i < basis.size(); ++i) {
      fields.point_data.push_back(
          {"basis" + std::to_string(i + 1), khz::examples::per_vertex(basis.vectors.col(i))});
    }
    fields.point_data.push_back({"check_load_shape", khz::examples::per_vertex(u)});
    kr::write_volume_mesh("sketch_basis_tour.vtu", model.mesh(), fields);
    std::cout << "wrote sketch_basis_tour.vtu\n";
  } catch (const khz::reduced::Error& error) {
    std::cerr << "sketch_basis_tour: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
