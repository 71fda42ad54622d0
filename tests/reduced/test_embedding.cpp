#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Interpolating or extrapolating a linear field (magnitude ≈ 5) is exact up to rounding where
// the local coordinates are: on tetrahedra and parallelepipeds (measured ≤ 4e-15 over 2000
// points). On distorted hexahedra Newton stops at a residual of 1e-13 × the element's diagonal
// (hex_natural_coordinates), which |A| ≈ 3 amplifies (measured ≤ 2e-13).
constexpr double field_tolerance = 2e-14;
constexpr double distorted_field_tolerance = 5e-13;

const Eigen::Vector3d box_min(-0.5, 0.0, 0.25);
const Eigen::Vector3d box_max(1.0, 2.0, 1.25);

Eigen::Matrix3d field_gradient() {
  Eigen::Matrix3d a;
  a << 0.3, -1.2, 0.7, 2.0, 0.1, -0.4, -0.9, 0.5, 1.5;
  return a;
}
const Eigen::Vector3d field_offset(0.2, -0.7, 1.1);

// u(X) = A X + b at every vertex: a field that both element types reproduce exactly.
Eigen::VectorXd linear_field(const VolumeMesh& mesh) {
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    u.segment<3>(3 * v) = field_gradient() * mesh.vertices.row(v).transpose() + field_offset;
  }
  return u;
}

Eigen::Vector3d random_point(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                             std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return lo + Eigen::Vector3d(unit(random), unit(random), unit(random)).cwiseProduct(hi - lo);
}

// The point with local coordinates `local` (barycentric or natural) of element e.
Eigen::Vector3d point_in_element(const VolumeMesh& mesh, Eigen::Index e,
                                 const Eigen::VectorXd& weights) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
    x += weights[a] * mesh.vertices.row(mesh.elements(e, a)).transpose();
  }
  return x;
}

// Random points inside random elements (also for meshes whose hull is not a box).
PointMatrix random_element_points(const VolumeMesh& mesh, int count, std::mt19937& random) {
  std::uniform_int_distribution<Eigen::Index> element(0, mesh.num_elements() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> natural(-0.95, 0.95);
  PointMatrix points(count, 3);
  for (int p = 0; p < count; ++p) {
    Eigen::VectorXd weights;
    if (mesh.element_type == ElementType::tetrahedron) {
      Eigen::Vector4d w(unit(random), unit(random), unit(random), unit(random));
      weights = (w.array() + 0.05).matrix() / (w.sum() + 0.2);
    } else {
      weights = hex_shape_values({natural(random), natural(random), natural(random)});
    }
    points.row(p) = point_in_element(mesh, element(random), weights).transpose();
  }
  return points;
}

void expect_same(const EmbeddedPoint& a, const EmbeddedPoint& b) {
  EXPECT_EQ(a.element, b.element);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.gradients, b.gradients);
  EXPECT_EQ(a.distance_outside, b.distance_outside);
}

// Every check that a linear field u = A X + b makes of an embedded point inside the mesh.
void expect_reproduces_linear_field(const MeshEmbedding& embedding, const Eigen::Vector3d& x,
                                    double tolerance = field_tolerance) {
  const EmbeddedPoint point = embedding.locate(x);
  ASSERT_GE(point.element, 0);
  EXPECT_EQ(point.distance_outside, 0.0);
  EXPECT_NEAR(point.weights.sum(), 1.0, 1e-13);
  EXPECT_GE(point.weights.minCoeff(), -1e-12);
  const Eigen::VectorXd u = linear_field(embedding.mesh());
  const Eigen::Vector3d expected = field_gradient() * x + field_offset;
  EXPECT_LT((embedding.interpolate(point, u) - expected).norm(), tolerance) << x.transpose();
  const PointModes modes = embedding.modes(point, u);
  ASSERT_EQ(modes.gradient.size(), 1u);
  EXPECT_LT((modes.gradient[0] - field_gradient()).norm(), tolerance) << x.transpose();
}

