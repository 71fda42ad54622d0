// The C++ side of the Python tests' bit-for-bit comparisons: each command does in C++ what a test
// does from Python, on the same inputs, and writes what it got to files the test compares.
//
//   khz_python_reference report MESH
//       prints analyze_mesh(MESH) as `khz info` does
//   khz_python_reference repair MESH WELD_TOLERANCE OUT_MESH
//       repair_mesh() with that weld tolerance (other options default), written to OUT_MESH
//   khz_python_reference field MESH CELLS POINTS OUT
//       the signed field of MESH at CELLS cells, written to OUT.khzsdf, and its
//       distance_and_gradient() at POINTS (raw float64, N×3 rows) to OUT.distance (N float64)
//       and OUT.gradient (N×3 float64)
//   khz_python_reference query FIELD_MESH CELLS SHELL_MESH POSES OUT
//       the vertex pointshell of SHELL_MESH queried with default ContactOptions against the
//       signed field of FIELD_MESH at CELLS cells, once per pose of POSES (raw float64, 4×4
//       row-major each), about the pose's origin: force and torque, 6 float64 per pose, to OUT
//   khz_python_reference beam OUT
//       the beam of test_reduced.py (box_hex_mesh 0.3 × 0.04 × 0.02 m in 15×2×2 cells, StVK
//       1 MPa, ν = 0.4, 1000 kg/m³, clamped at x = 0): at u_j = 1e-3 sin(j) (written to OUT.at) its
//       R(u) to OUT.R, K(u)'s compressed-column values to OUT.K and E(u) to OUT.E; its
//       modal-derivative basis (4 modes, r = 8) to OUT.npy; the reduced model to OUT.khzmodel; 40
//       reduced Newmark steps (Δt 2 ms, 10 Newton iterations, tolerance 1e-6) under 0.2 N down on
//       the x = 0.3 m vertices, q after each to OUT.q; 5 full Newmark steps under the same load, u
//       to OUT.u
//   khz_python_reference scene SCENE CACHE CYCLES OUT
//       SCENE prepared with the cache directory CACHE and run with its own devices for CYCLES
//       cycles in simulated time (as kilohertz.scene.SceneRuntime.run() does); per cycle of hand
//       0 its contact force and simulation position, 6 float64, written to OUT

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/io/basis_export.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>

#include <cmath>

#include <exception>
#include <fstream>
#include <iostream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

namespace {

std::vector<double> read_doubles(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<double> values(bytes.size() / sizeof(double));
  std::copy(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(values.size() * 8),
            reinterpret_cast<char*>(values.data()));
  return values;
}

void write_doubles(const std::string& file, std::span<const double> values) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size_bytes()));
}

int field(const std::string& mesh_file, int cells, const std::string& points_file,
          const std::string& out) {
  const auto mesh = khz::reduced::read_triangle_mesh(mesh_file);
  khz::contact::DistanceFieldOptions options;
  options.cells = cells;
  const auto grid = khz::contact::signed_distance_field(mesh, options);
  khz::contact::write_distance_field(out + ".khzsdf", grid);
  const std::vector<double> points = read_doubles(points_file);
  std::vector<double> distances, gradients;
  for (std::size_t i = 0; i + 2 < points.size(); i += 3) {
    Eigen::Vector3d gradient;
    distances.push_back(
        grid.distance_and_gradient({points[i], points[i + 1], points[i + 2]}, gradient));
    gradients.insert(gradients.end(), gradient.data(), gradient.data() + 3);
  }
  write_doubles(out + ".distance", distances);
  write_doubles(out + ".gradient", gradients);
  return 0;
}

int query(const std::string& field_mesh, int cells, const std::string& shell_mesh,
          const std::string& poses_file, const std::string& out) {
  namespace kc = khz::contact;
  kc::DistanceFieldOptions options;
  options.cells = cells;
  const auto field =
      kc::signed_distance_field(khz::reduced::read_triangle_mesh(field_mesh), options);
  const kc::PointTree tree(kc::vertex_pointshell(khz::reduced::read_triangle_mesh(shell_mesh)));
  kc::ContactWorkspace workspace(tree, kc::ContactOptions{});
  const std::vector<double> poses = read_doubles(poses_file);
  std::vector<double> rows;
  for (std::size_t i = 0; i + 15 < poses.size(); i += 16) {
    const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> m(poses.data() + i);
    kc::ContactFrames frames;
    frames.pointshell.matrix() = m;
    frames.grasp_point = frames.pointshell.translation();
    kc::query_contact(tree, field, frames, workspace);
    const auto& r = workspace.result();
    rows.insert(rows.end(), r.force.data(), r.force.data() + 3);
    rows.insert(rows.end(), r.torque.data(), r.torque.data() + 3);
  }
  write_doubles(out, rows);
  return 0;
}

