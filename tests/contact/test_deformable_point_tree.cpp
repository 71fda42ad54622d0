#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

namespace khz::contact {
namespace {

constexpr int r = 6;

/// A unit cube simulated by 3×3×3 cells of tetrahedra, a random basis (any 3n×r matrix bounds
/// the same way; its columns move points by ~0.5 m per unit q — half the cube), and a pointshell
/// of random samples on the cube's faces in nested levels.
struct Fixture {
  reduced::VolumeMesh volume =
      reduced::box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  reduced::MeshEmbedding embedding{volume};
  Eigen::MatrixXd basis;
  Pointshell pointshell;

  Fixture() {
    std::mt19937 random(8);
    std::normal_distribution<double> gauss(0.0, 0.3);
    basis.resize(3 * volume.num_vertices(), r);
    for (Eigen::Index i = 0; i < basis.size(); ++i) basis.data()[i] = gauss(random);
    NestedLevelOptions options;
    options.schedule = LevelSchedule::quadrupling(8);
    pointshell = nested_pointshell(random_pointshell(test::unit_cube_surface(), 2000, 4), options);
  }
};

const Fixture& fixture() {
  static const Fixture instance;
  return instance;
}

const DeformablePointTree& deformable() {
  static const DeformablePointTree tree(PointTree(fixture().pointshell), fixture().embedding,
                                        fixture().basis);
  return tree;
}

void collect_subtree(const PointTree& tree, Eigen::Index n, std::vector<Eigen::Index>& points) {
  const PointTreeNode& node = tree.node(n);
  points.push_back(node.point);
  for (Eigen::Index c = node.first_child; c < node.first_child + node.child_count; ++c) {
    collect_subtree(tree, c, points);
  }
}

/// Brute force: the largest ‖p_s(q) − p_c(q)‖ over the subtree of node n.
double deformed_subtree_radius(const DeformablePointTree& tree, Eigen::Index n,
                               const Eigen::VectorXd& q) {
  std::vector<Eigen::Index> subtree;
  collect_subtree(tree.tree(), n, subtree);
  const Eigen::Vector3d centre = tree.position(tree.tree().node(n).point, q);
  double largest = 0.0;
  for (const Eigen::Index s : subtree) {
    largest = std::max(largest, (tree.position(s, q) - centre).norm());
  }
  return largest;
}

TEST(DeformablePointTree, PointsFollowTheEmbeddedBasis) {
  const DeformablePointTree& tree = deformable();
  ASSERT_EQ(tree.dimension(), r);
  const Fixture& s = fixture();
  // Independent references: FEM interpolation of u = Uq for positions, libreduced's embedded
  // surface (built on the input order) for the eq. 3.8 normals.
  const reduced::EmbeddedSurface surface(s.embedding, s.pointshell.points, s.pointshell.normals,
                                         s.basis);
  std::mt19937 random(1);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q(r);
    for (Eigen::Index j = 0; j < r; ++j) q[j] = gauss(random);
    const Eigen::VectorXd u = s.basis * q;
    for (Eigen::Index p = 0; p < tree.tree().num_points(); p += 7) {
      const Eigen::Vector3d rest = tree.tree().pointshell().points.row(p).transpose();
      const Eigen::Vector3d expected = rest + s.embedding.interpolate(s.embedding.locate(rest), u);
      // Measured 9e-16 and 4e-16 (summation order).
      EXPECT_LT((tree.position(p, q) - expected).norm(), 1e-14) << p;
      EXPECT_LT((tree.normal(p, q) - surface.normal(tree.tree().source_index(p), q)).norm(), 1e-14)
          << p;
    }
  }
}

TEST(DeformablePointTree, BoundingRadiiCoverTheDeformedSubtreesForSmallAndLargeQ) {
  const DeformablePointTree& tree = deformable();
  std::mt19937 random(2);
  std::normal_distribution<double> gauss;
  // Measured largest displacements ‖U_s q‖: 0.004 m, 0.34 m, 2.5 m and 14 m — up to many times
  // the 1 m cube.
  for (const double scale : {1e-3, 0.1, 1.0, 5.0}) {
    for (int trial = 0; trial < 8; ++trial) {
      Eigen::VectorXd q(r);
      for (Eigen::Index j = 0; j < r; ++j) q[j] = scale * gauss(random);
      const Eigen::VectorXd abs_q = q.cwiseAbs();
      for (Eigen::Index n = 0; n < tree.tree().num_internal_nodes(); ++n) {
        const double radius = tree.bounding_radius(n, abs_q);
        // Bound and brute force round differently: a relative 1e-14.
        EXPECT_LE(deformed_subtree_radius(tree, n, q), radius * (1 + 1e-14))
            << "node " << n << " scale " << scale;
      }
    }
  }
}

TEST(DeformablePointTree, CoefficientsAreTheLargestModeDifferencesAndTight) {
  const DeformablePointTree& tree = deformable();
  const PointTree& topology = tree.tree();
  std::vector<Eigen::Index> subtree;
  for (Eigen::Index n = 0; n < topology.num_internal_nodes(); ++n) {
    subtree.clear();
    collect_subtree(topology, n, subtree);
    const Eigen::Index c = topology.node(n).point;
    for (Eigen::Index j = 0; j < r; ++j) {
      double largest = 0.0;
      for (const Eigen::Index s : subtree) {
        largest = std::max(
            largest,
            (tree.displacement_modes(s).col(j) - tree.displacement_modes(c).col(j)).norm());
      }
      EXPECT_DOUBLE_EQ(tree.radius_coefficients(n)[j], largest) << n << ", " << j;
      // Along q = t e_j the bound exceeds the true deformed radius by at most 2 R_i0, for any
      // t: the maximizing point has ‖p_s − p_c‖ ≥ |t| a_ij − R_i0. So a_ij is not inflated.
      for (const double t : {-50.0, -0.5, 0.5, 50.0}) {
        const Eigen::VectorXd q = t * Eigen::VectorXd::Unit(r, j);
        const double bound = tree.bounding_radius(n, q.cwiseAbs());
        const double slack = bound - deformed_subtree_radius(tree, n, q);
        EXPECT_GE(slack, -1e-14 * bound);
        EXPECT_LE(slack, 2 * topology.node(n).rest_radius + 1e-14 * bound)
            << n << ", " << j << ", " << t;
      }
    }
  }
}

TEST(DeformablePointTree, RestShapeAndLeaves) {
  const DeformablePointTree& tree = deformable();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(r);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(r);
  for (Eigen::Index n = 0; n < tree.tree().num_nodes(); ++n) {
    EXPECT_EQ(tree.bounding_radius(n, zero), tree.tree().node(n).rest_radius);
    if (n >= tree.tree().num_internal_nodes()) {
      EXPECT_EQ(tree.bounding_radius(n, ones), 0.0);
    }
  }
  for (Eigen::Index s = 0; s < tree.tree().num_points(); ++s) {
    EXPECT_EQ(tree.position(s, zero), tree.tree().pointshell().points.row(s).transpose());
    EXPECT_EQ(tree.normal(s, zero), tree.tree().pointshell().normals.row(s).transpose());
  }
}

TEST(DeformablePointTree, DisplacementBoundCoversEveryPointsMotion) {
  // From the basis itself (the embedding's interpolation of U), not from the stored U_s: no
  // point moves more than displacement_bound() · ‖Δq‖, and some point comes close.
  const DeformablePointTree& tree = deformable();
  const Fixture& f = fixture();
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  double tightest = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd dq(r);
    for (Eigen::Index j = 0; j < r; ++j) dq[j] = gauss(random);
    const Eigen::VectorXd u = f.basis * dq;
    for (Eigen::Index s = 0; s < tree.tree().num_points(); ++s) {
      const Eigen::Vector3d rest = tree.tree().pointshell().points.row(s).transpose();
      const double moved = f.embedding.interpolate(f.embedding.locate(rest), u).norm();
      const double ratio = moved / (tree.displacement_bound() * dq.norm());
      ASSERT_LE(ratio, 1.0 + 1e-12) << "point " << s;
      tightest = std::max(tightest, ratio);
    }
  }
  EXPECT_GT(tightest, 0.3);  // not vacuously loose
}

