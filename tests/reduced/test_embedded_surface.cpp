#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/reduced/subspace/vertex_normals.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/element_types.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;

// Affine fields are reproduced exactly by both element types, inside and extrapolated: what
// remains is rounding in positions and vectors of magnitude ≈ 3 (measured ≤ 2.1e-15).
constexpr double affine_tolerance = 1e-14;

// Reduced coordinates from a list. (Assigning a fixed-size vector to a VectorXd trips GCC 12's
// -Warray-bounds under -march=native.)
Eigen::VectorXd coordinates(std::initializer_list<double> values) {
  return Eigen::Map<const Eigen::VectorXd>(values.begin(),
                                           static_cast<Eigen::Index>(values.size()));
}

// u(X) = A X + t, one basis column per field.
struct AffineField {
  Eigen::Matrix3d gradient;
  Eigen::Vector3d offset;
};

Eigen::Matrix3d rotation() {
  return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

Eigen::Matrix3d shear() {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  s(0, 1) = 0.8;  // x += 0.8 y
  return s;
}

// Column 0: R − I (q_0 = 1 rotates by R), column 1: I (uniform scale), column 2: a shear,
// column 3: a general affine field. q = (s, s − 1, 0, 0) gives F = sR.
std::vector<AffineField> affine_fields() {
  Eigen::Matrix3d general;
  general << 0.3, -0.2, 0.1, 0.05, 0.25, -0.15, -0.1, 0.2, 0.4;
  return {{rotation() - Eigen::Matrix3d::Identity(), {0.1, -0.2, 0.3}},
          {Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()},
          {shear(), {0.0, 0.0, 0.05}},
          {general, {-0.3, 0.1, 0.2}}};
}

Eigen::MatrixXd affine_basis(const VolumeMesh& mesh, const std::vector<AffineField>& fields) {
  Eigen::MatrixXd basis(3 * mesh.num_vertices(), static_cast<Eigen::Index>(fields.size()));
  for (Eigen::Index j = 0; j < basis.cols(); ++j) {
    const AffineField& field = fields[static_cast<std::size_t>(j)];
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      basis.col(j).segment<3>(3 * v) =
          field.gradient * mesh.vertices.row(v).transpose() + field.offset;
    }
  }
  return basis;
}

// F(q) = I + Σ_j q_j A_j and t(q) = Σ_j q_j t_j: the deformation x ↦ F x + t the basis makes.
Eigen::Matrix3d deformation_gradient(const std::vector<AffineField>& fields,
                                     const Eigen::VectorXd& q) {
  Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
  for (std::size_t j = 0; j < fields.size(); ++j) {
    f += q[static_cast<Eigen::Index>(j)] * fields[j].gradient;
  }
  return f;
}
Eigen::Vector3d translation(const std::vector<AffineField>& fields, const Eigen::VectorXd& q) {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < fields.size(); ++j)
    t += q[static_cast<Eigen::Index>(j)] * fields[j].offset;
  return t;
}

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// The unit sphere in a box flatter than it: the caps |z| > 0.6 lie outside the volume mesh and
// extrapolate, the equator touches its sides.
class EmbeddedSurfaceInBox : public ::testing::TestWithParam<ElementType> {
 protected:
  VolumeMesh volume() const {
    const Eigen::Vector3d lo(-1.0, -1.0, -0.6);
    const Eigen::Vector3d hi(1.0, 1.0, 0.6);
    const Eigen::Vector3i cells(4, 4, 3);
    return GetParam() == ElementType::tetrahedron ? box_tet_mesh(lo, hi, cells)
                                                  : box_hex_mesh(lo, hi, cells);
  }
};

INSTANTIATE_TEST_SUITE_P(ElementTypes, EmbeddedSurfaceInBox,
                         ::testing::ValuesIn(test::all_element_types), test::element_type_name);