int beam(const std::string& out) {
  namespace kr = khz::reduced;
  const kr::FemModel fem(kr::box_hex_mesh(Eigen::Vector3d::Zero(), {0.3, 0.04, 0.02}, {15, 2, 2}),
                         {kr::Material::stvk(1e6, 0.4, 1000.0)});
  const auto& x = fem.mesh().vertices;
  std::vector<int> clamped, tip;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (x(v, 0) == 0.0) clamped.push_back(static_cast<int>(v));
    if (std::abs(x(v, 0) - 0.3) < 1e-12) tip.push_back(static_cast<int>(v));
  }
  Eigen::VectorXd u(fem.num_dofs());
  for (Eigen::Index j = 0; j < u.size(); ++j) u(j) = 1e-3 * std::sin(static_cast<double>(j));
  write_doubles(out + ".at", {u.data(), static_cast<std::size_t>(u.size())});
  Eigen::VectorXd forces;
  fem.internal_forces(u, forces);
  write_doubles(out + ".R", {forces.data(), static_cast<std::size_t>(forces.size())});
  kr::SparseMatrix stiffness = fem.stiffness_pattern();
  fem.tangent_stiffness(u, stiffness);
  write_doubles(out + ".K", {stiffness.valuePtr(), static_cast<std::size_t>(stiffness.nonZeros())});
  const double energy = fem.strain_energy(u);
  write_doubles(out + ".E", {&energy, 1});

  kr::ModalDerivativeBasisOptions basis_options;
  basis_options.modes.num_modes = 4;
  basis_options.basis_size = 8;
  const auto model =
      kr::ReducedModel::precompute(fem, kr::modal_derivative_basis(fem, clamped, basis_options));
  kr::write_basis_npy(out + ".npy", model.basis());
  kr::write_reduced_model(out + ".khzmodel", model, fem.mesh());

  Eigen::VectorXd load = Eigen::VectorXd::Zero(fem.num_dofs());
  for (int v : tip) load(3 * v + 2) = -0.2 / static_cast<double>(tip.size());
  auto options = model.defaults().newmark_options();
  options.newmark.time_step = 2e-3;
  options.max_newton_iterations = 10;
  options.tolerance = 1e-6;
  kr::PolynomialForces polynomial(model.energy_polynomial());
  const auto integrator = kr::make_reduced_newmark(polynomial, model.mass(), options);
  const Eigen::VectorXd reduced_load = model.basis().vectors.transpose() * load;
  std::vector<double> q;
  for (int step = 0; step < 40; ++step) {
    integrator->step(reduced_load);
    q.insert(q.end(), integrator->coordinates().data(),
             integrator->coordinates().data() + integrator->coordinates().size());
  }
  write_doubles(out + ".q", q);
  kr::FullNewmarkOptions full_options;
  full_options.newmark.time_step = 2e-3;
  full_options.tolerance = 1e-6;
  kr::FullNewmark full(fem, clamped, full_options);
  for (int step = 0; step < 5; ++step) full.step(load);
  write_doubles(out + ".u",
                {full.displacement().data(), static_cast<std::size_t>(full.displacement().size())});
  return 0;
}

int run_scene(const std::string& scene_file, const std::string& cache_directory, int cycles,
              const std::string& out) {
  khz::scene::ProductCache cache(cache_directory);
  const auto prepared = khz::scene::prepare_scene(khz::scene::read_scene(scene_file), cache);
  khz::scene::SceneRuntime runtime(prepared);
  runtime.open_devices();
  auto& world = runtime.world();
  const double period = 1.0 / prepared.description.loop.rate_hz;
  std::vector<double> rows;
  for (int i = 0; i < cycles; ++i) {
    const double now = i * period;
    const auto& record = world.cycle(now, now + period, [now] { return now; })[0];
    rows.insert(rows.end(), record.contact.force.data(), record.contact.force.data() + 3);
    rows.insert(rows.end(), record.simulation.position.data(),
                record.simulation.position.data() + 3);
  }
  runtime.close_devices();
  write_doubles(out, rows);
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 2 && args[0] == "report") {
    std::cout << khz::reduced::analyze_mesh(khz::reduced::read_triangle_mesh(args[1]));
    return 0;
  }
  if (args.size() == 4 && args[0] == "repair") {
    auto mesh = khz::reduced::read_triangle_mesh(args[1]);
    khz::reduced::repair_mesh(mesh, {.weld_tolerance = std::stod(args[2])});
    khz::reduced::write_triangle_mesh(args[3], mesh);
    return 0;
  }
  if (args.size() == 2 && args[0] == "beam") return beam(args[1]);
  if (args.size() == 6 && args[0] == "query") {
    return query(args[1], std::stoi(args[2]), args[3], args[4], args[5]);
  }
  if (args.size() == 5 && args[0] == "scene") {
    return run_scene(args[1], args[2], std::stoi(args[3]), args[4]);
  }
  if (args.size() == 5 && args[0] == "field")
    return field(args[1], std::stoi(args[2]), args[3], args[4]);
  std::cerr << "usage: see the comment at the top of tests/python/reference.cpp\n";
  return 2;
} catch (const std::exception& error) {
  std::cerr << "khz_python_reference: " << error.what() << '\n';
  return 1;
}
