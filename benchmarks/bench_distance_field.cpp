// Signed distance fields (thesis §3.11) of bunny00.off (CGAL's demo data: 75,408 triangles,
// closed, genus 0):
// - signed_distance_field() at 128³ and 256³ cells, with its accuracy against exact distances at
//   sampled nodes and its signs against CGAL's Side_of_triangle_mesh;
// - closest-point queries of MeshDistance against CGAL's AABB_tree, near the surface and
//   uniformly in the field's box;
// - DistanceGrid::distance() lookups, and the IEEE-mantissa voxel indexing of §3.11 (valid for
//   power-of-two resolutions) against the plain floor/int conversion the library uses.
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/mesh_distance.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <benchmark/benchmark.h>
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

namespace kc = khz::contact;
using Kernel = CGAL::Simple_cartesian<double>;
using Surface = CGAL::Surface_mesh<Kernel::Point_3>;
using Tree =
    CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<Surface>>>;

const kc::TriangleMesh& bunny() {
  static const kc::TriangleMesh mesh = [] {
    kc::TriangleMesh m =
        khz::reduced::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / "bunny00.off");
    if (!khz::reduced::analyze_mesh(m).closed) throw kc::Error("bunny00.off is not closed");
    return m;
  }();
  return mesh;
}

Surface cgal_surface(const kc::TriangleMesh& mesh) {
  Surface surface;
  std::vector<Surface::Vertex_index> vertices;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    vertices.push_back(
        surface.add_vertex({mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2)}));
  }
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    surface.add_face(vertices[static_cast<std::size_t>(mesh.triangles(t, 0))],
                     vertices[static_cast<std::size_t>(mesh.triangles(t, 1))],
                     vertices[static_cast<std::size_t>(mesh.triangles(t, 2))]);
  }
  return surface;
}

double process_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Query points: near the surface (a vertex plus up to 1% of the box) or uniform in the cube
/// the default field covers.
std::vector<Eigen::Vector3d> query_points(const kc::TriangleMesh& mesh, bool near, int count) {
  const kc::GridGeometry box = kc::GridGeometry::cube_around(
      Eigen::AlignedBox3d(mesh.vertices.colwise().minCoeff().transpose(),
                          mesh.vertices.colwise().maxCoeff().transpose()),
      1.5, 1);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<Eigen::Index> vertex(0, mesh.num_vertices() - 1);
  std::vector<Eigen::Vector3d> points;
  for (int s = 0; s < count; ++s) {
    const Eigen::Vector3d u(unit(random), unit(random), unit(random));
    points.push_back(near ? Eigen::Vector3d(mesh.vertices.row(vertex(random)).transpose() +
                                            0.01 * box.size() * (2.0 * u.array() - 1.0).matrix())
                          : Eigen::Vector3d(box.origin + box.size() * u));
  }
  return points;
}

// Arguments: cells, threads.
void BM_SignedDistanceField(benchmark::State& state) {
  const kc::TriangleMesh& mesh = bunny();
  kc::DistanceFieldOptions options;
  options.cells = static_cast<int>(state.range(0));
  const int threads = omp_get_max_threads();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  std::optional<kc::DistanceGrid> grid;
  double cpu = 0.0;
  for (auto _ : state) {
    const double start = process_seconds();
    grid = kc::signed_distance_field(mesh, options);
    cpu += process_seconds() - start;
    benchmark::DoNotOptimize(grid->values().data());
  }
  omp_set_num_threads(threads);
  state.counters["triangles"] = static_cast<double>(mesh.num_triangles());
  state.counters["nodes"] = static_cast<double>(grid->geometry().node_count());
  state.counters["cpu_s"] = cpu / static_cast<double>(state.iterations());

  // Accuracy at 20,000 random nodes: MeshDistance is exact (tested against brute force and
  // CGAL); the sides come from CGAL's ray shooting.
  const kc::MeshDistance exact(mesh);
  const Surface surface = cgal_surface(mesh);
  const CGAL::Side_of_triangle_mesh<Surface, Kernel> side(surface);
  const kc::GridGeometry& g = grid->geometry();
  std::mt19937 random(3);
  std::uniform_int_distribution<int> node(0, g.cells);
  double band_max = 0.0, fill_max = 0.0, fill_sum = 0.0;
  int fill_nodes = 0, fill_exact = 0, sign_errors = 0;
  for (int s = 0; s < 20000; ++s) {
    const int i = node(random), j = node(random), k = node(random);
    const Eigen::Vector3d p = g.node_position(i, j, k);
    const double d = exact.closest(p).distance;
    const double value = grid->node(i, j, k);
    const double error = std::abs(value) - d;
    if (d <= options.exact_band * g.spacing) {
      band_max = std::max(band_max, std::abs(error));
    } else {
      ++fill_nodes;
      fill_max = std::max(fill_max, error);
      fill_sum += error;
      fill_exact += error <= 1e-6 * g.spacing;
    }
    const CGAL::Bounded_side where = side({p.x(), p.y(), p.z()});
    if (where != CGAL::ON_BOUNDARY && (value < 0.0) != (where == CGAL::ON_BOUNDED_SIDE)) {
      ++sign_errors;
    }
  }
  state.counters["band_max_err_of_box"] = band_max / g.size();
  state.counters["fill_max_err_h"] = fill_max / g.spacing;
  state.counters["fill_mean_err_h"] = fill_sum / std::max(fill_nodes, 1) / g.spacing;
  state.counters["fill_exact_fraction"] = static_cast<double>(fill_exact) / std::max(fill_nodes, 1);
  state.counters["sign_errors"] = sign_errors;
}
BENCHMARK(BM_SignedDistanceField)
    ->Args({128, 1})
    ->Args({128, 2})
    ->Args({256, 2})
    ->ArgNames({"cells", "threads"})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

