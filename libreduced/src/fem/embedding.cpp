#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "fem/element_bvh.hpp"
#include "fem/triangle_closest_point.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace khz::reduced {

namespace {

// A point is inside an element when its local coordinates are inside the reference element up
// to this slack (barycentric or natural units), so points on shared faces and vertices are
// found in every element that touches them rather than in none.
constexpr double inside_tolerance = 1e-12;
// Element boxes grow by this fraction of their diagonal, so a point accepted within the
// tolerance above is never missed because it lies a rounding error outside its element's box.
constexpr double box_padding = 1e-10;

using Triangle = std::array<int, 3>;

// The element types as MeshEmbedding needs them: local coordinates (barycentric for
// tetrahedra, natural ξ for hexahedra), how far inside the reference element they are, the
// shape functions there, and the boundary as triangles of local node indices.
struct Tetrahedron {
  static constexpr int nodes = 4;
  using Corners = TetCorners;
  using Local = Eigen::Vector4d;
  static constexpr std::array<Triangle, 4> boundary{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};

  static Local node_local(int a) { return Local::Unit(a); }
  // Barycentric coordinates extend affinely to any point, so they always exist.
  static std::optional<Local> local_coordinates(const Corners& corners, const Eigen::Vector3d& x) {
    return tet_barycentric(corners, x);
  }
  static double margin(const Local& local) { return local.minCoeff(); }
  static void shape(const Corners& corners, const Local& local, EmbeddedPoint& point) {
    point.weights.head<4>() = local;
    point.gradients.topRows<4>() = tet_shape_gradients(corners);
  }
};

struct Hexahedron {
  static constexpr int nodes = 8;
  using Corners = HexCorners;
  using Local = Eigen::Vector3d;
  // Each VTK face (bottom, top, then the four sides) split into two triangles along a diagonal;
  // for non-planar faces this is the boundary the distance is measured to.
  static constexpr std::array<Triangle, 12> boundary{{{0, 3, 2},
                                                      {0, 2, 1},
                                                      {4, 5, 6},
                                                      {4, 6, 7},
                                                      {0, 1, 5},
                                                      {0, 5, 4},
                                                      {1, 2, 6},
                                                      {1, 6, 5},
                                                      {2, 3, 7},
                                                      {2, 7, 6},
                                                      {3, 0, 4},
                                                      {3, 4, 7}}};

  static Local node_local(int a) { return hex_node_natural_coordinates().row(a).transpose(); }
  // Newton on the trilinear map; it can fail for points far outside a distorted element.
  static std::optional<Local> local_coordinates(const Corners& corners, const Eigen::Vector3d& x) {
    return hex_natural_coordinates(corners, x);
  }
  static double margin(const Local& local) { return 1.0 - local.cwiseAbs().maxCoeff(); }
  static void shape(const Corners& corners, const Local& local, EmbeddedPoint& point) {
    point.weights = hex_shape_values(local);
    point.gradients = hex_shape_gradients(corners, local).gradients;
  }
};

template <typename Element>
typename Element::Corners element_corners(const VolumeMesh& mesh, Eigen::Index element) {
  typename Element::Corners corners;
  for (int a = 0; a < Element::nodes; ++a) {
    corners.row(a) = mesh.vertices.row(mesh.elements(element, a));
  }
  return corners;
}

// Where on an element's boundary a point outside it is nearest: the squared distance, and the
// local coordinates of that boundary point (interpolated from the triangle's corner nodes, exact
// for planar faces).
template <typename Element>
struct BoundaryPoint {
  double squared_distance = std::numeric_limits<double>::infinity();
  typename Element::Local local;
};

template <typename Element>
BoundaryPoint<Element> nearest_boundary_point(const typename Element::Corners& corners,
                                              const Eigen::Vector3d& x) {
  BoundaryPoint<Element> best;
  for (const Triangle& triangle : Element::boundary) {
    const detail::TriangleClosestPoint closest = detail::closest_point_on_triangle(
        x, corners.row(triangle[0]).transpose(), corners.row(triangle[1]).transpose(),
        corners.row(triangle[2]).transpose());
    if (closest.squared_distance < best.squared_distance) {
      best.squared_distance = closest.squared_distance;
      best.local = Element::Local::Zero();
      for (int k = 0; k < 3; ++k) {
        best.local += closest.barycentric[k] * Element::node_local(triangle[k]);
      }
    }
  }
  return best;
}

template <typename Element>
EmbeddedPoint embedded_point(Eigen::Index element, const typename Element::Corners& corners,
                             const typename Element::Local& local, double distance_outside) {
  EmbeddedPoint point;
  point.element = element;
  Element::shape(corners, local, point);
  point.distance_outside = distance_outside;
  return point;
}

// Rejects elements with no interior: their local coordinates and gradients are undefined.
// FemModel rejects them too, so every mesh that can be simulated can be embedded into.
void check_element_shapes(const VolumeMesh& mesh) {
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    if (mesh.element_type == ElementType::tetrahedron) {
      if (!(tet_signed_volume(element_corners<Tetrahedron>(mesh, e)) > 0.0)) {
        throw MeshError("element " + std::to_string(e) + " is inverted or degenerate", e);
      }
      continue;
    }
    const HexCorners corners = element_corners<Hexahedron>(mesh, e);
    for (const QuadraturePoint& q : hex_gauss_points()) {
      if (!(hex_shape_gradients(corners, q.xi).jacobian_determinant > 0.0)) {
        throw MeshError("element " + std::to_string(e) + " is inverted or degenerate", e);
      }
    }
  }
}

