// beam_reduced_vs_full: a cantilever bent far into the nonlinear range by the full FEM model and
// by its reduced model, side by side (the thesis's spoon experiment, §2.13.1, on a beam).
//
//   beam_reduced_vs_full [--out DIR] [--small] [--steps N]
//
// Clamps a 30 cm × 4 cm × 2 cm rubber strip (StVK, E = 1 MPa, ν = 0.4, ρ = 1000 kg/m³) at x = 0,
// then
//   1. builds a modal-derivative basis (k = 6 modes, mass-PCA to r = 18, §2.8.3) and the reduced
//      model (§2.6),
//   2. hangs a weight on the tip, ramped up over 0.4 s so that the tip sinks by about half the
//      length, holds it and lets go at 0.6 s, so the beam swings freely; the full model
//      (FullNewmark) and the reduced one (make_reduced_newmark()) run in lockstep with the same Δt
//      of 2 ms, both iterating Newton to the same tolerance, so that their difference is the
//      subspace's alone,
//   3. prints the tips as it goes, then the mean cost of a step in each model, the speed-up and
//      the errors,
// and writes to DIR (default ./beam_output): beam.csv (per step: time, both tips' displacement,
// the error e(t), both step times in µs), frame_<i>_<instant>.png (the full beam on the left,
// the reduced one on the right: at rest, deepest, highest after the release, at the end) and
// tip.png (the tip's displacement over time in both models). 2 s of simulated time by default;
// --small: a coarser mesh and 1.2 s, a few seconds in all (what CI runs).
//
// The tip is the mean of the x = 0.3 m face's vertices. The error is
// e(t) = ‖U q(t) − u(t)‖_M / max_s ‖u(s)‖_M, u the full displacement and M the mass matrix: a
// mass-weighted L2 distance over the volume, relative to the run's largest displacement
// (relative to ‖u(t)‖_M it would divide by zero whenever the beam swings through its rest shape).
#include "cantilever.hpp"
#include "point_array.hpp"
#include "progress_bar.hpp"

#include <khz/plot/line_plot.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reconstruction.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/render/camera.hpp>
#include <khz/render/png_file.hpp>
#include <khz/render/rasterizer.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace kr = khz::reduced;
namespace kv = khz::render;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double length = 0.3, width = 0.04, thickness = 0.02;  // m
constexpr double tip_weight = 0.4;                              // N, along −z
constexpr double ramp_time = 0.4, release_time = 0.6;           // s
constexpr double time_step = 2e-3;                              // s
constexpr int basis_modes = 6, basis_size = 18;
// Newton to convergence in both models: one iteration would add the semi-implicit step's own
// error (about 10 % on a beam, docs/REDUCED_MODELS.md) to the subspace's.
constexpr int newton_iterations = 10;
constexpr double newton_tolerance = 1e-6;

const kv::Color full_color{60, 110, 210}, reduced_color{235, 125, 35};

