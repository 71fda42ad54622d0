// contact_tour: distributed contact between two complex rigid objects (thesis §3.5–§3.11).
//
//   contact_tour [FIELD_MESH] [POINTSHELL_MESH]
//
// Defaults: CGAL's dino.off as the distance-field object, bunny00.off as the pointshell object.
//   1. builds a 128³ signed distance field of the first mesh and a 4-level particle-repulsion
//      pointshell (21,760 points) of the second, and links it into a nested point tree,
//   2. presses the pointshell object half a voxel into the field object's flank, slides it along
//      and pulls it back out in 400 queries (one per haptic cycle), printing the contact force
//      and torque on the field object, the points in contact, the nodes the traversal visited
//      and the time per query,
//   3. replays the same path with a 20 µs time budget (graceful degradation, §3.10.3) and with
//      temporal coherence (§3.10.2), and compares their cost and force with the full traversal.
#include "progress_bar.hpp"

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/io/mesh_file.hpp>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace {

namespace kc = khz::contact;

/// The x at which the pointshell object, posed as in `frames` but moved along x, first touches
/// the field object: found by stepping in from `far_x` and bisecting.
double touching_x(const kc::PointTree& tree, const kc::DistanceGrid& field,
                  kc::ContactFrames frames, double far_x, kc::ContactWorkspace& probe) {
  const auto touches = [&](double x) {
    frames.pointshell.translation().x() = x;
    kc::query_contact(tree, field, frames, probe);
    return probe.result().statistics.points_in_contact > 0;
  };
  const double step = field.geometry().spacing;
  double outside = far_x;
  while (!touches(outside - step) && outside > far_x - 1000.0 * step) outside -= step;
  double inside = outside - step;
  for (int i = 0; i < 30; ++i) {
    const double middle = 0.5 * (outside + inside);
    (touches(middle) ? inside : outside) = middle;
  }
  return outside;
}

/// The path: the pointshell object comes in from +x, presses `depth` into the field object,
/// slides along z while turning and following its flank, and leaves; one pose per query.
std::vector<kc::ContactFrames> trajectory(const kc::PointTree& tree, const kc::DistanceGrid& field,
                                          const Eigen::AlignedBox3d& field_box,
                                          const Eigen::AlignedBox3d& shell_box) {
  const double far_x = field_box.max().x() - shell_box.min().x() + field.geometry().spacing;
  const double depth = 0.5 * field.geometry().spacing;
  kc::ContactWorkspace probe(tree, kc::ContactOptions{});
  std::vector<kc::ContactFrames> path;
  constexpr int steps = 400;
  for (int step = 0; step < steps; ++step) {
    const double t = static_cast<double>(step) / (steps - 1);
    const double press = t < 0.2 ? t / 0.2 : t > 0.8 ? (1.0 - t) / 0.2 : 1.0;  // in, hold, out
    kc::ContactFrames frames;
    frames.pointshell.translation() =
        Eigen::Vector3d(far_x, field_box.center().y(),
                        field_box.center().z() + 0.4 * (t - 0.5) * field_box.sizes().z());
    frames.pointshell.linear() =
        Eigen::AngleAxisd(0.6 * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const double touch = touching_x(tree, field, frames, far_x, probe);
    frames.pointshell.translation().x() = far_x + press * (touch - depth - far_x);
    frames.grasp_point = Eigen::Vector3d::Zero();  // the field object's origin
    path.push_back(frames);
  }
  return path;
}

struct RunSummary {
  double mean_microseconds = 0.0, max_microseconds = 0.0, mean_nodes = 0.0;
  std::vector<Eigen::Vector3d> forces;
};

RunSummary run(const kc::PointTree& tree, const kc::DistanceGrid& field,
               const std::vector<kc::ContactFrames>& path, const kc::ContactOptions& options,
               bool print) {
  kc::ContactWorkspace workspace(tree, options);
  RunSummary summary;
  for (std::size_t i = 0; i < path.size(); ++i) {
    kc::query_contact(tree, field, path[i], workspace);
    const kc::ContactResult& result = workspace.result();
    const kc::ContactStatistics& stats = result.statistics;
    summary.mean_microseconds += stats.microseconds / static_cast<double>(path.size());
    summary.max_microseconds = std::max(summary.max_microseconds, stats.microseconds);
    summary.mean_nodes +=
        static_cast<double>(stats.nodes_traversed) / static_cast<double>(path.size());
    summary.forces.push_back(result.force);
    if (print && i % 40 == 0) {
      std::cout << std::right << std::setw(5) << i << std::fixed << std::setprecision(2)
                << std::setw(10) << result.force.norm() << std::setw(10) << result.torque.norm()
                << std::setw(8) << stats.points_in_contact << std::setw(8) << stats.nodes_traversed
                << std::setw(6) << stats.deepest_level << std::setw(9) << stats.microseconds
                << "\n";
    }
  }
  return summary;
}

double mean_force_difference(const RunSummary& a, const RunSummary& reference) {
  double difference = 0.0, size = 0.0;
  for (std::size_t i = 0; i < a.forces.size(); ++i) {
    difference += (a.forces[i] - reference.forces[i]).norm();
    size += reference.forces[i].norm();
  }
  return size > 0.0 ? difference / size : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::filesystem::path meshes(KHZ_CGAL_MESH_DIR);
    const std::string field_file = argc > 1 ? argv[1] : (meshes / "dino.off").string();
    const std::string shell_file = argc > 2 ? argv[2] : (meshes / "bunny00.off").string();
    const kc::TriangleMesh field_mesh = khz::reduced::read_triangle_mesh(field_file);
    const kc::TriangleMesh shell_mesh = khz::reduced::read_triangle_mesh(shell_file);

    std::cout << "1. distance field of " << field_file << " and pointshell of " << shell_file
              << "\n";
    kc::DistanceFieldOptions field_options;
    field_options.cells = 128;
    field_options.progress = khz::examples::print_progress;
    const kc::DistanceGrid field = kc::signed_distance_field(field_mesh, field_options);
    kc::RepulsionOptions repulsion;
    repulsion.first_level_points = 256;
    repulsion.levels = 4;
    repulsion.progress = khz::examples::print_progress;
    const kc::PointTree tree(kc::repulsion_pointshell(shell_mesh, field_options, repulsion),
                             khz::examples::print_progress);
    std::cout << "   " << tree.num_points() << " points in " << tree.num_levels() << " levels, "
              << tree.num_nodes() << " tree nodes; field spacing " << field.geometry().spacing
              << " m\n";

    Eigen::AlignedBox3d field_box, shell_box;
    field_box.setEmpty();
    shell_box.setEmpty();
    for (Eigen::Index v = 0; v < field_mesh.num_vertices(); ++v)
      field_box.extend(field_mesh.vertices.row(v).transpose());
    for (Eigen::Index v = 0; v < shell_mesh.num_vertices(); ++v)
      shell_box.extend(shell_mesh.vertices.row(v).transpose());
    const std::vector<kc::ContactFrames> path = trajectory(tree, field, field_box, shell_box);

    std::cout << "2. full traversal along the path (k_C = 1000 N/m, L = 10)\n"
              << "query   |F| (N) |T| (N·m) contact   nodes level     µs\n";
    kc::ContactOptions options;
    const RunSummary full = run(tree, field, path, options, true);

    std::cout << "3. the same path with a time budget, and with temporal coherence\n";
    kc::ContactOptions budget = options;
    budget.degradation.mode = kc::DegradationOptions::Mode::time_budget;
    budget.degradation.budget_microseconds = 20.0;
    const RunSummary degraded = run(tree, field, path, budget, false);
    kc::ContactOptions coherent = options;
    coherent.coherence.enabled = true;
    coherent.coherence.max_translation = 0.01;  // the path moves ≤ 7 mm per query
    coherent.coherence.max_rotation = 0.002;    // and turns 1.5 mrad
    const RunSummary skipping = run(tree, field, path, coherent, false);
    std::cout << std::setprecision(1) << "   full:               mean " << full.mean_microseconds
              << " µs, max " << full.max_microseconds << " µs, " << full.mean_nodes
              << " nodes per query\n"
              << "   20 µs budget:       mean " << degraded.mean_microseconds << " µs, max "
              << degraded.max_microseconds << " µs, " << degraded.mean_nodes
              << " nodes; force differs by " << std::setprecision(3)
              << 100.0 * mean_force_difference(degraded, full) << "% on average\n"
              << std::setprecision(1) << "   temporal coherence: mean "
              << skipping.mean_microseconds << " µs, max " << skipping.max_microseconds << " µs, "
              << skipping.mean_nodes << " nodes; force differs by " << std::setprecision(3)
              << 100.0 * mean_force_difference(skipping, full) << "%\n";
  } catch (const khz::contact::Error& error) {
    std::cerr << "contact_tour: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