// A parallelepiped mesh: the box sheared, rotated and moved.
VolumeMesh transformed(VolumeMesh mesh, const Eigen::Matrix3d& map) {
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    mesh.vertices.row(v) = (map * mesh.vertices.row(v).transpose()).transpose();
  }
  return mesh;
}

Eigen::Matrix3d shear_and_rotation() {
  Eigen::Matrix3d shear;
  shear << 1.0, 0.4, -0.3, 0.0, 1.2, 0.25, 0.0, 0.0, 0.9;
  return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()).toRotationMatrix() * shear;
}

// Interior lattice points moved by up to 15% of a cell: general trilinear hexahedra with
// non-planar faces, and tetrahedra of varied shape.
VolumeMesh jittered(VolumeMesh mesh, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  const Eigen::Vector3d cell(0.5, 0.5, 0.5);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    const bool interior =
        ((x - box_min).array() > 1e-9).all() && ((box_max - x).array() > 1e-9).all();
    if (!interior) continue;
    for (int k = 0; k < 3; ++k) mesh.vertices(v, k) += jitter(random) * cell[k];
  }
  return mesh;
}

class EmbeddingOfBox : public ::testing::TestWithParam<ElementType> {
 protected:
  VolumeMesh box() const {
    // 3×4×2 cells of 0.5 m.
    const Eigen::Vector3i cells(3, 4, 2);
    return GetParam() == ElementType::tetrahedron ? box_tet_mesh(box_min, box_max, cells)
                                                  : box_hex_mesh(box_min, box_max, cells);
  }
};

INSTANTIATE_TEST_SUITE_P(ElementTypes, EmbeddingOfBox,
                         ::testing::Values(ElementType::tetrahedron, ElementType::hexahedron),
                         [](const auto& param_info) {
                           return param_info.param == ElementType::tetrahedron ? "Tetrahedra"
                                                                               : "Hexahedra";
                         });

TEST_P(EmbeddingOfBox, InterpolatesLinearFieldExactlyAtRandomInteriorPoints) {
  const MeshEmbedding embedding(box());
  std::mt19937 random(1);
  for (int p = 0; p < 300; ++p) {
    expect_reproduces_linear_field(embedding, random_point(box_min, box_max, random));
  }
}

TEST_P(EmbeddingOfBox, LocatesVerticesAndSharedFacesInAnElementContainingThem) {
  const MeshEmbedding embedding(box());
  const VolumeMesh& mesh = embedding.mesh();
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    points.push_back(mesh.vertices.row(v).transpose());  // shared by up to 24 tetrahedra
  }
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {  // face centres, edge midpoints
    for (Eigen::Index a = 1; a < mesh.elements.cols(); ++a) {
      points.push_back(
          0.5 * (mesh.vertices.row(mesh.elements(e, 0)) + mesh.vertices.row(mesh.elements(e, a)))
                    .transpose());
    }
  }
  PointMatrix rows(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t p = 0; p < points.size(); ++p) {
    expect_reproduces_linear_field(embedding, points[p]);
    rows.row(static_cast<Eigen::Index>(p)) = points[p].transpose();
  }
  // The choice among the touching elements is a function of the point alone.
  const std::vector<EmbeddedPoint> all = embedding.locate_all(rows);
  for (std::size_t p = 0; p < points.size(); ++p) expect_same(all[p], embedding.locate(points[p]));
}

