#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include "meshing/cube_corners.hpp"
#include "meshing/triangle_box_overlap.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

constexpr int max_resolution = 1024;
// Voxel and lattice-point indices are 32-bit: (1024 + 1)³ lattice points fit.
static_assert(std::uint64_t(max_resolution + 1) * (max_resolution + 1) * (max_resolution + 1) <
              (std::uint64_t(1) << 32));

void check_options(const VoxelizeOptions& options) {
  if (options.resolution < 1 || options.resolution > max_resolution) {
    throw Error("voxelize: resolution must be in [1, " + std::to_string(max_resolution) +
                "], got " + std::to_string(options.resolution));
  }
  if (!(options.enlargement >= 1.0) || !std::isfinite(options.enlargement)) {
    throw Error("voxelize: enlargement must be a finite number >= 1, got " +
                std::to_string(options.enlargement));
  }
}

/// The cube grid of §2.5.2: all sides equal, centred on the model, enlarged by a factor.
/// Computation happens in voxel coordinates, where voxel (i, j, k) is the unit cube with lowest
/// corner (i, j, k) and the grid spans [0, resolution]³.
struct VoxelGrid {
  int resolution = 0;
  Eigen::Vector3d origin;  // world position of lattice point (0, 0, 0)
  double voxel_size = 0.0;

  Eigen::Vector3d to_voxel(const Eigen::Vector3d& x) const {
    // Mathematically inside [0, resolution]³ (enlargement ≥ 1); clamping removes rounding
    // overshoot that could push a triangle on the grid's outer face out of its voxels.
    return ((x - origin) / voxel_size).cwiseMax(0.0).cwiseMin(double(resolution));
  }
  std::uint32_t voxel(int i, int j, int k) const {
    return std::uint32_t(i) + std::uint32_t(resolution) * (j + std::uint32_t(resolution) * k);
  }
  std::uint32_t num_voxels() const { return voxel(0, 0, resolution); }
  Eigen::Vector3i voxel_position(std::uint32_t v) const {
    const auto r = std::uint32_t(resolution);
    return Eigen::Vector3i(int(v % r), int(v / r % r), int(v / r / r));
  }
  std::uint32_t lattice_point(const Eigen::Vector3i& p) const {
    const auto n = std::uint32_t(resolution) + 1;
    return std::uint32_t(p.x()) + n * (p.y() + n * std::uint32_t(p.z()));
  }
  Eigen::Vector3d lattice_position(std::uint32_t point) const {
    const auto n = std::uint32_t(resolution) + 1;
    return origin + voxel_size * Eigen::Vector3d(point % n, point / n % n, point / n / n);
  }
};

VoxelGrid fit_grid(const TriangleMesh& soup, const VoxelizeOptions& options) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index t = 0; t < soup.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) box.extend(soup.vertices.row(soup.triangles(t, k)).transpose());
  }
  const double extent = box.sizes().maxCoeff();
  if (!(extent > 0.0)) {
    throw Error("voxelize: all triangle vertices coincide, the mesh has no extent");
  }
  VoxelGrid grid;
  grid.resolution = options.resolution;
  const double side = options.enlargement * extent;
  grid.voxel_size = side / options.resolution;
  grid.origin = box.center() - Eigen::Vector3d::Constant(side / 2);
  return grid;
}

/// Sorted indices of the voxels whose closed box touches some triangle. Each triangle is tested
/// against the voxels its bounding box touches.
std::vector<std::uint32_t> surface_voxels(const TriangleMesh& soup, const VoxelGrid& grid) {
  std::vector<std::uint32_t> voxels;
  const int last = grid.resolution - 1;
  for (Eigen::Index t = 0; t < soup.num_triangles(); ++t) {
    std::array<detail::Point3, 3> triangle;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(grid.resolution);
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = grid.to_voxel(soup.vertices.row(soup.triangles(t, k)).transpose());
      triangle[k] = {p.x(), p.y(), p.z()};
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    // Voxel i spans [i, i+1]: it touches [lo, hi] iff ceil(lo) − 1 ≤ i ≤ floor(hi).
    std::array<int, 3> first{};
    std::array<int, 3> end{};  // one past the last
    for (int axis = 0; axis < 3; ++axis) {
      first[axis] = std::clamp(int(std::ceil(lo[axis])) - 1, 0, last);
      end[axis] = std::clamp(int(std::floor(hi[axis])), 0, last) + 1;
    }
    for (int k = first[2]; k < end[2]; ++k) {
      for (int j = first[1]; j < end[1]; ++j) {
        for (int i = first[0]; i < end[0]; ++i) {
          if (detail::triangle_overlaps_box(triangle, {i + 0.5, j + 0.5, k + 0.5}, 0.5)) {
            voxels.push_back(grid.voxel(i, j, k));
          }
        }
      }
    }
  }
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  return voxels;
}

