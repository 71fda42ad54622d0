#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include "meshing/cube_corners.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <sstream>

namespace khz::reduced {
namespace {

void check_box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
               const Eigen::Vector3i& cells) {
  if ((cells.array() < 1).any()) {
    std::ostringstream message;
    message << "box mesh needs at least one cell per axis, got " << cells.transpose();
    throw Error(message.str());
  }
  if (!min_corner.allFinite() || !max_corner.allFinite() ||
      !(min_corner.array() < max_corner.array()).all()) {
    std::ostringstream message;
    message << "box mesh needs finite corners with min < max in every coordinate, got min ("
            << min_corner.transpose() << ") and max (" << max_corner.transpose() << ")";
    throw Error(message.str());
  }
  // Six tetrahedra per cell is the largest count either generator produces; indices are int.
  const std::int64_t cell_count = std::int64_t(cells.x()) * cells.y() * cells.z();
  if (cell_count > std::numeric_limits<int>::max() / 6) {
    throw Error("box mesh with " + std::to_string(cell_count) + " cells is too large");
  }
}

/// The lattice vertices shared by both generators, numbered x fastest, then y, then z.
VolumeMesh box_lattice(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                       const Eigen::Vector3i& cells, ElementType type) {
  check_box(min_corner, max_corner, cells);
  const Eigen::Vector3d step = (max_corner - min_corner).cwiseQuotient(cells.cast<double>());
  VolumeMesh mesh;
  mesh.element_type = type;
  mesh.vertices.resize(Eigen::Index(cells.x() + 1) * (cells.y() + 1) * (cells.z() + 1), 3);
  Eigen::Index v = 0;
  for (int k = 0; k <= cells.z(); ++k) {
    for (int j = 0; j <= cells.y(); ++j) {
      for (int i = 0; i <= cells.x(); ++i) {
        // The last layer is placed exactly on max_corner, not at min + n·h (which may round).
        const Eigen::Vector3i index(i, j, k);
        for (int axis = 0; axis < 3; ++axis) {
          mesh.vertices(v, axis) = index[axis] == cells[axis]
                                       ? max_corner[axis]
                                       : min_corner[axis] + index[axis] * step[axis];
        }
        ++v;
      }
    }
  }
  return mesh;
}

/// Calls visit(cell, corners) for every cell in element order, corners being the vertex indices
/// of the cell's eight corners in VTK hexahedron order.
template <typename Visit>
void for_each_cell(const Eigen::Vector3i& cells, Visit visit) {
  const auto vertex = [&](const Eigen::Vector3i& p) {
    return p.x() + (cells.x() + 1) * (p.y() + (cells.y() + 1) * p.z());
  };
  Eigen::Index cell = 0;
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      for (int i = 0; i < cells.x(); ++i) {
        std::array<int, 8> corners{};
        for (int a = 0; a < 8; ++a) {
          corners[a] = vertex(Eigen::Vector3i(i, j, k) + detail::hex_corner_offsets()[a]);
        }
        visit(cell++, corners);
      }
    }
  }
}

// The Kuhn split as hexahedron node numbers (VTK order; node 0 is the cube's (0,0,0) corner,
// node 6 its (1,1,1) corner). Each tetrahedron walks from node 0 to node 6 along three cube
// edges, one per axis, in one of the six axis orders; tetrahedra from odd axis permutations
// have their middle nodes swapped so that all six are positively oriented.
constexpr std::array<std::array<int, 4>, 6> kuhn_tetrahedra = {{
    {0, 1, 2, 6},  // x, y, z
    {0, 5, 1, 6},  // x, z, y (swapped)
    {0, 2, 3, 6},  // y, x, z (swapped)
    {0, 3, 7, 6},  // y, z, x
    {0, 4, 5, 6},  // z, x, y
    {0, 7, 4, 6},  // z, y, x (swapped)
}};

}  // namespace

VolumeMesh box_hex_mesh(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                        const Eigen::Vector3i& cells) {
  VolumeMesh mesh = box_lattice(min_corner, max_corner, cells, ElementType::hexahedron);
  mesh.elements.resize(Eigen::Index(cells.x()) * cells.y() * cells.z(), 8);
  for_each_cell(cells, [&](Eigen::Index cell, const std::array<int, 8>& corners) {
    for (int a = 0; a < 8; ++a) mesh.elements(cell, a) = corners[a];
  });
  return mesh;
}

VolumeMesh box_tet_mesh(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                        const Eigen::Vector3i& cells) {
  VolumeMesh mesh = box_lattice(min_corner, max_corner, cells, ElementType::tetrahedron);
  mesh.elements.resize(6 * Eigen::Index(cells.x()) * cells.y() * cells.z(), 4);
  for_each_cell(cells, [&](Eigen::Index cell, const std::array<int, 8>& corners) {
    for (int t = 0; t < 6; ++t) {
      for (int a = 0; a < 4; ++a) mesh.elements(6 * cell + t, a) = corners[kuhn_tetrahedra[t][a]];
    }
  });
  return mesh;
}

}  // namespace khz::reduced
