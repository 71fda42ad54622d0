// Speed against error: the same dynamic scenarios in the full FEM model and in reduced models with
// modal-derivative bases of growing size r (thesis §2.13.2). For each r one table row: what the
// reduced model costs to prepare and to step (median time per step; the full model's likewise),
// how much faster it runs than the full model, and
// how far its trajectory strays from the full one. Writes speed_against_error.csv and .png, and
// the tracked vertex's trajectories in speed_against_error_trajectories.csv.
//
//   speed_against_error [--scenario beam|dino|all] [--ranks 5,10,...] [--output DIR]
//
// (a) beam: a clamped hexahedral cantilever under a short tip impulse deep into the nonlinear
//     range; (b) dino: CGAL's dino.off tetrahedralized (~11k tetrahedra), anchored at its feet,
//     pulled sideways at the head for a short time. Both then swing freely (no damping), so the
//     first period measures the nonlinear frequency each model predicts.

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include <plplot/plplot.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace khz::reduced;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The median of per-step times: robust to the odd interrupt or page fault, which at a few
// microseconds per step would otherwise dominate a mean over a few hundred steps.
double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// A dynamic test: a load spread over `loaded` vertices for the first `load_duration` seconds,
// then free motion. The trajectory of `tracked` is compared.
struct Scenario {
  std::string name;
  FemModel model;
  std::vector<int> fixed;
  std::vector<int> loaded;
  int tracked = -1;
  Eigen::Vector3d force;  // total (N)
  double load_duration = 0.0;
  double time_step = 1e-3;
  int steps = 0;

  Eigen::VectorXd load() const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
    for (int v : loaded) f.segment<3>(3 * v) = force / static_cast<double>(loaded.size());
    return f;
  }
  bool loaded_at(int step) const { return (step + 1) * time_step <= load_duration + 1e-12; }
};

// 0.4 m × 4 cm × 4 cm rubber-like beam, 50×5×5 hexahedra, first bending mode ≈ 5 Hz.
Scenario beam_scenario() {
  const double length = 0.4, side = 0.04;
  FemModel model(box_hex_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(length, side, side),
                              Eigen::Vector3i(50, 5, 5)),
                 {Material::stvk(1.5e7, 0.45, 1000.0)});
  const auto face = [&](double x) {
    const double eps = 1e-9;
    return vertices_in_box(model.mesh().vertices,
                           Eigen::AlignedBox3d(Eigen::Vector3d(x - eps, -eps, -eps),
                                               Eigen::Vector3d(x + eps, side + eps, side + eps)));
  };
  std::vector<int> clamped = face(0.0), tip = face(length);
  Scenario s{"beam",
             std::move(model),
             std::move(clamped),
             std::move(tip),
             -1,
             Eigen::Vector3d(0.0, 30.0, 0.0),
             0.02,
             1e-3,
             500};
  s.tracked = s.loaded[s.loaded.size() / 2];
  return s;
}

std::filesystem::path dino_file() { return std::filesystem::path(KHZ_CGAL_MESH_DIR) / "dino.off"; }

// dino.off (≈ 4 units long; read as metres) tetrahedralized to ~11k elements; feet: the
// vertices below y = −0.45; head: the vertices within 0.2 of the highest point.
Scenario dino_scenario() {
  const TriangleMesh surface = read_triangle_mesh(dino_file());
  const double diagonal =
      (surface.vertices.colwise().maxCoeff() - surface.vertices.colwise().minCoeff()).norm();
  TetrahedralizeOptions options;
  options.facet_size = options.cell_size = diagonal / 50;
  options.facet_distance = diagonal / 500;
  // Stiff enough for a first mode near 2.5 Hz, so 0.6 s holds one and a half periods.
  FemModel model(tetrahedralize(surface, options), {Material::stvk(3e8, 0.4, 1000.0)});
  const VertexMatrix& x = model.mesh().vertices;
  std::vector<int> feet, head;
  Eigen::Index top = 0;
  x.col(1).maxCoeff(&top);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (x(v, 1) < -0.45) feet.push_back(static_cast<int>(v));
    if ((x.row(v) - x.row(top)).norm() < 0.2) head.push_back(static_cast<int>(v));
  }
  return Scenario{"dino",
                  std::move(model),
                  std::move(feet),
                  std::move(head),
                  static_cast<int>(top),
                  Eigen::Vector3d(4e4, 0.0, 0.0),
                  0.05,
                  1e-3,
                  600};
}

