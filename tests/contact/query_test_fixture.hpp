#pragma once
// What the contact query's tests share: a rigid sphere tree and a deformable cube tree, poses,
// and the central-difference check of the four force gradients (§4.2).

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/generated_meshes.hpp>
#include <khz/test/sphere_points.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <random>

namespace khz::contact::query_test {

constexpr int r = 6;

/// A unit sphere sampled by Fibonacci points (near-uniform), nested ×4 per level from 20.
inline Pointshell fibonacci_sphere(Eigen::Index count) {
  Pointshell shell;
  shell.points = test::fibonacci_sphere_points(count);
  shell.normals = -shell.points;
  shell.level_ends = {count};
  NestedLevelOptions options;
  options.schedule = LevelSchedule::quadrupling(20);
  return nested_pointshell(shell, options);
}

/// A rigid sphere tree, and a deformable cube tree on a random basis (its columns move points by
/// ~0.3 m per unit q), as in test_deformable_point_tree.
struct Fixture {
  PointTree sphere{fibonacci_sphere(6000)};
  reduced::VolumeMesh volume =
      reduced::box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {3, 3, 3});
  reduced::MeshEmbedding embedding{volume};
  Eigen::MatrixXd basis;
  DeformablePointTree cube;

  Fixture() : basis(random_basis()), cube(cube_tree(embedding, basis)) {}

  Eigen::MatrixXd random_basis() const {
    std::mt19937 random(8);
    std::normal_distribution<double> gauss(0.0, 0.3);
    Eigen::MatrixXd u(3 * volume.num_vertices(), r);
    for (Eigen::Index i = 0; i < u.size(); ++i) u.data()[i] = gauss(random);
    return u;
  }
  static DeformablePointTree cube_tree(const reduced::MeshEmbedding& embedding,
                                       const Eigen::MatrixXd& basis) {
    NestedLevelOptions options;
    options.schedule = LevelSchedule::quadrupling(8);
    return DeformablePointTree(PointTree(nested_pointshell(
                                   random_pointshell(test::unit_cube_surface(), 3000, 4), options)),
                               embedding, basis);
  }
};

inline const Fixture& fixture() {
  static const Fixture instance;
  return instance;
}

/// The solid half-space z < 0.
inline ImplicitShape ground() { return HalfSpace(Eigen::Vector3d(0.0, 0.0, 1.0), 0.0); }

inline Eigen::Isometry3d pose(const Eigen::Vector3d& axis_angle,
                              const Eigen::Vector3d& translation) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (axis_angle.norm() > 0.0) {
    t.linear() = Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()).toRotationMatrix();
  }
  t.translation() = translation;
  return t;
}

/// Central differences of the force and torque on the haptic object as it moves by (Δx, Δω)
/// about the grasp point, in the axes §4.2 states: turning with a field haptic object.
struct Differences {
  Eigen::Matrix3d force_by_translation, force_by_rotation, torque_by_translation,
      torque_by_rotation;
};

template <typename Query>
Differences finite_differences(const ContactFrames& frames, HapticObject haptic,
                               const Query& query) {
  constexpr double h = 1e-6;
  Differences differences;
  for (int column = 0; column < 6; ++column) {
    Eigen::Vector3d force[2], torque[2];
    for (int side = 0; side < 2; ++side) {
      Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
      delta[column] = side == 0 ? h : -h;
      const Eigen::Isometry3d motion = Eigen::Translation3d(frames.grasp_point + delta.head<3>()) *
                                       pose(delta.tail<3>(), Eigen::Vector3d::Zero()) *
                                       Eigen::Translation3d(-frames.grasp_point);
      ContactFrames moved = frames;
      moved.grasp_point += delta.head<3>();
      Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
      if (haptic == HapticObject::distance_field) {
        moved.field = motion * frames.field;
        axes = motion.linear().transpose();
      } else {
        moved.pointshell = motion * frames.pointshell;
      }
      const ContactResult& result = query(moved);
      force[side] = axes * result.force;
      torque[side] = axes * result.torque;
    }
    const Eigen::Vector3d df = (force[0] - force[1]) / (2.0 * h);
    const Eigen::Vector3d dt = (torque[0] - torque[1]) / (2.0 * h);
    if (column < 3) {
      differences.force_by_translation.col(column) = df;
      differences.torque_by_translation.col(column) = dt;
    } else {
      differences.force_by_rotation.col(column - 3) = df;
      differences.torque_by_rotation.col(column - 3) = dt;
    }
  }
  return differences;
}

inline void expect_gradients_match(const ContactResult& result, const Differences& differences) {
  const auto check = [](const Eigen::Matrix3d& analytic, const Eigen::Matrix3d& numeric,
                        const char* name) {
    EXPECT_LE((analytic - numeric).norm(), 1e-6 * std::max(1.0, numeric.norm()))
        << name << "\nanalytic\n"
        << analytic << "\nfinite differences\n"
        << numeric;
  };
  check(result.force_by_translation, differences.force_by_translation, "∂F/∂x");
  check(result.force_by_rotation, differences.force_by_rotation, "∂F/∂ω");
  check(result.torque_by_translation, differences.torque_by_translation, "∂T/∂x");
  check(result.torque_by_rotation, differences.torque_by_rotation, "∂T/∂ω");
  EXPECT_GT(differences.force_by_rotation.norm(), 1.0);  // not a vacuous comparison
}

}  // namespace khz::contact::query_test