TEST_P(EmbeddingOfBox, AttachesPointsOutsideToTheNearestElement) {
  const MeshEmbedding embedding(box());
  const Eigen::AlignedBox3d hull(box_min, box_max);
  const Eigen::VectorXd u = linear_field(embedding.mesh());
  std::mt19937 random(2);
  std::uniform_int_distribution<int> axis(0, 2);
  std::uniform_int_distribution<int> side(0, 1);
  for (int p = 0; p < 200; ++p) {
    // 0.01 m off a random face, or off an edge or corner for the later points.
    Eigen::Vector3d x = random_point(box_min, box_max, random);
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    for (int k = 0; k < (p < 100 ? 1 : 3); ++k) {
      const int a = axis(random);
      const bool high = side(random) == 1;
      x[a] = high ? box_max[a] : box_min[a];
      offset[a] = high ? 1.0 : -1.0;
    }
    x += 0.01 * offset.normalized();
    const EmbeddedPoint point = embedding.locate(x);
    EXPECT_NEAR(point.distance_outside, hull.exteriorDistance(x), 1e-14);
    EXPECT_NEAR(point.distance_outside, 0.01, 1e-14);
    // Nearest: the element touches the point of the box nearest to x.
    const Eigen::Vector3d nearest = x.cwiseMax(box_min).cwiseMin(box_max);
    const VolumeMesh& mesh = embedding.mesh();
    if (mesh.element_type == ElementType::tetrahedron) {
      TetCorners corners;
      for (int a = 0; a < 4; ++a)
        corners.row(a) = mesh.vertices.row(mesh.elements(point.element, a));
      EXPECT_GE(tet_barycentric(corners, nearest).minCoeff(), -1e-12);
    } else {
      HexCorners corners;
      for (int a = 0; a < 8; ++a)
        corners.row(a) = mesh.vertices.row(mesh.elements(point.element, a));
      EXPECT_LE(hex_natural_coordinates(corners, nearest)->cwiseAbs().maxCoeff(), 1 + 1e-12);
    }
    // The element's field extrapolated: still exact for a linear field.
    EXPECT_NEAR(point.weights.sum(), 1.0, 1e-13);
    EXPECT_LT((embedding.interpolate(point, u) - (field_gradient() * x + field_offset)).norm(),
              field_tolerance);
  }
}

TEST_P(EmbeddingOfBox, LocateAllMatchesLocate) {
  const MeshEmbedding embedding(box());
  std::mt19937 random(3);
  PointMatrix points(500, 3);
  for (Eigen::Index p = 0; p < points.rows(); ++p) {  // inside and up to 0.5 m outside
    points.row(p) =
        random_point((box_min.array() - 0.5).matrix(), (box_max.array() + 0.5).matrix(), random)
            .transpose();
  }
  const std::vector<EmbeddedPoint> all = embedding.locate_all(points);
  ASSERT_EQ(all.size(), 500u);
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    expect_same(all[static_cast<std::size_t>(p)], embedding.locate(points.row(p).transpose()));
  }
}

TEST_P(EmbeddingOfBox, DistributeForceIsTheTransposeOfInterpolate) {
  const MeshEmbedding embedding(box());
  const Eigen::Index dofs = 3 * embedding.mesh().num_vertices();
  std::mt19937 random(4);
  for (int p = 0; p < 50; ++p) {
    const Eigen::Vector3d x =
        random_point((box_min.array() - 0.2).matrix(), (box_max.array() + 0.2).matrix(), random);
    const EmbeddedPoint point = embedding.locate(x);
    const Eigen::VectorXd u = Eigen::VectorXd::Random(dofs);
    const Eigen::Vector3d f = Eigen::Vector3d::Random();
    Eigen::VectorXd forces = Eigen::VectorXd::Zero(dofs);
    embedding.distribute_force(point, f, forces);
    EXPECT_NEAR(f.dot(embedding.interpolate(point, u)), forces.dot(u), 1e-13);
    // Forces add up: the total force is f.
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (Eigen::Index v = 0; v < embedding.mesh().num_vertices(); ++v) {
      total += forces.segment<3>(3 * v);
    }
    EXPECT_LT((total - f).norm(), 1e-14);
  }
}