// Argument: 1 for points near the surface, 0 for points uniform in the field's box.
void BM_ClosestPointMeshDistance(benchmark::State& state) {
  const kc::MeshDistance distance(bunny());
  const auto points = query_points(bunny(), state.range(0) != 0, 20000);
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(distance.closest(points[next]).distance);
    next = next + 1 == points.size() ? 0 : next + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosestPointMeshDistance)->Arg(1)->Arg(0)->ArgName("near");

void BM_ClosestPointCgalAabbTree(benchmark::State& state) {
  const Surface surface = cgal_surface(bunny());
  Tree tree(faces(surface).first, faces(surface).second, surface);
  tree.accelerate_distance_queries();
  const auto points = query_points(bunny(), state.range(0) != 0, 20000);
  std::size_t next = 0;
  for (auto _ : state) {
    const Eigen::Vector3d& p = points[next];
    benchmark::DoNotOptimize(tree.closest_point_and_primitive({p.x(), p.y(), p.z()}));
    next = next + 1 == points.size() ? 0 : next + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosestPointCgalAabbTree)->Arg(1)->Arg(0)->ArgName("near");

void BM_BuildMeshDistance(benchmark::State& state) {
  for (auto _ : state) {
    const kc::MeshDistance distance(bunny());
    benchmark::DoNotOptimize(&distance);
  }
}
BENCHMARK(BM_BuildMeshDistance)->Unit(benchmark::kMillisecond);

void BM_BuildCgalAabbTree(benchmark::State& state) {
  const Surface surface = cgal_surface(bunny());
  for (auto _ : state) {
    Tree tree(faces(surface).first, faces(surface).second, surface);
    tree.accelerate_distance_queries();
    tree.build();
    benchmark::DoNotOptimize(&tree);
  }
}
BENCHMARK(BM_BuildCgalAabbTree)->Unit(benchmark::kMillisecond);

/// The grid the lookup benchmarks share: bunny00.off at 128³ cells (a power of two).
const kc::DistanceGrid& lookup_grid() {
  static const kc::DistanceGrid grid = [] {
    kc::DistanceFieldOptions options;
    options.cells = 128;
    return kc::signed_distance_field(bunny(), options);
  }();
  return grid;
}

/// Points inside the grid's box, where the voxel index is computed: anywhere in it (the grid,
/// 8.6 MB, is read from memory) or within an 8-cell cube (it stays in the L1 cache, so the
/// index computation weighs most).
const std::vector<Eigen::Vector3d>& lookup_points(bool local) {
  static const auto make = [](double extent) {
    const kc::GridGeometry& g = lookup_grid().geometry();
    std::mt19937 random(9);
    std::uniform_real_distribution<double> unit(0.0, extent);
    std::vector<Eigen::Vector3d> points(1 << 20);
    const Eigen::Vector3d corner = g.origin + Eigen::Vector3d::Constant(0.4 * g.size());
    for (auto& p : points)
      p = corner + g.size() * Eigen::Vector3d(unit(random), unit(random), unit(random));
    return points;
  };
  static const std::vector<Eigen::Vector3d> anywhere = make(0.6), nearby = make(8.0 / 128.0);
  return local ? nearby : anywhere;
}

/// Trilinear interpolation in cell (i, j, k) at fractions (x, y, z): DistanceGrid's arithmetic.
inline double interpolate(const float* values, std::int64_t n, std::int64_t cell, double x,
                          double y, double z) {
  const float* c = values + cell;
  const double c000 = c[0], c100 = c[1], c010 = c[n], c110 = c[n + 1];
  const double c001 = c[n * n], c101 = c[n * n + 1], c011 = c[n * n + n], c111 = c[n * n + n + 1];
  const double c00 = c000 + x * (c100 - c000), c10 = c010 + x * (c110 - c010);
  const double c01 = c001 + x * (c101 - c001), c11 = c011 + x * (c111 - c011);
  const double c0 = c00 + y * (c10 - c00), c1 = c01 + y * (c11 - c01);
  return c0 + z * (c1 - c0);
}

/// The voxel lookup as DistanceGrid does it inside the box: scale, truncate to int, clamp.
inline double lookup_plain(const kc::GridGeometry& g, const float* values, double inverse_spacing,
                           const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = (p - g.origin) * inverse_spacing;
  const int i = std::min(static_cast<int>(local.x()), g.cells - 1);
  const int j = std::min(static_cast<int>(local.y()), g.cells - 1);
  const int k = std::min(static_cast<int>(local.z()), g.cells - 1);
  const std::int64_t n = g.nodes_per_axis();
  return interpolate(values, n, g.node_index(i, j, k), local.x() - i, local.y() - j, local.z() - k);
}

/// The voxel lookup of thesis §3.11 for 2^bits cells: with w ∈ [0, 1) the position in the box,
/// the first `bits` mantissa bits of 1 + w are the cell index and the rest its fraction, with no
/// float-to-int conversion. (The upper box faces, w = 1, would need the plain path.)
inline double lookup_mantissa(const kc::GridGeometry& g, const float* values, double inverse_size,
                              int bits, const Eigen::Vector3d& p) {
  constexpr std::uint64_t mantissa = (std::uint64_t{1} << 52) - 1;
  constexpr std::uint64_t one = 0x3FF0000000000000;
  int index[3];
  double fraction[3];
  for (int axis = 0; axis < 3; ++axis) {
    const double w = (p[axis] - g.origin[axis]) * inverse_size;
    const auto u = std::bit_cast<std::uint64_t>(w + 1.0);
    index[axis] = static_cast<int>((u & mantissa) >> (52 - bits));
    fraction[axis] = std::bit_cast<double>(((u << bits) & mantissa) | one) - 1.0;
  }
  return interpolate(values, g.nodes_per_axis(), g.node_index(index[0], index[1], index[2]),
                     fraction[0], fraction[1], fraction[2]);
}

// Arguments: variant (0 DistanceGrid::distance(), 1 the same lookup inlined here, 2 the mantissa
// lookup, 3 DistanceGrid::distance_and_gradient()), local (points within 8 cells).
void BM_DistanceGridLookup(benchmark::State& state) {
  const kc::DistanceGrid& grid = lookup_grid();
  const auto& points = lookup_points(state.range(1) != 0);
  const kc::GridGeometry& g = grid.geometry();
  const float* values = grid.values().data();
  const int bits = std::countr_zero(static_cast<unsigned>(g.cells));
  const double inverse_spacing = 1.0 / g.spacing, inverse_size = 1.0 / g.size();
  const auto variant = state.range(0);
  // The variants agree (the mantissa split is exact for power-of-two cells).
  for (std::size_t s = 0; s < 1000; ++s) {
    const double expected = grid.distance(points[s]);
    if (std::abs(lookup_plain(g, values, inverse_spacing, points[s]) - expected) > 1e-6 ||
        std::abs(lookup_mantissa(g, values, inverse_size, bits, points[s]) - expected) > 1e-6) {
      state.SkipWithError("the lookup variants disagree");
      return;
    }
  }
  std::size_t next = 0;
  double sum = 0.0;
  Eigen::Vector3d gradient;
  for (auto _ : state) {
    for (int repeat = 0; repeat < 1024; ++repeat) {
      const Eigen::Vector3d& p = points[next];
      next = (next + 1) & (points.size() - 1);
      switch (variant) {
        case 0:
          sum += grid.distance(p);
          break;
        case 1:
          sum += lookup_plain(g, values, inverse_spacing, p);
          break;
        case 2:
          sum += lookup_mantissa(g, values, inverse_size, bits, p);
          break;
        default:
          sum += grid.distance_and_gradient(p, gradient);
          break;
      }
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * 1024);
}
BENCHMARK(BM_DistanceGridLookup)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->ArgNames({"variant", "local"});

}  // namespace
