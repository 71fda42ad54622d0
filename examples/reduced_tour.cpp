// reduced_tour: a reduced nonlinear model from basis to time steps (thesis §2.6–§2.12).
//
//   reduced_tour [BASIS_SIZE]
//
// Default r = 15. Clamps a 1 m rubber beam, then
//   1. builds a modal-derivative basis (k = 6 modes) and precomputes the reduced energy
//      polynomials (the exact reduced StVK forces, §2.6),
//   2. saves them as reduced_tour.khzmodel and loads the file back, without the mesh, as a
//      haptic program would,
//   3. swings the beam with a short tip impulse (implicit Newmark, one Newton iteration per
//      step, §2.9) and prints the tip's motion and the cost per step,
//   4. stiffens the material at runtime (λ, μ × 4, §2.11) and swings it again: the same impulse
//      now moves the tip about half as far,
// and writes reduced_tour.vtu, the beam at its largest deflection, for ParaView.
#include "cantilever.hpp"
#include "point_array.hpp"
#include "progress_bar.hpp"

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reconstruction.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/reduced/subspace/reduced_point_forces.hpp>

#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <vector>

namespace {

namespace kr = khz::reduced;
using Clock = std::chrono::steady_clock;

// Swings the beam: a tip force for 20 ms, then free motion up to 1 s (the first bending period
// is about 2 s at E = 1 MPa). Returns the coordinates at
// the largest tip deflection.
Eigen::VectorXd swing(kr::ReducedIntegrator& integrator, const Eigen::VectorXd& impulse_force,
                      const Eigen::MatrixXd& tip_modes) {
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(impulse_force.size());
  Eigen::VectorXd largest = integrator.coordinates();
  double stepping = 0, deepest = 0;
  const int steps = 1000;
  for (int step = 0; step < steps; ++step) {
    const auto start = Clock::now();
    const kr::ReducedStepReport report = integrator.step(step < 20 ? impulse_force : none);
    stepping += std::chrono::duration<double>(Clock::now() - start).count();
    if (report.status == kr::ReducedStepStatus::failed) {
      throw kr::SolverError("step " + std::to_string(step) + " failed");
    }
    const double tip = (tip_modes * integrator.coordinates()).norm();
    if (tip > deepest) {
      deepest = tip;
      largest = integrator.coordinates();
    }
    if (step % 100 == 99) {
      std::cout << std::fixed << std::setprecision(0) << "  t = " << std::setw(4)
                << 1e3 * integrator.time() << " ms: tip moved " << std::setprecision(1)
                << std::setw(6) << 1e3 * tip << " mm\n";
    }
  }
  std::cout << "  largest tip deflection " << 1e3 * deepest << " mm; " << std::setprecision(2)
            << 1e6 * stepping / steps << " µs per step\n"
            << std::defaultfloat;
  return largest;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const int r = argc > 1 ? std::atoi(argv[1]) : 15;
    const double length = 1.0, side = 0.1;
    const kr::FemModel fem(
        kr::box_hex_mesh(Eigen::Vector3d::Zero(), {length, side, side}, {40, 4, 4}),
        {kr::Material::stvk(1e6, 0.45, 1100.0)});  // rubber: Pa, –, kg/m³
    const std::vector<int> clamped = khz::examples::vertices_at_x(fem.mesh().vertices, 0.0);
    const std::vector<int> tip = khz::examples::vertices_at_x(fem.mesh().vertices, length);

    auto start = Clock::now();
    kr::ModalDerivativeBasisOptions basis_options;
    basis_options.modes.num_modes = 6;
    basis_options.basis_size = r;
    basis_options.progress = khz::examples::print_progress;
    kr::Basis basis = kr::modal_derivative_basis(fem, clamped, basis_options);
    kr::ReducedModelOptions model_options;
    model_options.progress = khz::examples::print_progress;
    const kr::ReducedModel prepared = kr::ReducedModel::precompute(fem, basis, model_options);
    std::cout << "reduced model: r = " << r << ", prepared in " << std::setprecision(3)
              << std::chrono::duration<double>(Clock::now() - start).count() << " s\n";

    kr::write_reduced_model("reduced_tour.khzmodel", prepared, fem.mesh());
    kr::ReducedModel model = kr::read_reduced_model("reduced_tour.khzmodel");
    std::cout << "saved and reloaded reduced_tour.khzmodel\n";

    // The impulse: 150 N along −z spread over the tip, projected into the basis (f̃ = Uᵀf,
    // reading only the tip's rows of U).
    std::vector<kr::PointForce> impulse;
    for (int v : tip) impulse.push_back({v, {0.0, 0.0, -150.0 / static_cast<double>(tip.size())}});
    Eigen::VectorXd reduced_force(r);
    kr::reduced_point_forces(model.basis().vectors, impulse, reduced_force);
    const Eigen::MatrixXd tip_modes = khz::examples::vertex_mean(model.basis().vectors, tip);

    kr::PolynomialForces forces(model.energy_polynomial());
    // The integrator settings the model file carries (Δt, Newmark, damping, Newton).
    const auto integrator =
        kr::make_reduced_newmark(forces, model.mass(), model.defaults().newmark_options());
    std::cout << "swing 1 (E = 1 MPa):\n";
    const Eigen::VectorXd deepest = swing(*integrator, reduced_force, tip_modes);

    const kr::LameParameters lame = model.groups()[0].material.lame();
    model.set_lame(0, {4 * lame.lambda, 4 * lame.mu});
    forces.set_polynomial(model.energy_polynomial());
    integrator->set_state(Eigen::VectorXd::Zero(r), Eigen::VectorXd::Zero(r),
                          Eigen::VectorXd::Zero(r));
    std::cout << "swing 2 (E = 4 MPa, changed at runtime):\n";
    swing(*integrator, reduced_force, tip_modes);

    Eigen::VectorXd u(fem.num_dofs());
    kr::reconstruct_displacement(model.basis().vectors, deepest, u);
    kr::VtkFields fields;
    fields.point_data.push_back({"displacement", khz::examples::per_vertex(u)});
    kr::write_volume_mesh("reduced_tour.vtu", fem.mesh(), fields);
    std::cout << "wrote reduced_tour.vtu (warp by 'displacement' in ParaView)\n";
  } catch (const kr::Error& error) {
    std::cerr << "reduced_tour: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