// Per step, the full displacement (3n) of the reference run.
struct FullRun {
  std::vector<Eigen::VectorXd> displacements;
  double step_seconds = 0.0;
};

FullRun run_full(const Scenario& s) {
  FullNewmarkOptions options;
  options.newmark.time_step = s.time_step;
  FullNewmark integrator(s.model, s.fixed, options);
  const Eigen::VectorXd load = s.load(), none = Eigen::VectorXd::Zero(s.model.num_dofs());
  FullRun run;
  std::vector<double> seconds;
  for (int step = 0; step < s.steps; ++step) {
    const auto start = Clock::now();
    integrator.step(s.loaded_at(step) ? load : none);
    seconds.push_back(seconds_since(start));
    run.displacements.push_back(integrator.displacement());
  }
  run.step_seconds = median(seconds);
  return run;
}

// Linear modes and derivatives are shared by every r; only the PCA depends on it.
struct DerivativeSamples {
  Eigen::MatrixXd samples;
  SparseMatrix mass;
  double seconds = 0.0;
  double first_frequency_hz = 0.0;
};

DerivativeSamples derivative_samples(const Scenario& s, int num_modes) {
  const auto start = Clock::now();
  LinearModesOptions options;
  options.num_modes = num_modes;
  const LinearModes modes = compute_linear_modes(s.model, s.fixed, options);
  const ModalDerivatives derivatives = compute_modal_derivatives(s.model, modes);
  DerivativeSamples result;
  result.mass = s.model.mass_matrix();
  result.samples = weighted_modal_samples(modes, derivatives, result.mass);
  result.seconds = seconds_since(start);
  result.first_frequency_hz = modes.frequencies_hz()[0];
  return result;
}

struct Row {
  std::string scenario;
  int r = 0;
  double basis_seconds = 0, polynomial_seconds = 0, step_us = 0, full_step_us = 0;
  double trajectory_error = 0, peak_vertex_error = 0, peak_vertex_error_relative = 0;
  double frequency_error = 0;
  // σ_r / σ_{r+1} of the PCA: near 1, the cut splits a cluster of equally important directions
  // (e.g. the y and z twins of a square beam) and drops some of them arbitrarily.
  double cut_ratio = 0;
  int failed_steps = 0;
  std::vector<Eigen::Vector3d> trajectory;  // of the tracked vertex's displacement (m)
};

// First local maximum of f after `from` that reaches half the global maximum, refined by a
// parabola through its neighbours (in steps, fractional).
std::optional<double> first_peak(const std::vector<double>& f, std::size_t from, double sign) {
  double largest = 0;
  for (double value : f) largest = std::max(largest, sign * value);
  for (std::size_t i = std::max<std::size_t>(from, 1); i + 1 < f.size(); ++i) {
    const double a = sign * f[i - 1], b = sign * f[i], c = sign * f[i + 1];
    if (b >= a && b > c && b > 0.5 * largest) {
      const double curvature = a - 2 * b + c;
      return static_cast<double>(i) + (curvature != 0 ? 0.5 * (a - c) / curvature : 0.0);
    }
  }
  return std::nullopt;
}

// Period (in steps) of a signal from its first maximum to the following minimum, doubled.
std::optional<double> first_period(const std::vector<double>& f) {
  const std::optional<double> peak = first_peak(f, 1, 1.0);
  if (!peak) return std::nullopt;
  const std::optional<double> trough = first_peak(f, static_cast<std::size_t>(*peak) + 1, -1.0);
  if (!trough) return std::nullopt;
  return 2.0 * (*trough - *peak);
}