std::vector<Eigen::AlignedBox3d> element_boxes(const VolumeMesh& mesh) {
  std::vector<Eigen::AlignedBox3d> boxes(static_cast<std::size_t>(mesh.num_elements()));
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    Eigen::AlignedBox3d& box = boxes[static_cast<std::size_t>(e)];
    for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
      box.extend(mesh.vertices.row(mesh.elements(e, a)).transpose());
    }
    const Eigen::Vector3d pad = Eigen::Vector3d::Constant(box_padding * box.diagonal().norm());
    box.min() -= pad;
    box.max() += pad;
  }
  return boxes;
}

void check_element_index(const VolumeMesh& mesh, const EmbeddedPoint& point) {
  if (point.element < 0 || point.element >= mesh.num_elements()) {
    throw Error("embedded point names element " + std::to_string(point.element) +
                ", the mesh has " + std::to_string(mesh.num_elements()));
  }
}

void check_full_size(const VolumeMesh& mesh, Eigen::Index size, const char* what) {
  if (size != 3 * mesh.num_vertices()) {
    throw Error(std::string(what) + " has " + std::to_string(size) + " entries, the mesh needs " +
                std::to_string(3 * mesh.num_vertices()));
  }
}

}  // namespace

struct MeshEmbedding::Data {
  VolumeMesh mesh;
  detail::ElementBvh bvh;

  template <typename Element>
  EmbeddedPoint locate(const Eigen::Vector3d& x) const;
};

// The element containing x, or else the nearest one (thesis §2.5.2: a rendering-mesh vertex is
// carried by the voxel containing it; §3.6.1: pointshell points likewise).
template <typename Element>
EmbeddedPoint MeshEmbedding::Data::locate(const Eigen::Vector3d& x) const {
  // Among the elements containing x (several when x is on a shared face, edge or vertex), take
  // the one x is deepest inside, the lower index on ties: the answer then depends on the mesh
  // alone, not on the tree's traversal order.
  Eigen::Index best = -1;
  double best_margin = 0.0;
  typename Element::Local best_local;
  bvh.visit_containing(x, [&](int e) {
    const auto local = Element::local_coordinates(element_corners<Element>(mesh, e), x);
    if (!local) return false;
    const double margin = Element::margin(*local);
    if (margin < -inside_tolerance) return false;
    if (best < 0 || margin > best_margin || (margin == best_margin && e < best)) {
      best = e;
      best_margin = margin;
      best_local = *local;
    }
    // Strictly inside one element means outside every other (elements do not overlap).
    return margin > inside_tolerance;
  });
  if (best >= 0) {
    return embedded_point<Element>(best, element_corners<Element>(mesh, best), best_local, 0.0);
  }

  // Outside the mesh: x is in no element, so its distance to an element is its distance to the
  // element's boundary triangles.
  const detail::ElementBvh::Nearest nearest = bvh.nearest(x, [&](int e) {
    return nearest_boundary_point<Element>(element_corners<Element>(mesh, e), x).squared_distance;
  });
  const typename Element::Corners corners = element_corners<Element>(mesh, nearest.element);
  // Extrapolate the element's field to x; if its local coordinates cannot be found, use those
  // of the nearest boundary point (the field is then constant along the normal direction).
  const auto local = Element::local_coordinates(corners, x);
  return embedded_point<Element>(nearest.element, corners,
                                 local ? *local : nearest_boundary_point<Element>(corners, x).local,
                                 std::sqrt(nearest.squared_distance));
}