TEST_P(EmbeddedSurfaceInBox, ReproducesAffineFieldsInsideAndOutside) {
  const VolumeMesh mesh = volume();
  const MeshEmbedding embedding(mesh);
  const std::vector<AffineField> fields = affine_fields();
  const TriangleMesh sphere = test::uv_sphere(24, 12);
  const EmbeddedSurface surface(embedding, sphere, affine_basis(mesh, fields));
  ASSERT_EQ(surface.size(), sphere.num_vertices());
  ASSERT_EQ(surface.dimension(), 4);

  int outside = 0;
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    if (surface.embedded_point(s).distance_outside > 0.0) ++outside;
    const Eigen::Vector3d rest = sphere.vertices.row(s).transpose();
    EXPECT_EQ(surface.rest_position(s), rest);
    const Eigen::Vector3d normal = surface.rest_normal(s);
    EXPECT_NEAR(normal.norm(), 1.0, 1e-15);
    for (Eigen::Index j = 0; j < 4; ++j) {
      const AffineField& field = fields[static_cast<std::size_t>(j)];
      // U_s column j = A_j P_s + t_j (eq. 3.6); ΔN_s column j = F_{s,j} N_s with F_{s,j} = A_j.
      EXPECT_LT((surface.displacement_modes(s).col(j) - (field.gradient * rest + field.offset))
                    .cwiseAbs()
                    .maxCoeff(),
                affine_tolerance)
          << "point " << s << " column " << j;
      EXPECT_LT((surface.normal_modes(s).col(j) - field.gradient * normal).cwiseAbs().maxCoeff(),
                affine_tolerance)
          << "point " << s << " column " << j;
    }
  }
  EXPECT_GT(outside, 50);  // both caps

  const Eigen::VectorXd q = coordinates({0.3, -0.2, 0.5, 0.1});
  const Eigen::Matrix3d f = deformation_gradient(fields, q);
  VertexMatrix positions(surface.size(), 3);
  surface.deformed_positions(q, positions);
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    const Eigen::Vector3d expected =
        f * sphere.vertices.row(s).transpose() + translation(fields, q);
    EXPECT_LT((positions.row(s).transpose() - expected).cwiseAbs().maxCoeff(), affine_tolerance)
        << "point " << s;
  }
}

TEST_P(EmbeddedSurfaceInBox, NormalsAreExactUnderRotationAndUniformScale) {
  const VolumeMesh mesh = volume();
  const MeshEmbedding embedding(mesh);
  const std::vector<AffineField> fields = affine_fields();
  const TriangleMesh sphere = test::uv_sphere(24, 12);
  const EmbeddedSurface surface(embedding, sphere, affine_basis(mesh, fields));

  const double scale = 1.7;
  const Eigen::VectorXd q = coordinates({scale, scale - 1.0, 0.0, 0.0});  // F = sR
  ASSERT_LT((deformation_gradient(fields, q) - scale * rotation()).norm(), 1e-15);
  VertexMatrix positions(surface.size(), 3);
  VertexMatrix normals(surface.size(), 3);
  VertexMatrix exact(surface.size(), 3);
  surface.deformed_positions(q, positions);
  surface.deformed_normals(q, normals);
  vertex_normals(positions, sphere.triangles, exact);
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    const Eigen::Vector3d rotated = rotation() * surface.rest_normal(s);
    EXPECT_LT((normals.row(s).transpose() - rotated).cwiseAbs().maxCoeff(), affine_tolerance);
    EXPECT_LT((exact.row(s).transpose() - rotated).cwiseAbs().maxCoeff(), affine_tolerance);
  }
}

