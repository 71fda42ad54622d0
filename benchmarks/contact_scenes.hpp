#pragma once
// The scenes of bench_contact_query: meshes, distance fields, pointshells, point trees and
// reduced bases built once and cached in the build tree (KHZ_CONTACT_CACHE_DIR) in Kilohertz's
// own file formats, and smooth procedural trajectories that keep contact shallow, as a haptic
// loop with virtual coupling would (thesis §3.13: "typically one voxel or half a voxel").

#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>
#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace khz::bench {

namespace kc = khz::contact;
namespace kr = khz::reduced;
using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// What one precompute cost: built (first run) or read from the cache.
struct PrecomputeRecord {
  std::string what;
  double seconds = 0.0;
  bool from_cache = false;
};

inline std::vector<PrecomputeRecord>& precompute_log() {
  static std::vector<PrecomputeRecord> log;
  return log;
}

/// Prints each precompute stage when it starts and when it ends (with its time).
inline kc::ProgressCallback print_progress(const std::string& what) {
  struct Stage {
    std::string name;
    Clock::time_point start;
  };
  auto stage = std::make_shared<Stage>();
  return [what, stage](const kc::Progress& p) {
    if (p.done == 0 && p.stage != stage->name) {
      stage->name = std::string(p.stage);
      stage->start = Clock::now();
      std::printf("    %s: %s ...\n", what.c_str(), stage->name.c_str());
      std::fflush(stdout);
    } else if (p.done == p.total && p.stage == stage->name) {
      std::printf("    %s: %s done in %.1f s\n", what.c_str(), stage->name.c_str(),
                  seconds_since(stage->start));
      std::fflush(stdout);
      stage->name.clear();
    }
    return true;
  };
}

inline std::filesystem::path cache_file(const std::string& name) {
  const std::filesystem::path dir(KHZ_CONTACT_CACHE_DIR);
  std::filesystem::create_directories(dir);
  return dir / name;
}

/// `read(path)` if the cache holds `name`, else `build()` followed by `write(path, value)`; the
/// cost either way goes to precompute_log().
template <typename Build, typename Read, typename Write>
auto cached(const std::string& name, Build build, Read read, Write write) {
  const std::filesystem::path path = cache_file(name);
  const Clock::time_point start = Clock::now();
  if (std::filesystem::exists(path)) {
    auto value = read(path);
    precompute_log().push_back({name, seconds_since(start), true});
    return value;
  }
  std::printf("  building %s (cached for later runs in %s)\n", name.c_str(),
              path.parent_path().c_str());
  std::fflush(stdout);
  auto value = build();
  write(path, value);
  precompute_log().push_back({name, seconds_since(start), false});
  std::printf("  built %s in %.1f s\n", name.c_str(), precompute_log().back().seconds);
  return value;
}

/// A mesh of CGAL's demo data, centred on its bounding box and scaled to a longest side of
/// `size` (m).
inline kc::TriangleMesh demo_mesh(const std::string& file, double size) {
  kc::TriangleMesh mesh = kr::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / file);
  const Eigen::RowVector3d low = mesh.vertices.colwise().minCoeff();
  const Eigen::RowVector3d high = mesh.vertices.colwise().maxCoeff();
  const double scale = size / (high - low).maxCoeff();
  mesh.vertices = ((mesh.vertices.rowwise() - 0.5 * (low + high)) * scale).eval();
  return mesh;
}

/// Appends the planar quad a, b, c, d (counter-clockwise seen from outside) as two triangles.
inline void add_quad(std::vector<Eigen::Vector3i>& triangles, int a, int b, int c, int d) {
  triangles.emplace_back(a, b, c);
  triangles.emplace_back(a, c, d);
}

inline kc::TriangleMesh to_mesh(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<Eigen::Vector3i>& triangles) {
  kc::TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh.vertices.row(static_cast<Eigen::Index>(v)) = vertices[v].transpose();
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    mesh.triangles.row(static_cast<Eigen::Index>(t)) = triangles[t].transpose();
  }
  return mesh;
}

