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
//   khz_python_reference scene SCENE CACHE CYCLES OUT
//       SCENE prepared with the cache directory CACHE and run with its own devices for CYCLES
//       cycles in simulated time (as kilohertz.scene.SceneRuntime.run() does); per cycle of hand
//       0 its contact force and simulation position, 6 float64, written to OUT

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/io/distance_field_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>

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