// Eq. 3.8 pushes N forward as F N; the true normal of the deformed surface is F⁻ᵀN. They agree
// for F = sR only: under shear the deformation-gradient normal is off by exactly the angle
// between the two, the approximation's documented limitation.
TEST_P(EmbeddedSurfaceInBox, NormalsUnderShearDeviateAsFNVersusFInverseTransposeN) {
  const VolumeMesh mesh = volume();
  const MeshEmbedding embedding(mesh);
  const std::vector<AffineField> fields = affine_fields();
  const TriangleMesh sphere = test::uv_sphere(24, 12);
  const EmbeddedSurface surface(embedding, sphere, affine_basis(mesh, fields));

  const Eigen::VectorXd q = coordinates({0.0, 0.0, 1.0, 0.0});  // F = I + S
  const Eigen::Matrix3d f = deformation_gradient(fields, q);
  VertexMatrix positions(surface.size(), 3);
  VertexMatrix normals(surface.size(), 3);
  VertexMatrix exact(surface.size(), 3);
  surface.deformed_positions(q, positions);
  surface.deformed_normals(q, normals);
  vertex_normals(positions, sphere.triangles, exact);
  double largest_deviation = 0.0;
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    const Eigen::Vector3d pushed = (f * surface.rest_normal(s)).normalized();
    const Eigen::Vector3d true_normal =
        (f.inverse().transpose() * surface.rest_normal(s)).normalized();
    EXPECT_LT((normals.row(s).transpose() - pushed).cwiseAbs().maxCoeff(), affine_tolerance);
    EXPECT_LT((exact.row(s).transpose() - true_normal).cwiseAbs().maxCoeff(), affine_tolerance);
    const double deviation = angle(normals.row(s).transpose(), exact.row(s).transpose());
    EXPECT_NEAR(deviation, angle(pushed, true_normal), 1e-14);  // measured ≤ 4.5e-16
    largest_deviation = std::max(largest_deviation, deviation);
  }
  // Not a rounding effect: at N = e_y alone the two differ by atan(0.8) = 38.7°.
  EXPECT_GT(largest_deviation, 0.6);
}

// For a general basis, U_s and ΔN_s are MeshEmbedding's modes at the point (extrapolated
// outside), and p_s is the embedding's interpolation of the full displacement U q.
TEST_P(EmbeddedSurfaceInBox, AgreesWithTheEmbeddingForAGeneralBasis) {
  const VolumeMesh mesh = volume();
  const MeshEmbedding embedding(mesh);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::MatrixXd basis =
      Eigen::MatrixXd::NullaryExpr(3 * mesh.num_vertices(), 5, [&] { return unit(random); });
  const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(5, [&] { return unit(random); });
  const Eigen::VectorXd u = basis * q;
  const TriangleMesh sphere = test::uv_sphere(16, 8);
  const EmbeddedSurface surface(embedding, sphere, basis);

  VertexMatrix positions(surface.size(), 3);
  VertexMatrix normals(surface.size(), 3);
  surface.deformed_positions(q, positions);
  surface.deformed_normals(q, normals);
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    const EmbeddedPoint& point = surface.embedded_point(s);
    EXPECT_EQ(point.element, embedding.locate(sphere.vertices.row(s).transpose()).element);
    const PointModes modes = embedding.modes(point, basis);
    const Eigen::Vector3d rest_normal = surface.rest_normal(s);
    EXPECT_EQ(surface.displacement_modes(s), modes.displacement);
    Eigen::Vector3d pushed = rest_normal;
    for (Eigen::Index j = 0; j < 5; ++j) {
      const Eigen::Vector3d column = modes.gradient[static_cast<std::size_t>(j)] * rest_normal;
      EXPECT_LT((surface.normal_modes(s).col(j) - column).cwiseAbs().maxCoeff(), 1e-14);
      pushed += q[j] * column;
    }
    const Eigen::Vector3d expected =
        sphere.vertices.row(s).transpose() + embedding.interpolate(point, u);
    // Rounding of sums of 5 and 40 terms of magnitude ≤ 1 (measured ≤ 9.5e-16).
    EXPECT_LT((positions.row(s).transpose() - expected).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((normals.row(s).transpose() - pushed.normalized()).cwiseAbs().maxCoeff(), 1e-14);
    // The bulk calls give what the per-point calls give, bit for bit.
    EXPECT_EQ(positions.row(s).transpose(), surface.position(s, q));
    EXPECT_EQ(normals.row(s).transpose(), surface.normal(s, q));
  }
}