/// The four corners (±a, ±a) of a square at height z, counter-clockwise seen from +z.
inline void add_square(std::vector<Eigen::Vector3d>& vertices, double a, double z) {
  vertices.emplace_back(-a, -a, z);
  vertices.emplace_back(a, -a, z);
  vertices.emplace_back(a, a, z);
  vertices.emplace_back(-a, a, z);
}

/// A square peg: the box [−a, a]² × [0, length], closed and outward oriented.
inline kc::TriangleMesh square_peg(double a, double length) {
  std::vector<Eigen::Vector3d> v;
  add_square(v, a, 0.0);     // 0–3
  add_square(v, a, length);  // 4–7
  std::vector<Eigen::Vector3i> t;
  add_quad(t, 0, 3, 2, 1);
  add_quad(t, 4, 5, 6, 7);
  for (int k = 0; k < 4; ++k) add_quad(t, k, (k + 1) % 4, 4 + (k + 1) % 4, 4 + k);
  return to_mesh(v, t);
}

/// A block [−w, w]² × [0, height] with a blind square hole [−a, a]² × [height − depth, height]
/// (the CSG difference of two boxes, Fig. 3.28), closed and outward oriented: 28 triangles.
inline kc::TriangleMesh block_with_hole(double w, double height, double a, double depth) {
  std::vector<Eigen::Vector3d> v;
  add_square(v, w, height);          // 0–3: outer top
  add_square(v, a, height);          // 4–7: hole rim
  add_square(v, a, height - depth);  // 8–11: hole floor
  add_square(v, w, 0.0);             // 12–15: outer bottom
  std::vector<Eigen::Vector3i> t;
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    add_quad(t, k, n, 4 + n, 4 + k);          // top ring, +z
    add_quad(t, 12 + k, 12 + n, n, k);        // outer walls
    add_quad(t, 4 + k, 4 + n, 8 + n, 8 + k);  // hole walls, facing the hole's axis
  }
  add_quad(t, 8, 9, 10, 11);    // hole floor, +z
  add_quad(t, 12, 15, 14, 13);  // bottom, −z
  return to_mesh(v, t);
}

inline kc::DistanceGrid cached_signed_field(const std::string& name, const kc::TriangleMesh& mesh,
                                            int cells) {
  return cached(
      name + "_" + std::to_string(cells) + ".khzsdf",
      [&] {
        kc::DistanceFieldOptions options;
        options.cells = cells;
        options.progress = print_progress(name);
        return kc::signed_distance_field(mesh, options);
      },
      [](const std::filesystem::path& p) { return kc::read_distance_field(p); },
      [](const std::filesystem::path& p, const kc::DistanceGrid& g) {
        kc::write_distance_field(p, g);
      });
}

/// n₀·(4ᴸ − 1)/3 points in L levels by particle repulsion (§3.8.1) on the zero level set of a
/// closed mesh's signed field (`soup` = false) or of a polygon soup's offset-surface field.
inline kc::Pointshell cached_pointshell(const std::string& name, const kc::TriangleMesh& mesh,
                                        bool soup, int field_cells, Eigen::Index first_level,
                                        int levels) {
  kc::RepulsionOptions options;
  options.first_level_points = first_level;
  options.levels = levels;
  options.progress = print_progress(name);
  const Eigen::Index points = first_level * ((Eigen::Index{1} << (2 * levels)) - 1) / 3;
  return cached(
      name + "_" + std::to_string(points) + "_L" + std::to_string(levels) + ".khzshell",
      [&] {
        kc::DistanceFieldOptions field_options;
        field_options.cells = field_cells;
        field_options.progress = options.progress;
        kc::RepulsionReport report;
        kc::Pointshell shell;
        if (soup) {
          kc::PolygonSoupFieldOptions soup_options;
          soup_options.field = field_options;
          const kc::PolygonSoupField field = kc::polygon_soup_field(mesh, soup_options);
          shell =
              kc::repulsion_pointshell(field.field, 0.0, field.offset_surface, options, &report);
        } else {
          shell = kc::repulsion_pointshell(mesh, field_options, options, &report);
        }
        std::printf("    %s: %ld points, converged: %s\n", name.c_str(),
                    static_cast<long>(shell.size()), report.converged() ? "yes" : "no");
        return shell;
      },
      [](const std::filesystem::path& p) { return kc::read_pointshell(p); },
      [](const std::filesystem::path& p, const kc::Pointshell& s) { kc::write_pointshell(p, s); });
}