Row run_reduced(const Scenario& s, const FullRun& full, const DerivativeSamples& samples, int r,
                int newton_iterations) {
  Row row;
  row.scenario = s.name;
  row.r = r;
  auto start = Clock::now();
  PcaOptions pca;
  pca.basis_size = r;
  PcaResult components = principal_components(samples.samples, samples.mass, pca);
  const Eigen::VectorXd& sigma = components.singular_values;
  row.cut_ratio = r < sigma.size() ? sigma[r - 1] / sigma[r] : std::nan("");
  Basis basis{std::move(components.basis), s.fixed,
              "modal derivatives, mass PCA to r=" + std::to_string(r)};
  row.basis_seconds = samples.seconds + seconds_since(start);

  start = Clock::now();
  const ReducedModel reduced = ReducedModel::precompute(s.model, basis);
  row.polynomial_seconds = seconds_since(start);

  PolynomialForces forces(reduced.energy_polynomial());
  ReducedNewmarkOptions options;
  options.newmark.time_step = s.time_step;
  options.max_newton_iterations = newton_iterations;
  const auto integrator = make_reduced_newmark(forces, reduced.mass(), options);
  const Eigen::VectorXd load = basis.vectors.transpose() * s.load();
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(r);
  std::vector<Eigen::VectorXd> coordinates;
  std::vector<double> seconds;
  for (int step = 0; step < s.steps; ++step) {
    const auto begin = Clock::now();
    const ReducedStepReport report = integrator->step(s.loaded_at(step) ? load : none);
    seconds.push_back(seconds_since(begin));
    if (report.status == ReducedStepStatus::failed) ++row.failed_steps;
    coordinates.push_back(integrator->coordinates());
  }
  row.step_us = 1e6 * median(seconds);
  row.full_step_us = 1e6 * full.step_seconds;

  // Tracked vertex: trajectory error, and its motion along the direction of the first peak.
  const Eigen::MatrixXd tracked_modes = basis.vectors.middleRows<3>(3 * s.tracked);
  double error_squares = 0, reference_squares = 0;
  std::vector<Eigen::Vector3d> reference(s.steps), simulated(s.steps);
  for (int step = 0; step < s.steps; ++step) {
    reference[step] = full.displacements[step].segment<3>(3 * s.tracked);
    simulated[step] = tracked_modes * coordinates[step];
    error_squares += (simulated[step] - reference[step]).squaredNorm();
    reference_squares += reference[step].squaredNorm();
  }
  row.trajectory_error = std::sqrt(error_squares / reference_squares);
  row.trajectory = simulated;

  std::vector<double> magnitude(s.steps);
  for (int step = 0; step < s.steps; ++step) magnitude[step] = reference[step].norm();
  const std::optional<double> peak = first_peak(magnitude, 1, 1.0);
  if (peak) {
    const auto at = static_cast<std::size_t>(std::lround(*peak));
    const Eigen::VectorXd error = basis.vectors * coordinates[at] - full.displacements[at];
    double largest_error = 0, largest_displacement = 0;
    for (Eigen::Index v = 0; v < error.size() / 3; ++v) {
      largest_error = std::max(largest_error, error.segment<3>(3 * v).norm());
      largest_displacement =
          std::max(largest_displacement, full.displacements[at].segment<3>(3 * v).norm());
    }
    row.peak_vertex_error = largest_error;
    row.peak_vertex_error_relative = largest_error / largest_displacement;

    const Eigen::Vector3d direction = reference[at].normalized();
    std::vector<double> along_reference(s.steps), along_simulated(s.steps);
    for (int step = 0; step < s.steps; ++step) {
      along_reference[step] = direction.dot(reference[step]);
      along_simulated[step] = direction.dot(simulated[step]);
    }
    const std::optional<double> period_full = first_period(along_reference);
    const std::optional<double> period_reduced = first_period(along_simulated);
    row.frequency_error =
        period_full && period_reduced ? *period_full / *period_reduced - 1.0 : std::nan("");
  }
  return row;
}