TEST(DeformablePointTree, QueriesAreNoexceptAndAllocateNothing) {
  const DeformablePointTree& tree = deformable();
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(r, -1.0, 1.0);
  const Eigen::VectorXd abs_q = q.cwiseAbs();
  // Binding a VectorXd to Eigen::Ref is not noexcept itself; the calls are.
  const Eigen::Ref<const Eigen::VectorXd> q_ref(q);
  static_assert(noexcept(tree.position(0, q_ref)));
  static_assert(noexcept(tree.normal(0, q_ref)));
  static_assert(noexcept(tree.bounding_radius(0, q_ref)));
  static_assert(noexcept(tree.radius_coefficients(0)));
  double sum = 0.0;
  test::allocation_count = 0;
  for (Eigen::Index n = 0; n < tree.tree().num_nodes(); ++n) {
    const Eigen::Index s = tree.tree().node(n).point;
    sum += tree.position(s, q).sum() + tree.normal(s, q).sum() + tree.bounding_radius(n, abs_q);
  }
  EXPECT_EQ(test::allocation_count, 0u);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(DeformablePointTree, FromPlainModesEqualsFromTheEmbedding) {
  const DeformablePointTree& reference = deformable();
  const Eigen::Index points = reference.tree().num_points();
  std::vector<double> displacement, normal;
  for (Eigen::Index s = 0; s < points; ++s) {
    for (int k = 0; k < 3; ++k) {
      for (Eigen::Index j = 0; j < r; ++j) {
        displacement.push_back(reference.displacement_modes(s)(k, j));
        normal.push_back(reference.normal_modes(s)(k, j));
      }
    }
  }
  const DeformablePointTree plain(reference.tree(), r, displacement, normal);
  for (Eigen::Index n = 0; n < reference.tree().num_internal_nodes(); ++n) {
    EXPECT_EQ(plain.radius_coefficients(n), reference.radius_coefficients(n));
  }

  EXPECT_THROW(DeformablePointTree(reference.tree(), 0, {}, {}), Error);
  EXPECT_THROW(DeformablePointTree(reference.tree(), r, displacement, {}), Error);
  std::vector<double> bad = displacement;
  bad[3 * r * 17 + 2] = std::numeric_limits<double>::quiet_NaN();
  try {
    DeformablePointTree(reference.tree(), r, bad, normal);
    FAIL() << "no exception";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("point 17"), std::string::npos) << error.what();
  }
  const Eigen::MatrixXd short_basis = fixture().basis.topRows(fixture().basis.rows() - 3);
  EXPECT_THROW(DeformablePointTree(reference.tree(), fixture().embedding, short_basis), Error);
  EXPECT_THROW(DeformablePointTree(reference.tree(), fixture().embedding, Eigen::MatrixXd(192, 0)),
               Error);
}