/// The voxel mesh (`resolution` cells along the longest side, interior filled) a deformable
/// scene's reduced model lives on.
inline kr::VolumeMesh voxel_volume(const kc::TriangleMesh& mesh, int resolution = 32) {
  kr::VoxelizeOptions voxels;
  voxels.resolution = resolution;
  voxels.fill_interior = true;
  return kr::voxelize(mesh, voxels);
}

/// The vertices of the lowest 8% in y: the anchors of the deformable scenes' reduced models.
inline std::vector<int> lowest_vertices(const kr::VolumeMesh& volume) {
  const double low = volume.vertices.col(1).minCoeff();
  const double high = volume.vertices.col(1).maxCoeff();
  std::vector<int> anchors;
  for (Eigen::Index v = 0; v < volume.num_vertices(); ++v) {
    if (volume.vertices(v, 1) < low + 0.08 * (high - low)) anchors.push_back(static_cast<int>(v));
  }
  return anchors;
}

/// A modal-derivative basis (§2.8.3) of `r` vectors from r/3 + 1 linear modes.
inline kr::Basis cached_basis(const std::string& name, const kr::VolumeMesh& volume,
                              const std::vector<int>& anchors, int r) {
  return cached(
      name + "_r" + std::to_string(r) + ".khzbasis",
      [&] {
        kr::FemModel model(volume, {kr::Material::stvk(1e6, 0.4, 1000.0)});
        kr::ModalDerivativeBasisOptions options;
        options.basis_size = r;
        options.modes.num_modes = r / 3 + 1;
        options.progress = print_progress(name);
        return kr::modal_derivative_basis(model, anchors, options);
      },
      [&](const std::filesystem::path& p) { return kr::read_basis(p, volume); },
      [&](const std::filesystem::path& p, const kr::Basis& b) { kr::write_basis(p, b, volume); });
}

/// The point tree of `shell()` embedded in `volume` with the modes of `basis`.
template <typename ShellSource>
kc::DeformablePointTree cached_deformable_tree(const std::string& name, ShellSource shell,
                                               const kr::VolumeMesh& volume,
                                               const kr::Basis& basis) {
  return cached(
      name + ".khztree",
      [&] {
        const kr::MeshEmbedding embedding(volume);
        return kc::DeformablePointTree(kc::PointTree(shell(), print_progress(name)), embedding,
                                       basis.vectors, print_progress(name));
      },
      [&](const std::filesystem::path& p) {
        return kc::read_deformable_point_tree(p, print_progress(name));
      },
      [](const std::filesystem::path& p, const kc::DeformablePointTree& t) {
        kc::write_deformable_point_tree(p, t);
      });
}

/// Writes a run's rows to <build>/benchmarks/<folder>/<run>.csv (run's non-alphanumerics as _).
inline void write_run_csv(const std::string& folder, const std::string& run,
                          const std::string& text) {
  std::string name;
  for (const char c : run) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  const std::filesystem::path dir =
      std::filesystem::path(KHZ_CONTACT_CACHE_DIR).parent_path() / folder;
  std::filesystem::create_directories(dir);
  std::ofstream(dir / (name + ".csv")) << text;
}

// ---------------------------------------------------------------------------------------------
// Trajectories.

/// One recorded manipulandum trajectory: per haptic cycle the pointshell's pose (world ← body)
/// and, for a reduced deformable pointshell, its q; the field object stays at the identity.
struct Trajectory {
  std::vector<Eigen::Isometry3d> pointshell;
  std::vector<Eigen::VectorXd> q;  // empty for a rigid pointshell
  /// Deepest penetration per pose (m, ≥ 0; 0 when apart): −min_s d(p_s).
  std::vector<double> penetration;

  std::size_t size() const noexcept { return pointshell.size(); }
};

/// A rigid pointshell's points for min_distance().
struct RigidShape {
  const kc::PointTree& tree;
  explicit RigidShape(const kc::PointTree& t) : tree(t) {}
  Eigen::Vector3d position(Eigen::Index s) const {
    return tree.pointshell().points.row(s).transpose();
  }
  double radius(Eigen::Index node) const { return tree.node(node).rest_radius; }
};