void print_header() {
  std::printf("%-6s %3s %9s %9s %10s %10s %9s %10s %12s %10s %9s %9s\n", "scene", "r", "basis s",
              "poly s", "step us", "full us", "speedup", "traj L2", "peak err mm", "peak rel",
              "freq err", "σr/σr+1");
}

void print_row(const Row& row) {
  std::printf("%-6s %3d %9.2f %9.2f %10.2f %10.0f %9.0f %10.2e %12.3f %10.2e %+8.2f%% %9.4f%s\n",
              row.scenario.c_str(), row.r, row.basis_seconds, row.polynomial_seconds, row.step_us,
              row.full_step_us, row.full_step_us / row.step_us, row.trajectory_error,
              1e3 * row.peak_vertex_error, row.peak_vertex_error_relative,
              100.0 * row.frequency_error, row.cut_ratio,
              row.failed_steps > 0
                  ? ("  (" + std::to_string(row.failed_steps) + " failed steps)").c_str()
                  : "");
  std::fflush(stdout);
}

void write_csv(const std::filesystem::path& file, const std::vector<Row>& rows) {
  std::ofstream out(file);
  out << "scenario,r,basis_seconds,polynomial_seconds,precompute_seconds,step_us,full_step_us,"
         "speedup,trajectory_relative_l2,peak_max_vertex_error_m,peak_max_vertex_error_relative,"
         "first_period_frequency_error,pca_cut_ratio,failed_steps\n";
  for (const Row& row : rows) {
    out << row.scenario << ',' << row.r << ',' << row.basis_seconds << ',' << row.polynomial_seconds
        << ',' << row.basis_seconds + row.polynomial_seconds << ',' << row.step_us << ','
        << row.full_step_us << ',' << row.full_step_us / row.step_us << ',' << row.trajectory_error
        << ',' << row.peak_vertex_error << ',' << row.peak_vertex_error_relative << ','
        << row.frequency_error << ',' << row.cut_ratio << ',' << row.failed_steps << '\n';
  }
}

// The tracked vertex's displacement per step: the full model's as r = 0, then each reduced one.
void write_trajectories(
    const std::filesystem::path& file, const std::vector<Row>& rows,
    const std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>>& full) {
  std::ofstream out(file);
  out << "scenario,r,step,ux,uy,uz\n";
  const auto write = [&](const std::string& scenario, int r,
                         const std::vector<Eigen::Vector3d>& u) {
    for (std::size_t step = 0; step < u.size(); ++step) {
      out << scenario << ',' << r << ',' << step << ',' << u[step].x() << ',' << u[step].y() << ','
          << u[step].z() << '\n';
    }
  };
  for (const auto& [scenario, u] : full) write(scenario, 0, u);
  for (const Row& row : rows) write(row.scenario, row.r, row.trajectory);
}