/// The surface voxels plus every voxel not reachable from the grid boundary through
/// face-adjacent untouched voxels, in grid order. A path of untouched voxels is a path of closed
/// boxes that miss the surface, so it cannot cross a closed surface: what it cannot reach is
/// enclosed.
std::vector<std::uint32_t> solid_voxels(const std::vector<std::uint32_t>& surface,
                                        const VoxelGrid& grid) {
  std::vector<bool> blocked(grid.num_voxels());  // surface, or already known to be outside
  for (const std::uint32_t v : surface) blocked[v] = true;
  std::vector<bool> outside(grid.num_voxels());
  // Breadth-first, so the queue holds a front (∝ resolution²), not the whole outside region.
  std::deque<std::uint32_t> queue;
  const auto visit = [&](const Eigen::Vector3i& p) {
    const std::uint32_t v = grid.voxel(p.x(), p.y(), p.z());
    if (blocked[v]) return;
    blocked[v] = true;
    outside[v] = true;
    queue.push_back(v);
  };
  const int r = grid.resolution;
  for (int a = 0; a < r; ++a) {
    for (int b = 0; b < r; ++b) {
      for (const int side : {0, r - 1}) {
        visit({side, a, b});
        visit({a, side, b});
        visit({a, b, side});
      }
    }
  }
  while (!queue.empty()) {
    const Eigen::Vector3i p = grid.voxel_position(queue.front());
    queue.pop_front();
    for (int axis = 0; axis < 3; ++axis) {
      for (const int step : {-1, 1}) {
        Eigen::Vector3i q = p;
        q[axis] += step;
        if (q[axis] >= 0 && q[axis] < r) visit(q);
      }
    }
  }
  std::vector<std::uint32_t> voxels;
  for (std::uint32_t v = 0; v < grid.num_voxels(); ++v) {
    if (!outside[v]) voxels.push_back(v);
  }
  return voxels;
}

/// One hexahedron per voxel; the lattice points the voxels use become the vertices, numbered in
/// grid order so that the result does not depend on how the voxels were found.
VolumeMesh hexahedra(const std::vector<std::uint32_t>& voxels, const VoxelGrid& grid) {
  const auto& offsets = detail::hex_corner_offsets();
  std::vector<std::uint32_t> corners;
  corners.reserve(8 * voxels.size());
  for (const std::uint32_t v : voxels) {
    const Eigen::Vector3i p = grid.voxel_position(v);
    for (const Eigen::Vector3i& offset : offsets) corners.push_back(grid.lattice_point(p + offset));
  }
  std::vector<std::uint32_t> points = corners;
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());

  VolumeMesh mesh;
  mesh.element_type = ElementType::hexahedron;
  mesh.vertices.resize(Eigen::Index(points.size()), 3);
  for (std::size_t n = 0; n < points.size(); ++n) {
    mesh.vertices.row(Eigen::Index(n)) = grid.lattice_position(points[n]).transpose();
  }
  mesh.elements.resize(Eigen::Index(voxels.size()), 8);
  for (std::size_t n = 0; n < corners.size(); ++n) {
    const auto found = std::lower_bound(points.begin(), points.end(), corners[n]);
    mesh.elements(Eigen::Index(n / 8), Eigen::Index(n % 8)) = int(found - points.begin());
  }
  return mesh;
}

}  // namespace

VolumeMesh voxelize(const TriangleMesh& soup, const VoxelizeOptions& options) {
  check_options(options);
  validate(soup);
  if (soup.num_triangles() == 0) throw Error("voxelize: the mesh has no triangles");
  const VoxelGrid grid = fit_grid(soup, options);
  const std::vector<std::uint32_t> surface = surface_voxels(soup, grid);
  return hexahedra(options.fill_interior ? solid_voxels(surface, grid) : surface, grid);
}

}  // namespace khz::reduced