TEST_P(EmbeddingOfBox, ModesMatchInterpolationAndItsDerivative) {
  const MeshEmbedding embedding(box());
  const Eigen::Index dofs = 3 * embedding.mesh().num_vertices();
  std::srand(5);
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(dofs, 4);
  std::mt19937 random(5);
  // Points at least ≈ 0.002 m inside their element, so x ± h stays in it.
  const PointMatrix points = random_element_points(embedding.mesh(), 40, random);
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    const Eigen::Vector3d x = points.row(p).transpose();
    const EmbeddedPoint point = embedding.locate(x);
    const PointModes modes = embedding.modes(point, basis);
    ASSERT_EQ(modes.displacement.cols(), 4);
    ASSERT_EQ(modes.gradient.size(), 4u);
    constexpr double h = 1e-5;
    for (Eigen::Index j = 0; j < 4; ++j) {
      const Eigen::VectorXd column = basis.col(j);
      EXPECT_LT((modes.displacement.col(j) - embedding.interpolate(point, column)).norm(), 1e-14);
      // F_j = ∂(U_s)_j/∂X by central differences (exact for the affine tetrahedra; O(h²) ≈
      // 1e-10 for the trilinear hexahedra).
      Eigen::Matrix3d difference;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(k);
        const EmbeddedPoint plus = embedding.locate(x + step);
        const EmbeddedPoint minus = embedding.locate(x - step);
        ASSERT_EQ(plus.element, point.element);
        ASSERT_EQ(minus.element, point.element);
        difference.col(k) =
            (embedding.interpolate(plus, column) - embedding.interpolate(minus, column)) / (2 * h);
      }
      EXPECT_LT((modes.gradient[static_cast<std::size_t>(j)] - difference).norm(), 1e-8);
    }
  }
}

TEST_P(EmbeddingOfBox, ShearedRotatedMeshReproducesLinearFields) {
  const Eigen::Matrix3d map = shear_and_rotation();
  const MeshEmbedding embedding(transformed(box(), map));
  std::mt19937 random(6);
  for (int p = 0; p < 200; ++p) {
    expect_reproduces_linear_field(embedding, map * random_point(box_min, box_max, random));
  }
  // Distances outside: along a face's normal, 0.01 m off the middle of the x = max face.
  const Eigen::Vector3d face_centre = map * Eigen::Vector3d(box_max.x(), 1.0, 0.75);
  const Eigen::Vector3d normal = map.inverse().transpose().col(0).normalized();
  const EmbeddedPoint outside = embedding.locate(face_centre + 0.01 * normal);
  EXPECT_NEAR(outside.distance_outside, 0.01, 1e-14);
  EXPECT_LT((embedding.interpolate(outside, linear_field(embedding.mesh())) -
             (field_gradient() * (face_centre + 0.01 * normal) + field_offset))
                .norm(),
            field_tolerance);
}

TEST_P(EmbeddingOfBox, DistortedMeshReproducesLinearFields) {
  const MeshEmbedding embedding(jittered(box(), 7));
  std::mt19937 random(7);
  const PointMatrix points = random_element_points(embedding.mesh(), 300, random);
  for (Eigen::Index p = 0; p < points.rows(); ++p) {
    expect_reproduces_linear_field(embedding, points.row(p).transpose(), distorted_field_tolerance);
  }
}

TEST(Embedding, BreaksTiesOnSharedFacesAndVerticesByLowestElement) {
  // 2×2×2 cells of 0.5 m: exact binary coordinates, so points on shared faces get natural
  // coordinates of exactly ±1 in every touching element.
  const MeshEmbedding embedding(box_hex_mesh(box_min, box_min.array() + 1.0, {2, 2, 2}));
  const Eigen::Vector3d centre = box_min.array() + 0.5;  // vertex of all 8 cells
  EXPECT_EQ(embedding.locate(centre).element, 0);
  // Face between cells 6 (i=0, j=1, k=1) and 7 (i=1, j=1, k=1).
  EXPECT_EQ(embedding.locate(centre + Eigen::Vector3d(0.0, 0.25, 0.25)).element, 6);
  // Edge shared by cells 5 and 7 (i=1, k=1; j=0 and 1).
  EXPECT_EQ(embedding.locate(centre + Eigen::Vector3d(0.25, 0.0, 0.25)).element, 5);
}