// Log–log plot of trajectory error against speedup, one line per scenario, points labelled r.
void write_plot(const std::filesystem::path& file, const std::vector<Row>& rows) {
  std::vector<double> x, y;
  for (const Row& row : rows) {
    x.push_back(std::log10(row.full_step_us / row.step_us));
    y.push_back(std::log10(std::max(row.trajectory_error, 1e-6)));
  }
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  const auto [y_min, y_max] = std::minmax_element(y.begin(), y.end());
  plsdev("pngcairo");
  plsfnam(file.c_str());
  plspage(0, 0, 1000, 700, 0, 0);
  plscolbg(255, 255, 255);
  plinit();
  plscol0(15, 0, 0, 0);
  plcol0(15);
  plenv(std::floor(*x_min - 0.2), std::ceil(*x_max + 0.2), std::floor(*y_min - 0.1),
        std::ceil(*y_max + 0.1), 0, 30);
  pllab("speedup over the full FEM model (per step)",
        "relative L2 error of the tracked vertex's trajectory",
        "Kilohertz: reduced StVK, speed against error");
  int colour = 1;
  for (std::size_t begin = 0; begin < rows.size();) {
    std::size_t end = begin;
    while (end < rows.size() && rows[end].scenario == rows[begin].scenario) ++end;
    const auto count = static_cast<PLINT>(end - begin);
    plcol0(colour);
    plline(count, &x[begin], &y[begin]);
    plpoin(count, &x[begin], &y[begin], 17);
    for (std::size_t i = begin; i < end; ++i) {
      plptex(x[i], y[i] + 0.04, 0, 0, 0.5, ("r=" + std::to_string(rows[i].r)).c_str());
    }
    plptex(x[begin], y[begin] - 0.12, 0, 0, 0.5, rows[begin].scenario.c_str());
    ++colour;
    begin = end;
  }
  plend();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Speed against error of reduced models versus the full FEM model"};
  std::string which = "all";
  std::vector<int> ranks{5, 10, 15, 20, 30, 45, 60};
  std::filesystem::path output = KHZ_BENCHMARK_OUTPUT_DIR;
  int num_modes = 20;
  int newton_iterations = 1;
  app.add_option("--scenario", which, "beam, dino or all")
      ->check(CLI::IsMember({"beam", "dino", "all"}));
  app.add_option("--ranks", ranks, "basis sizes r")->delimiter(',');
  app.add_option("--modes", num_modes, "linear modes k whose derivatives span the bases");
  app.add_option("--newton-iterations", newton_iterations,
                 "Newton iterations per reduced step (j_max; 1 is the haptic-rate setting)")
      ->check(CLI::PositiveNumber);
  app.add_option("--output", output, "directory for speed_against_error.csv and .png");
  CLI11_PARSE(app, argc, argv);

  try {
    std::vector<Row> rows;
    std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>> full_trajectories;
    print_header();
    for (const std::string& name : {std::string("beam"), std::string("dino")}) {
      if (which != "all" && which != name) continue;
      const Scenario scenario = name == "beam" ? beam_scenario() : dino_scenario();
      std::printf("# %s: %td vertices, %td elements, %zu fixed, %d steps of %g ms\n", name.c_str(),
                  scenario.model.mesh().num_vertices(), scenario.model.mesh().elements.rows(),
                  scenario.fixed.size(), scenario.steps, 1e3 * scenario.time_step);
      const FullRun full = run_full(scenario);
      const DerivativeSamples samples = derivative_samples(scenario, num_modes);
      double largest = 0;
      std::vector<Eigen::Vector3d>& tracked =
          full_trajectories.emplace_back(name, std::vector<Eigen::Vector3d>{}).second;
      for (const Eigen::VectorXd& u : full.displacements) {
        tracked.push_back(u.segment<3>(3 * scenario.tracked));
        largest = std::max(largest, tracked.back().norm());
      }
      std::printf(
          "# full model: %.1f ms per step; first linear mode %.2f Hz; tracked vertex moves up "
          "to %.3f m\n",
          1e3 * full.step_seconds, samples.first_frequency_hz, largest);
      for (int r : ranks) {
        rows.push_back(run_reduced(scenario, full, samples, r, newton_iterations));
        print_row(rows.back());
      }
    }
    std::filesystem::create_directories(output);
    write_csv(output / "speed_against_error.csv", rows);
    write_plot(output / "speed_against_error.png", rows);
    write_trajectories(output / "speed_against_error_trajectories.csv", rows, full_trajectories);
    std::printf("wrote speed_against_error.csv, .png and _trajectories.csv to %s\n",
                output.c_str());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "speed_against_error: %s\n", error.what());
    return 1;
  }
  return 0;
}