/// A reduced deformable pointshell's points in configuration q.
struct DeformedShape {
  const kc::DeformablePointTree& deformable;
  const kc::PointTree& tree;
  Eigen::VectorXd q, abs_q;
  DeformedShape(const kc::DeformablePointTree& t, Eigen::VectorXd configuration)
      : deformable(t), tree(t.tree()), q(std::move(configuration)), abs_q(q.cwiseAbs()) {}
  Eigen::Vector3d position(Eigen::Index s) const { return deformable.position(s, q); }
  double radius(Eigen::Index node) const { return deformable.bounding_radius(node, abs_q); }
};

/// min_s d(field_from_shell · p_s) over every point of the tree, by branch and bound on its
/// spheres (a subtree can hold nothing below d(centre) − radius).
template <typename Shape, kc::DistanceField Field>
double min_distance(const Shape& shape, const Field& field,
                    const Eigen::Isometry3d& field_from_shell) {
  const kc::PointTree& tree = shape.tree;
  std::vector<std::int32_t> current, next;
  for (Eigen::Index n = 0; n < tree.level_end(0); ++n) current.push_back(static_cast<int>(n));
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> distances;
  while (!current.empty()) {
    distances.resize(current.size());
    for (std::size_t k = 0; k < current.size(); ++k) {
      distances[k] = field.distance(field_from_shell * shape.position(tree.node(current[k]).point));
      best = std::min(best, distances[k]);
    }
    next.clear();
    for (std::size_t k = 0; k < current.size(); ++k) {
      const kc::PointTreeNode& node = tree.node(current[k]);
      if (distances[k] - shape.radius(current[k]) >= best) continue;
      for (std::int32_t c = 0; c < node.child_count; ++c) next.push_back(node.first_child + c);
    }
    std::swap(current, next);
  }
  return best;
}

/// How a trajectory goes, as smooth functions of s ∈ [0, 1]. The pose at s is
///   translation = lateral(s) + u(s)·approach_axis,  rotation = rotation(s),
/// with u chosen so that the deepest point's distance is clearance(s) (m; < 0 penetrates)
/// while clearance ≤ 0, and apart by clearance(s) along the axis otherwise.
struct TrajectoryScript {
  int poses = 400;
  /// u is solved at every `keyframe_stride`-th pose and interpolated between (Catmull–Rom), so
  /// penetration follows clearance() closely but not exactly; Trajectory::penetration has it.
  int keyframe_stride = 8;
  Eigen::Vector3d approach_axis = Eigen::Vector3d::UnitX();  // unit; the pointshell moves −axis
  /// u (m) the search for the first keyframe's contact starts from: apart, but near enough that
  /// its growing steps do not leap over the field object (1 m suits the 1 m dino).
  double start = 1.0;
  std::function<Eigen::Matrix3d(double)> rotation;
  std::function<Eigen::Vector3d(double)> lateral;
  std::function<double(double)> clearance;
  std::function<Eigen::VectorXd(double)> q;  // empty for a rigid pointshell
};

/// Radians per degree.
inline constexpr double degrees = std::numbers::pi / 180.0;