// A surface big enough for the parallel path (1106 points × r = 12 is above the 8192 mode
// entries from which bulk calls use threads): the same bits for any thread count, equal to the
// serial per-point calls.
TEST(EmbeddedSurface, ResultsDoNotDependOnTheThreadCount) {
  const VolumeMesh mesh = box_hex_mesh({-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, {3, 3, 3});
  const MeshEmbedding embedding(mesh);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::MatrixXd basis =
      Eigen::MatrixXd::NullaryExpr(3 * mesh.num_vertices(), 12, [&] { return unit(random); });
  const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(12, [&] { return unit(random); });
  const EmbeddedSurface surface(embedding, test::uv_sphere(48, 24), basis);
  ASSERT_GE(surface.size() * surface.dimension(), 8192);

  std::vector<VertexMatrix> positions;
  std::vector<VertexMatrix> normals;
  for (const int threads : {1, 2, 3}) {
    const ScopedWorkerThreads count(threads);
    positions.emplace_back(surface.size(), 3);
    normals.emplace_back(surface.size(), 3);
    surface.deformed_positions(q, positions.back());
    surface.deformed_normals(q, normals.back());
  }
  for (std::size_t run = 1; run < positions.size(); ++run) {
    EXPECT_EQ(positions[run], positions[0]) << "run " << run;
    EXPECT_EQ(normals[run], normals[0]) << "run " << run;
  }
  for (Eigen::Index s = 0; s < surface.size(); ++s) {
    ASSERT_EQ(positions[0].row(s).transpose(), surface.position(s, q)) << "point " << s;
    ASSERT_EQ(normals[0].row(s).transpose(), surface.normal(s, q)) << "point " << s;
  }
}

TEST(EmbeddedSurface, RuntimeCallsAllocateNothing) {
  if (!test::allocation_count_sees_malloc) {
    GTEST_LOG_(INFO) << "counting operator new only (sanitized build)";
  }
  const VolumeMesh mesh = box_tet_mesh({-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, {2, 2, 2});
  const MeshEmbedding embedding(mesh);
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(3 * mesh.num_vertices(), 12);
  const Eigen::VectorXd q = Eigen::VectorXd::Random(12);
  for (const int slices : {8, 48}) {  // serial, and parallel as in the test above
    const TriangleMesh sphere = test::uv_sphere(slices, slices / 2);
    const EmbeddedSurface surface(embedding, sphere, basis);
    VertexMatrix positions(surface.size(), 3);
    VertexMatrix normals(surface.size(), 3);
    // The first parallel region may start the OpenMP thread pool.
    surface.deformed_positions(q, positions);
    test::allocation_count = 0;
    surface.deformed_positions(q, positions);
    surface.deformed_normals(q, normals);
    const Eigen::Vector3d sparse = surface.position(3, q) + surface.normal(3, q);
    vertex_normals(positions, sphere.triangles, normals);
    EXPECT_EQ(test::allocation_count.load(), 0u) << slices << " slices";
    EXPECT_TRUE(sparse.allFinite());
  }
}

TEST(EmbeddedSurface, KeepsTheRestNormalWhereThePushedNormalVanishes) {
  const VolumeMesh mesh = box_tet_mesh({-1.0, -1.0, -1.0}, {1.0, 1.0, 1.0}, {1, 1, 1});
  const MeshEmbedding embedding(mesh);
  // u = −z e_z: F(q) = I − q e_z e_zᵀ flattens z completely at q = 1.
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(3 * mesh.num_vertices(), 1);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) basis(3 * v + 2, 0) = -mesh.vertices(v, 2);
  VertexMatrix points(3, 3);
  points << 0.0, 0.0, 0.0, 0.5, 0.2, 0.1, 0.3, -0.4, 0.2;
  VertexMatrix normals(3, 3);
  normals << 0.0, 0.0, 2.0,  // normalized to e_z
      1.0, 0.0, 0.0,         // unaffected by F
      0.0, 0.0, 0.0;         // no normal
  const EmbeddedSurface surface(embedding, points, normals, basis);
  EXPECT_EQ(surface.rest_normal(0), Eigen::Vector3d::UnitZ());
  EXPECT_EQ(surface.rest_normal(2), Eigen::Vector3d::Zero());

  const auto normal_at = [&](Eigen::Index s, double q) {
    return surface.normal(s, Eigen::VectorXd::Constant(1, q));
  };
  EXPECT_LT((normal_at(0, 0.5) - Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_EQ(normal_at(0, 1.0), Eigen::Vector3d::UnitZ());                   // n' = 0: rest normal
  EXPECT_EQ(normal_at(0, 1.0 + 1e-14), Eigen::Vector3d::UnitZ());           // ‖n'‖ < 1e-12
  EXPECT_LT((normal_at(0, 1.5) + Eigen::Vector3d::UnitZ()).norm(), 1e-15);  // inverted: flips
  EXPECT_LT((normal_at(1, 1.0) - Eigen::Vector3d::UnitX()).norm(), 1e-15);
  EXPECT_EQ(normal_at(2, 0.5), Eigen::Vector3d::Zero());
  EXPECT_TRUE(normal_at(1, std::numeric_limits<double>::quiet_NaN()).hasNaN());
}

TEST(EmbeddedSurface, RejectsWrongSizesAndBadInput) {
  const VolumeMesh mesh = box_hex_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, {1, 1, 1});
  const MeshEmbedding embedding(mesh);
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(24, 2);
  const TriangleMesh cube = test::unit_cube_surface();

  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        EmbeddedSurface{embedding, cube, Eigen::MatrixXd::Zero(21, 2)};
      },
      "basis has 21 rows, expected 24 (three per volume-mesh vertex)"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        EmbeddedSurface{embedding, cube.vertices, cube.vertices.topRows(7), basis};
      },
      "normals has 7 rows, expected 8 (one per point)"));
  VertexMatrix bad = cube.vertices;
  bad(5, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        EmbeddedSurface{embedding, bad, cube.vertices, basis};
      },
      "cannot embed point 5: non-finite coordinate"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        EmbeddedSurface{embedding, cube.vertices, bad, basis};
      },
      "normal 5 has a non-finite component"));
  TriangleMesh broken = cube;
  broken.triangles(3, 2) = 8;
  EXPECT_TRUE(throws_with_message<MeshError>(
      [&] {
        EmbeddedSurface{embedding, broken, basis};
      },
      "triangle 3 uses vertex 8, outside [0, 8)"));

  const EmbeddedSurface surface(embedding, cube, basis);
  VertexMatrix out(8, 3);
  VertexMatrix short_out(7, 3);
  const Eigen::VectorXd q = coordinates({0.1, 0.2});
  const Eigen::VectorXd long_q = coordinates({0.1, 0.2, 0.3});
  EXPECT_TRUE(throws_with_message<Error>([&] { surface.deformed_positions(long_q, out); },
                                         "q has 3 entries, expected 2 (one per basis column)"));
  EXPECT_TRUE(throws_with_message<Error>([&] { surface.deformed_normals(long_q, out); },
                                         "q has 3 entries, expected 2 (one per basis column)"));
  EXPECT_TRUE(throws_with_message<Error>([&] { surface.deformed_positions(q, short_out); },
                                         "positions has 7 rows, expected 8 (one per point)"));
  EXPECT_TRUE(throws_with_message<Error>([&] { surface.deformed_normals(q, short_out); },
                                         "normals has 7 rows, expected 8 (one per point)"));
}

}  // namespace
}  // namespace khz::reduced