MeshEmbedding::MeshEmbedding(const VolumeMesh& mesh) {
  validate(mesh);
  if (mesh.num_elements() == 0) throw MeshError("cannot embed into a mesh without elements");
  check_element_shapes(mesh);
  m_data = std::make_unique<Data>(Data{mesh, detail::ElementBvh(element_boxes(mesh))});
}

MeshEmbedding::~MeshEmbedding() = default;
MeshEmbedding::MeshEmbedding(MeshEmbedding&&) noexcept = default;
MeshEmbedding& MeshEmbedding::operator=(MeshEmbedding&&) noexcept = default;

EmbeddedPoint MeshEmbedding::locate(const Eigen::Vector3d& x) const {
  if (!x.allFinite()) throw Error("cannot embed a point with a non-finite coordinate");
  return m_data->mesh.element_type == ElementType::tetrahedron ? m_data->locate<Tetrahedron>(x)
                                                               : m_data->locate<Hexahedron>(x);
}

std::vector<EmbeddedPoint> MeshEmbedding::locate_all(
    const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>& points)
    const {
  // Checked up front: an exception must not leave the parallel loop.
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    if (!points.row(p).allFinite()) {
      throw Error("cannot embed point " + std::to_string(p) + ": non-finite coordinate");
    }
  }
  std::vector<EmbeddedPoint> embedded(static_cast<std::size_t>(points.rows()));
  const bool tetrahedra = m_data->mesh.element_type == ElementType::tetrahedron;
#pragma omp parallel for num_threads(worker_threads()) schedule(dynamic, 64)
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    const Eigen::Vector3d x = points.row(p).transpose();
    embedded[static_cast<std::size_t>(p)] =
        tetrahedra ? m_data->locate<Tetrahedron>(x) : m_data->locate<Hexahedron>(x);
  }
  return embedded;
}

Eigen::Vector3d MeshEmbedding::interpolate(const EmbeddedPoint& point,
                                           const Eigen::VectorXd& u) const {
  const VolumeMesh& mesh = m_data->mesh;
  check_element_index(mesh, point);
  check_full_size(mesh, u.size(), "displacement");
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
    displacement += point.weights[a] * u.segment<3>(3 * mesh.elements(point.element, a));
  }
  return displacement;
}

void MeshEmbedding::distribute_force(const EmbeddedPoint& point, const Eigen::Vector3d& f,
                                     Eigen::VectorXd& forces) const {
  const VolumeMesh& mesh = m_data->mesh;
  check_element_index(mesh, point);
  check_full_size(mesh, forces.size(), "force vector");
  for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
    forces.segment<3>(3 * mesh.elements(point.element, a)) += point.weights[a] * f;
  }
}

PointModes MeshEmbedding::modes(const EmbeddedPoint& point, const Eigen::MatrixXd& basis) const {
  const VolumeMesh& mesh = m_data->mesh;
  check_element_index(mesh, point);
  check_full_size(mesh, basis.rows(), "basis");
  const Eigen::Index r = basis.cols();
  // Thesis eq. 3.6: U_s = Σ_a φ_a(X) U_a; eq. 3.7: F_{s,j} = ∂(U_s)_j/∂X = Σ_a U_{a,j} ∇φ_aᵀ,
  // with U_a the three rows of node a and U_{a,j} its column j.
  PointModes modes;
  modes.displacement.setZero(3, r);
  modes.gradient.assign(static_cast<std::size_t>(r), Eigen::Matrix3d::Zero());
  for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
    const auto node_rows = basis.middleRows<3>(3 * mesh.elements(point.element, a));
    modes.displacement += point.weights[a] * node_rows;
    const Eigen::RowVector3d gradient = point.gradients.row(a);
    for (Eigen::Index j = 0; j < r; ++j) {
      modes.gradient[static_cast<std::size_t>(j)] += node_rows.col(j) * gradient;
    }
  }
  return modes;
}

const VolumeMesh& MeshEmbedding::mesh() const noexcept { return m_data->mesh; }

}  // namespace khz::reduced