inline Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// The value below which a fraction of the values lie; NaN for no values.
inline double quantile(std::vector<double> values, double fraction) {
  if (values.empty()) return std::nan("");
  const auto k = static_cast<std::ptrdiff_t>(fraction * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[static_cast<std::size_t>(k)];
}

/// Cubic smoothstep from 0 at a to 1 at b.
inline double ramp(double s, double a, double b) {
  const double x = std::clamp((s - a) / (b - a), 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

/// A root of the increasing function g by bracketing from u0 and the Illinois method.
template <typename G>
double solve_increasing(const G& g, double u0, double step, double tolerance) {
  double lo = u0, hi = u0, g_lo = g(u0), g_hi = g_lo;
  for (int k = 0; k < 60 && !(g_lo < 0.0 && g_hi > 0.0); ++k, step *= 1.6) {
    if (g_hi <= 0.0) {
      lo = hi, g_lo = g_hi;
      hi += step, g_hi = g(hi);
    } else {
      hi = lo, g_hi = g_lo;
      lo -= step, g_lo = g(lo);
    }
  }
  int side = 0;
  for (int k = 0; k < 80 && hi - lo > tolerance; ++k) {
    const double u = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
    const double gu = g(u);
    if (gu < 0.0) {
      lo = u, g_lo = gu;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    } else {
      hi = u, g_hi = gu;
      if (side == 1) g_lo *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (lo + hi);
}

/// Plays `script` against `field` (at the identity). `shape_at(q)` gives the pointshell's
/// points in configuration q (a RigidShape ignores it).
template <typename ShapeAt, kc::DistanceField Field>
Trajectory record_trajectory(const TrajectoryScript& script, const ShapeAt& shape_at,
                             const Field& field, double voxel) {
  const auto pose = [&](double s, double u) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = script.rotation(s);
    t.translation() = script.lateral(s) + u * script.approach_axis;
    return t;
  };
  const auto q_at = [&](double s) { return script.q ? script.q(s) : Eigen::VectorXd(); };
  const auto parameter = [&](int i) { return static_cast<double>(i) / (script.poses - 1); };

  // u per keyframe, from the previous keyframe's.
  std::vector<double> keys;
  double u = script.start;
  for (int i = 0; i < script.poses + 3 * script.keyframe_stride; i += script.keyframe_stride) {
    const double s = std::min(parameter(i), 1.0);
    const auto shape = shape_at(q_at(s));
    const double c = script.clearance(s);
    const auto g = [&](double x) {
      return min_distance(shape, field, pose(s, x)) - std::min(c, 0.0);
    };
    u = solve_increasing(g, u, 0.25 * voxel, 1e-3 * voxel);
    keys.push_back(u + std::max(c, 0.0));
  }
  Trajectory trajectory;
  for (int i = 0; i < script.poses; ++i) {
    const std::size_t k = static_cast<std::size_t>(i / script.keyframe_stride);
    const double t = static_cast<double>(i % script.keyframe_stride) / script.keyframe_stride;
    const double p0 = keys[k == 0 ? 0 : k - 1], p1 = keys[k], p2 = keys[k + 1], p3 = keys[k + 2];
    const double ui =
        p1 +
        0.5 * t *
            (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
    const double s = parameter(i);
    trajectory.pointshell.push_back(pose(s, ui));
    if (script.q) trajectory.q.push_back(q_at(s));
    const auto shape = shape_at(q_at(s));
    trajectory.penetration.push_back(
        std::max(0.0, -min_distance(shape, field, trajectory.pointshell.back())));
  }
  return trajectory;
}

/// Temporal-coherence bounds (§3.10.2) the trajectory keeps, with 2% to spare: the largest
/// motion per cycle of the pointshell's reference point (its rest bounding box's centre) and
/// rotation; `modes_norm` (max_s ‖U_s‖_F, 0 for a rigid pointshell) times the largest ‖Δq‖.
inline kc::CoherenceOptions coherence_bounds(const Trajectory& trajectory,
                                             const kc::PointTree& tree, double modes_norm) {
  const kc::PointMatrix& points = tree.pointshell().points;
  const Eigen::Vector3d reference =
      0.5 * (points.colwise().minCoeff() + points.colwise().maxCoeff()).transpose();
  kc::CoherenceOptions bounds;
  bounds.enabled = true;
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const Eigen::Isometry3d& a = trajectory.pointshell[i - 1];
    const Eigen::Isometry3d& b = trajectory.pointshell[i];
    bounds.max_translation =
        std::max(bounds.max_translation, (b * reference - a * reference).norm());
    bounds.max_rotation = std::max(bounds.max_rotation,
                                   Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle());
    if (!trajectory.q.empty()) {
      bounds.max_deformation = std::max(
          bounds.max_deformation, modes_norm * (trajectory.q[i] - trajectory.q[i - 1]).norm());
    }
  }
  bounds.max_translation *= 1.02;
  bounds.max_rotation *= 1.02;
  bounds.max_deformation *= 1.02;
  return bounds;
}

}  // namespace khz::bench