TEST(Embedding, FallsBackToNearestBoundaryPointWhereNewtonFails) {
  // One hexahedron with a corner pulled far out: from a distant point on the far side,
  // Newton on the trilinear map diverges.
  VolumeMesh mesh;
  mesh.element_type = ElementType::hexahedron;
  mesh.vertices.resize(8, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 6, 6, 6, 0, 1, 1;
  mesh.elements.resize(1, 8);
  mesh.elements << 0, 1, 2, 3, 4, 5, 6, 7;
  const MeshEmbedding embedding(mesh);
  HexCorners corners = mesh.vertices;
  const Eigen::Vector3d x(-20.107, 41.0448, 41.6861);
  ASSERT_FALSE(hex_natural_coordinates(corners, x).has_value());
  const EmbeddedPoint point = embedding.locate(x);
  EXPECT_EQ(point.element, 0);
  // Natural coordinates of the nearest boundary point: on the element, weights in [0, 1].
  EXPECT_GE(point.weights.minCoeff(), 0.0);
  EXPECT_NEAR(point.weights.sum(), 1.0, 1e-13);
  const Eigen::Vector3d nearest = corners.transpose() * point.weights;
  EXPECT_NEAR((x - nearest).norm(), point.distance_outside, 1e-9);
  EXPECT_GT(point.distance_outside, 10.0);
}

TEST(Embedding, RejectsInvalidMeshes) {
  EXPECT_TRUE(
      throws_with_message<MeshError>([] { MeshEmbedding{VolumeMesh{}}; }, "without elements"));
  VolumeMesh mesh = box_tet_mesh(box_min, box_max, {1, 1, 1});
  mesh.elements(3, 2) = 99;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { MeshEmbedding{mesh}; }, "element 3"));
  mesh = box_tet_mesh(box_min, box_max, {1, 1, 1});
  std::swap(mesh.elements(4, 0), mesh.elements(4, 1));
  EXPECT_TRUE(throws_with_message<MeshError>([&] { MeshEmbedding{mesh}; },
                                             "element 4 is inverted or degenerate"));
  mesh = box_hex_mesh(box_min, box_max, {2, 1, 1});
  mesh.vertices.row(mesh.elements(1, 6)) = mesh.vertices.row(mesh.elements(1, 0));
  EXPECT_TRUE(throws_with_message<MeshError>([&] { MeshEmbedding{mesh}; },
                                             "element 1 is inverted or degenerate"));
}

TEST(Embedding, RejectsWrongSizesAndPoints) {
  const MeshEmbedding embedding(box_hex_mesh(box_min, box_max, {1, 1, 1}));
  const EmbeddedPoint point = embedding.locate({0.0, 1.0, 0.5});
  EXPECT_TRUE(
      throws_with_message<Error>([&] { embedding.modes(point, Eigen::MatrixXd::Zero(23, 2)); },
                                 "basis has 23 entries, the mesh needs 24"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { embedding.interpolate(point, Eigen::VectorXd::Zero(25)); }, "displacement has 25"));
  Eigen::VectorXd forces = Eigen::VectorXd::Zero(3);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { embedding.distribute_force(point, Eigen::Vector3d::Ones(), forces); },
      "force vector has 3"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { embedding.interpolate(EmbeddedPoint{}, Eigen::VectorXd::Zero(24)); },
      "names element -1, the mesh has 1"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_with_message<Error>([&] { embedding.locate({0.0, nan, 0.0}); }, "non-finite"));
  PointMatrix points = PointMatrix::Zero(3, 3);
  points(2, 0) = nan;
  EXPECT_TRUE(throws_with_message<Error>([&] { embedding.locate_all(points); }, "point 2"));
}

TEST(Embedding, IsMoveable) {
  MeshEmbedding a(box_tet_mesh(box_min, box_max, {1, 1, 1}));
  MeshEmbedding b(std::move(a));
  EXPECT_EQ(b.mesh().num_elements(), 6);
  MeshEmbedding c(box_hex_mesh(box_min, box_max, {1, 1, 1}));
  c = std::move(b);
  EXPECT_EQ(c.locate(box_min).distance_outside, 0.0);
}

}  // namespace
}  // namespace khz::reduced