TEST(DeformablePointTree, ReportsProgressAndCancels) {
  const DeformablePointTree& reference = deformable();
  const Eigen::Index points = reference.tree().num_points();
  const Eigen::Index internal = reference.tree().num_internal_nodes();
  std::vector<Progress> reports;
  const DeformablePointTree tree(reference.tree(), fixture().embedding, fixture().basis,
                                 [&](const Progress& progress) {
                                   reports.push_back(progress);
                                   return true;
                                 });
  ASSERT_GE(reports.size(), 4u);
  EXPECT_EQ(reports.front().stage, "embedding points");
  EXPECT_EQ(reports.front().total, points);
  EXPECT_EQ(reports.back().stage, "BD-tree coefficients");
  EXPECT_EQ(reports.back().total, internal);
  EXPECT_EQ(reports.back().done, internal);
  for (std::size_t i = 1; i < reports.size(); ++i) {
    if (reports[i].stage == reports[i - 1].stage) {
      EXPECT_GE(reports[i].done, reports[i - 1].done);
    }
  }
  for (const char* stage : {"embedding points", "BD-tree coefficients"}) {
    EXPECT_THROW(DeformablePointTree(reference.tree(), fixture().embedding, fixture().basis,
                                     [&](const Progress& p) { return p.stage != stage; }),
                 Cancelled)
        << stage;
  }
}

}  // namespace
}  // namespace khz::contact