// The tip load's share at time t: a smooth ramp (no jolt), held, then let go at once.
double load_fraction(double t) {
  if (t >= release_time) return 0.0;
  const double s = std::min(t / ramp_time, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

double microseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

// The clamped beam, meshed with cells.x() × cells.y() × cells.z() hexahedra.
struct Beam {
  kr::FemModel fem;
  std::vector<int> clamped, tip;
};

Beam make_beam(const Eigen::Vector3i& cells) {
  kr::FemModel fem(kr::box_hex_mesh(Eigen::Vector3d::Zero(), {length, width, thickness}, cells),
                   {kr::Material::stvk(1e6, 0.4, 1000.0)});  // rubber: Pa, –, kg/m³
  std::vector<int> clamped = khz::examples::vertices_at_x(fem.mesh().vertices, 0.0);
  std::vector<int> tip = khz::examples::vertices_at_x(fem.mesh().vertices, length);
  return {std::move(fem), std::move(clamped), std::move(tip)};
}

kr::ReducedModel make_reduced_model(const Beam& beam) {
  kr::ModalDerivativeBasisOptions basis_options;
  basis_options.modes.num_modes = basis_modes;
  basis_options.basis_size = basis_size;
  basis_options.progress = khz::examples::print_progress;
  kr::ReducedModelOptions model_options;
  model_options.progress = khz::examples::print_progress;
  return kr::ReducedModel::precompute(
      beam.fem, kr::modal_derivative_basis(beam.fem, beam.clamped, basis_options), model_options);
}

// One step of both models: one row of beam.csv.
struct Sample {
  double time = 0;                        // s
  Eigen::Vector3d tip_full, tip_reduced;  // m
  double error = 0;                       // e(t)
  double full_us = 0, reduced_us = 0;
};

// Both models' displacements (3n, m) at one instant, to draw.
struct Snapshot {
  std::string name;
  double time = 0;
  Eigen::VectorXd full, reduced;
};

struct Run {
  std::vector<Sample> samples;
  std::vector<Snapshot> snapshots;  // rest, deepest, highest after the release, end
  double full_iterations = 0, reduced_iterations = 0;  // Newton iterations, all steps
  int full_unconverged = 0, reduced_unconverged = 0;   // steps stopped at the iteration limit
};

// Both models in lockstep under the same load, `steps` steps from rest.
Run simulate(const Beam& beam, const kr::ReducedModel& model, int steps) {
  kr::NewmarkParameters newmark;
  newmark.time_step = time_step;
  kr::FullNewmarkOptions full_options;
  full_options.newmark = newmark;
  full_options.max_newton_iterations = newton_iterations;
  full_options.tolerance = newton_tolerance;
  kr::FullNewmark full(beam.fem, beam.clamped, full_options);
  kr::ReducedNewmarkOptions reduced_options;
  reduced_options.newmark = newmark;
  reduced_options.max_newton_iterations = newton_iterations;
  reduced_options.tolerance = newton_tolerance;
  kr::PolynomialForces forces(model.energy_polynomial());
  const auto reduced = kr::make_reduced_newmark(forces, model.mass(), reduced_options);

  const Eigen::MatrixXd& U = model.basis().vectors;
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(beam.fem.num_dofs());
  for (int v : beam.tip) weight(3 * v + 2) = -tip_weight / static_cast<double>(beam.tip.size());
  const Eigen::VectorXd reduced_weight = U.transpose() * weight;  // f̃ = Uᵀf
  const Eigen::MatrixXd tip_modes = khz::examples::vertex_mean(U, beam.tip);
  const kr::SparseMatrix mass = beam.fem.mass_matrix();
  const double total_mass = mass.sum() / 3.0;  // each vertex's mass appears once per axis

  Run run;
  run.samples.reserve(static_cast<std::size_t>(steps));
  const Eigen::VectorXd at_rest = Eigen::VectorXd::Zero(beam.fem.num_dofs());
  run.snapshots.push_back({"rest", 0.0, at_rest, at_rest});
  Snapshot deepest{"deepest", 0.0, at_rest, at_rest}, highest{"highest", 0.0, at_rest, at_rest};
  Eigen::VectorXd u_reduced(beam.fem.num_dofs()), reduced_force(U.cols());
  double largest_norm = 0;
  for (int step = 0; step < steps; ++step) {
    Sample& s = run.samples.emplace_back();
    s.time = (step + 1) * time_step;
    const double share = load_fraction(s.time);
    auto begin = Clock::now();
    const kr::StepReport full_report = full.step(share * weight);
    s.full_us = microseconds_since(begin);
    reduced_force = share * reduced_weight;
    begin = Clock::now();
    const kr::ReducedStepReport reduced_report = reduced->step(reduced_force);
    s.reduced_us = microseconds_since(begin);
    if (reduced_report.status == kr::ReducedStepStatus::failed) {
      throw kr::SolverError("reduced step " + std::to_string(step) + " failed");
    }
    run.full_iterations += full_report.iterations;
    run.reduced_iterations += reduced_report.iterations;
    run.full_unconverged += !full_report.converged;
    run.reduced_unconverged += reduced_report.status != kr::ReducedStepStatus::converged;

    const Eigen::VectorXd& u = full.displacement();
    kr::reconstruct_displacement(U, reduced->coordinates(), u_reduced);
    const Eigen::VectorXd difference = u_reduced - u;
    s.error = std::sqrt(difference.dot(mass * difference));  // normalized after the run
    largest_norm = std::max(largest_norm, std::sqrt(u.dot(mass * u)));
    s.tip_full = khz::examples::vertex_mean(u, beam.tip);
    s.tip_reduced = tip_modes * reduced->coordinates();

    if (s.tip_full.z() < khz::examples::vertex_mean(deepest.full, beam.tip)(2)) {
      deepest = {"deepest", s.time, u, u_reduced};
    }
    if (s.time > release_time &&
        s.tip_full.z() > khz::examples::vertex_mean(highest.full, beam.tip)(2)) {
      highest = {"highest", s.time, u, u_reduced};
    }
    if ((step + 1) % std::max(steps / 10, 1) == 0) {
      // ‖·‖_M / √(total mass): the mass-weighted RMS over the volume, in metres.
      std::cout << std::right << std::fixed << std::setprecision(2) << "  t = " << s.time
                << " s: tip z full " << std::setprecision(1) << std::setw(6) << 1e3 * s.tip_full.z()
                << " mm, reduced " << std::setw(6) << 1e3 * s.tip_reduced.z()
                << " mm; RMS difference " << std::setprecision(2)
                << 1e3 * s.error / std::sqrt(total_mass) << " mm\n"
                << std::defaultfloat;
    }
  }
  for (Sample& s : run.samples) s.error /= largest_norm;
  for (Snapshot* snapshot : {&deepest, &highest}) {
    if (snapshot->time > 0) run.snapshots.push_back(std::move(*snapshot));
  }
  run.snapshots.push_back({"end", run.samples.back().time, full.displacement(), u_reduced});
  return run;
}

// Costs, deflection and errors, from the samples.
void print_summary(const Run& run) {
  double full_us = 0, reduced_us = 0, largest_tip = 0, error_sum = 0;
  double tip_error_squares = 0, tip_squares = 0;
  const Sample* worst = &run.samples.front();
  for (const Sample& s : run.samples) {
    full_us += s.full_us;
    reduced_us += s.reduced_us;
    largest_tip = std::max(largest_tip, s.tip_full.norm());
    error_sum += s.error;
    if (s.error > worst->error) worst = &s;
    tip_error_squares += (s.tip_reduced - s.tip_full).squaredNorm();
    tip_squares += s.tip_full.squaredNorm();
  }
  const auto n = static_cast<double>(run.samples.size());
  std::cout << std::fixed << std::setprecision(1) << "per step: full " << full_us / n << " µs ("
            << run.full_iterations / n << " Newton iterations), reduced " << reduced_us / n
            << " µs (" << run.reduced_iterations / n << "): speed-up " << std::setprecision(0)
            << full_us / reduced_us << "×\n"
            << std::setprecision(1) << "largest tip displacement (full): " << 1e3 * largest_tip
            << " mm, " << 100 * largest_tip / length << " % of the length\n"
            << std::setprecision(2) << "error e(t) = ‖Uq − u‖_M / max ‖u‖_M: max "
            << 100 * worst->error << " % (t = " << worst->time << " s), mean "
            << 100 * error_sum / n << " %\n"
            << "tip trajectory error (relative L2 over the run): "
            << 100 * std::sqrt(tip_error_squares / tip_squares) << " %\n"
            << std::defaultfloat;
  if (run.full_unconverged + run.reduced_unconverged > 0) {
    std::cout << "note: steps stopped at " << newton_iterations
              << " Newton iterations before the tolerance: full " << run.full_unconverged
              << ", reduced " << run.reduced_unconverged << "\n";
  }
}

// The surface to draw: the faces of the hexahedra that belong to one element only (a face
// shared by two lies inside), two triangles each, counter-clockwise seen from outside.
kr::TriangleMatrix boundary_triangles(const kr::VolumeMesh& hexahedra) {
  // A VTK hexahedron's faces, counter-clockwise seen from outside.
  static constexpr std::array<std::array<int, 4>, 6> faces{
      {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
  std::map<std::array<int, 4>, std::array<int, 4>> boundary;  // sorted nodes → face
  for (Eigen::Index e = 0; e < hexahedra.num_elements(); ++e) {
    for (const std::array<int, 4>& face : faces) {
      std::array<int, 4> nodes{};
      for (int i = 0; i < 4; ++i) nodes[i] = hexahedra.elements(e, face[i]);
      std::array<int, 4> key = nodes;
      std::ranges::sort(key);
      // The second element with this face makes it an inner one.
      if (const auto [at, inserted] = boundary.try_emplace(key, nodes); !inserted) {
        boundary.erase(at);
      }
    }
  }
  kr::TriangleMatrix triangles(2 * static_cast<Eigen::Index>(boundary.size()), 3);
  Eigen::Index t = 0;
  for (const auto& [key, n] : boundary) {
    triangles.row(t++) << n[0], n[1], n[2];
    triangles.row(t++) << n[0], n[2], n[3];
  }
  return triangles;
}

// A camera that sees the beam from the side and a little from above, framing every pose drawn
// so that all frames share it and compare pixel for pixel.
kv::Camera frame_camera(const kr::VertexMatrix& rest, const std::vector<Snapshot>& snapshots) {
  Eigen::AlignedBox3d box;
  for (const Snapshot& snapshot : snapshots) {
    for (const Eigen::VectorXd* u : {&snapshot.full, &snapshot.reduced}) {
      const kr::VertexMatrix x = rest + khz::examples::per_vertex(*u);
      box.extend(x.colwise().minCoeff().transpose());
      box.extend(x.colwise().maxCoeff().transpose());
    }
  }
  return kv::frame_box(box, {-0.4, 1.0, -0.45}, Eigen::Vector3d::UnitZ(), std::numbers::pi / 6, 640,
                       480, 0.08);
}

// One instant as a PNG: the full beam in the left half, the reduced one in the right, both seen
// by `camera`, next to a grey plate standing for the clamp.
void write_frame(const fs::path& file, const kv::Camera& camera, const kr::VertexMatrix& rest,
                 const kr::TriangleMatrix& surface, const Snapshot& snapshot) {
  kr::VertexMatrix plate(4, 3);
  plate.row(0) << 0, -width, -2 * thickness;
  plate.row(1) << 0, 2 * width, -2 * thickness;
  plate.row(2) << 0, 2 * width, 3 * thickness;
  plate.row(3) << 0, -width, 3 * thickness;
  const kr::TriangleMatrix plate_triangles{{0, 1, 2}, {0, 2, 3}};
  kv::Image frame(2 * camera.width(), camera.height());
  const std::array<std::pair<const Eigen::VectorXd*, kv::Color>, 2> halves{
      {{&snapshot.full, full_color}, {&snapshot.reduced, reduced_color}}};
  for (int half = 0; half < 2; ++half) {
    kv::Rasterizer rasterizer(camera);
    const kr::VertexMatrix x = rest + khz::examples::per_vertex(*halves[half].first);
    rasterizer.draw_mesh(x, surface, {halves[half].second});
    rasterizer.draw_mesh(plate, plate_triangles, {{200, 200, 200}});
    for (int y = 0; y < camera.height(); ++y) {
      for (int column = 0; column < camera.width(); ++column) {
        frame.set_pixel(half * camera.width() + column, y, rasterizer.image().pixel(column, y));
      }
    }
  }
  kv::write_png(frame, file);
}

void write_csv(const fs::path& file, const std::vector<Sample>& samples) {
  std::ofstream out(file);
  out << "time,tip_full_x,tip_full_y,tip_full_z,tip_reduced_x,tip_reduced_y,tip_reduced_z,"
         "relative_error,full_us,reduced_us\n";
  out << std::setprecision(9);
  for (const Sample& s : samples) {
    out << s.time << ',' << s.tip_full.x() << ',' << s.tip_full.y() << ',' << s.tip_full.z() << ','
        << s.tip_reduced.x() << ',' << s.tip_reduced.y() << ',' << s.tip_reduced.z() << ','
        << s.error << ',' << s.full_us << ',' << s.reduced_us << '\n';
  }
  if (!out) throw kr::IoError(file.string() + ": cannot write");
}

// The tip's vertical (z) and axial (x) displacement over time in both models, in mm.
void write_tip_plot(const fs::path& file, const std::vector<Sample>& samples, Eigen::Index r) {
  std::vector<khz::plot::Series> series{{"full z", {}, {}, full_color, false},
                                        {"reduced z", {}, {}, reduced_color, false},
                                        {"full x", {}, {}, {150, 180, 235}, false},
                                        {"reduced x", {}, {}, {245, 190, 140}, false}};
  for (const Sample& s : samples) {
    const std::array<double, 4> values{s.tip_full.z(), s.tip_reduced.z(), s.tip_full.x(),
                                       s.tip_reduced.x()};
    for (std::size_t i = 0; i < series.size(); ++i) {
      series[i].x.push_back(s.time);
      series[i].y.push_back(1e3 * values[i]);
    }
  }
  khz::plot::PlotOptions options;
  options.title = "Cantilever tip: full FEM vs reduced (r = " + std::to_string(r) + ")";
  options.x_label = "time (s)";
  options.y_label = "tip displacement (mm)";
  khz::plot::write_line_plot(file, options, series);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"A large-deformation cantilever: full FEM and reduced model side by side",
               "beam_reduced_vs_full"};
  fs::path out = "beam_output";
  bool small = false;
  int steps = 0;
  app.add_option("--out", out, "directory for beam.csv and the PNG files (default: beam_output)");
  app.add_flag("--small", small, "coarser mesh and shorter run, a few seconds (what CI runs)");
  app.add_option("--steps", steps, "time steps of 2 ms (default: 1000, with --small 600)")
      ->check(CLI::Range(1, 10'000'000));
  CLI11_PARSE(app, argc, argv);

  try {
    if (steps == 0) steps = small ? 600 : 1000;
    fs::create_directories(out);  // before the run, so that a bad --out fails at once
    const Eigen::Vector3i cells = small ? Eigen::Vector3i(20, 3, 2) : Eigen::Vector3i(30, 4, 2);
    const Beam beam = make_beam(cells);
    std::cout << "beam: " << cells.x() << "×" << cells.y() << "×" << cells.z() << " hexahedra, "
              << beam.fem.mesh().num_vertices() << " vertices (" << beam.fem.num_dofs()
              << " dofs), " << beam.clamped.size() << " clamped\n";

    const auto start = Clock::now();
    const kr::ReducedModel model = make_reduced_model(beam);
    std::cout << "reduced model: k = " << basis_modes << " modes → r = " << model.dimension()
              << ", prepared in " << std::setprecision(3) << 1e-6 * microseconds_since(start)
              << " s\n"
              << "run: " << steps << " steps of " << 1e3 * time_step << " ms; " << tip_weight
              << " N on the tip, ramped up over " << ramp_time << " s, let go at " << release_time
              << " s\n";
    const Run run = simulate(beam, model, steps);
    print_summary(run);

    write_csv(out / "beam.csv", run.samples);
    write_tip_plot(out / "tip.png", run.samples, model.dimension());
    const kr::VertexMatrix& rest = beam.fem.mesh().vertices;
    const kv::Camera camera = frame_camera(rest, run.snapshots);
    const kr::TriangleMatrix surface = boundary_triangles(beam.fem.mesh());
    for (std::size_t i = 0; i < run.snapshots.size(); ++i) {
      const Snapshot& snapshot = run.snapshots[i];
      const fs::path file = out / ("frame_" + std::to_string(i) + "_" + snapshot.name + ".png");
      write_frame(file, camera, rest, surface, snapshot);
      std::cout << "wrote " << file.string() << " (t = " << snapshot.time << " s)\n";
    }
    std::cout << "wrote " << (out / "beam.csv").string() << " and " << (out / "tip.png").string()
              << "\n";
  } catch (const std::exception& error) {
    std::cerr << "beam_reduced_vs_full: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
