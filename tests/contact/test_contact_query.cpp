#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>
#include <khz/test/sphere_points.hpp>

#include "query_test_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace khz::contact {
namespace {

using namespace query_test;

/// The reference: every point of levels 0…deepest, no tree, straight from eq. 3.1 and §3.5, each
/// point through the contact onset of ContactOptions::onset_depth.
struct BruteForce {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // on the field object
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // about the grasp point
  Eigen::VectorXd reduced;                           // Σ U_sᵀ (force on point s, body frame)
  std::int64_t contacts = 0;
  double deepest_penetration = 0.0;  // −min d over the points in contact
  double weight = 0.0;               // ℓ
  std::int64_t within_onset = 0;     // points in contact shallower than the onset depth
};

/// A point `depth` > 0 deep through an onset of depth δ: how far it pushes (its force is k_C
/// times that) and how much of a point it counts in ℓ. Within δ: depth²/(2δ) and depth/δ; deeper:
/// depth − δ/2 and 1 (δ = 0: eq. 3.1).
struct OnsetPush {
  double push, count;
  OnsetPush(double depth, double onset)
      : push(depth < onset ? depth * depth / (2.0 * onset) : depth - onset / 2.0),
        count(depth < onset ? depth / onset : 1.0) {}
};

/// δ of `options` against `field`: its voxel if it has one.
template <typename Field>
double onset_of(const ContactOptions& options, const Field& field) {
  if constexpr (requires { field.cell_size(); }) return options.onset_depth_for(field.cell_size());
  return options.onset_depth_for(0.0);
}

template <typename Field>
BruteForce brute_force(const PointTree& tree, const DeformablePointTree* deformable,
                       const Eigen::VectorXd& q, const Field& field, const ContactFrames& frames,
                       const ContactOptions& options, int deepest) {
  BruteForce sum;
  sum.reduced = Eigen::VectorXd::Zero(deformable != nullptr ? deformable->dimension() : 0);
  double weight = 0.0;
  const double onset = onset_of(options, field);
  for (Eigen::Index s = 0; s < tree.pointshell().level_end(deepest); ++s) {
    const Eigen::Vector3d body = deformable != nullptr
                                     ? deformable->position(s, q)
                                     : Eigen::Vector3d(tree.pointshell().points.row(s));
    const Eigen::Vector3d x = frames.pointshell * body;
    const double d = field.distance(frames.field.inverse() * x);
    // The query transforms points its own way: a point this close to the surface could count on
    // one side and not the other, so the poses must avoid such points for the counts to compare.
    if (std::abs(d) < 1e-12) {
      ADD_FAILURE() << "point " << s << " lies on the surface to round-off (d = " << d
                    << "): choose a pose that avoids it";
    }
    if (!(d < 0.0)) continue;
    const Eigen::Vector3d normal_body = deformable != nullptr
                                            ? deformable->normal(s, q)
                                            : Eigen::Vector3d(tree.pointshell().normals.row(s));
    const OnsetPush onset_push(-d, onset);
    const Eigen::Vector3d f =
        -options.stiffness * onset_push.push * (frames.pointshell.linear() * normal_body);
    sum.force += f;
    sum.torque += (x - frames.grasp_point).cross(f);
    if (deformable != nullptr) {
      sum.reduced += deformable->displacement_modes(s).transpose() *
                     (frames.pointshell.linear().transpose() * -f);
    }
    weight += onset_push.count;
    ++sum.contacts;
    if (-d < onset) ++sum.within_onset;
    sum.deepest_penetration = std::max(sum.deepest_penetration, -d);
  }
  sum.weight = weight;
  const double scale = options.scaling_count / std::max(options.scaling_count, weight);
  sum.force *= scale;
  sum.torque *= scale;
  sum.reduced *= scale;
  return sum;
}

void expect_close(const Eigen::VectorXd& actual, const Eigen::VectorXd& expected, double relative) {
  ASSERT_EQ(actual.size(), expected.size());
  EXPECT_LE((actual - expected).norm(), relative * std::max(expected.norm(), 1e-300))
      << "actual " << actual.transpose() << "\nexpected " << expected.transpose();
}

/// Sphere-pointshell poses touching the unit box obstacle at growing depths, turned arbitrarily.
std::vector<ContactFrames> sphere_poses() {
  std::vector<ContactFrames> poses;
  for (int i = 0; i < 6; ++i) {
    ContactFrames frames;
    frames.pointshell =
        pose(Eigen::Vector3d(0.3 * i, -0.2, 0.1 * i), Eigen::Vector3d(0.0, 0.0, 0.0));
    frames.field = pose(Eigen::Vector3d(0.1, 0.2 * i, -0.3),
                        Eigen::Vector3d(0.2 * i - 0.5, 0.1, 1.45 - 0.05 * i));
    frames.grasp_point = frames.field.translation() + Eigen::Vector3d(0.1, -0.2, 0.3);
    poses.push_back(frames);
  }
  return poses;
}

TEST(ContactQuery, RigidTreeEqualsBruteForceOverEveryPointAgainstAnalyticShapes) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape box = Box(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.8, 0.6, 0.5));
  const ImplicitUnion blobs(
      {Sphere(Eigen::Vector3d(0.3, 0.0, 0.0), 0.5), Sphere(Eigen::Vector3d(-0.3, 0.2, 0.1), 0.4)});
  ContactOptions options;
  options.stiffness = 2000.0;
  ContactWorkspace workspace(tree, options);
  int touching = 0;
  for (const ContactFrames& frames : sphere_poses()) {
    for (int field = 0; field < 2; ++field) {
      const bool ok = field == 0 ? query_contact(tree, box, frames, workspace)
                                 : query_contact(tree, blobs, frames, workspace);
      ASSERT_TRUE(ok);
      const ContactResult& result = workspace.result();
      const BruteForce expected =
          field == 0
              ? brute_force(tree, nullptr, {}, box, frames, options, tree.num_levels() - 1)
              : brute_force(tree, nullptr, {}, blobs, frames, options, tree.num_levels() - 1);
      EXPECT_EQ(result.statistics.points_in_contact, expected.contacts);
      EXPECT_NEAR(result.statistics.deepest_penetration, expected.deepest_penetration, 1e-12);
      EXPECT_TRUE(result.statistics.complete);
      expect_close(result.force, expected.force, 1e-12);
      expect_close(result.torque, expected.torque, 1e-12);
      if (expected.contacts > options.scaling_count) ++touching;
      // The tree culls: far fewer nodes than points whenever contact is local.
      EXPECT_LT(result.statistics.nodes_traversed, tree.num_nodes());
    }
  }
  EXPECT_GE(touching, 8);  // the poses exercise the L/ℓ scaling
}

/// The unit cube [0, 1]³ as a signed distance field of 48 cells (voxel 31 mm).
const DistanceGrid& unit_cube_grid() {
  static const DistanceGrid grid = [] {
    DistanceFieldOptions options;
    options.cells = 48;
    return signed_distance_field(test::unit_cube_surface(), options);
  }();
  return grid;
}

TEST(ContactQuery, RigidTreeEqualsBruteForceAgainstASampledGrid) {
  // The unit sphere pressed 1–11 cm into the top face of the unit cube's sampled field, turned.
  const PointTree& tree = fixture().sphere;
  const DistanceGrid& grid = unit_cube_grid();
  ContactOptions options;
  options.onset_voxels = 1.0;  // deep enough that many of the poses' points lie within it
  ContactWorkspace workspace(tree, options);
  std::int64_t within_onset = 0, scaled = 0;
  for (int i = 0; i < 6; ++i) {
    ContactFrames frames;
    frames.pointshell = pose(Eigen::Vector3d(0.2 * i, -0.1, 0.3),
                             Eigen::Vector3d(0.5 + 0.03 * i, 0.45, 1.99 - 0.02 * i));
    frames.grasp_point = Eigen::Vector3d(0.2, 0.3, 1.5);  // off the centre: a torque
    ASSERT_TRUE(query_contact(tree, grid, frames, workspace));
    const BruteForce expected =
        brute_force(tree, nullptr, {}, grid, frames, options, tree.num_levels() - 1);
    EXPECT_EQ(workspace.result().statistics.points_in_contact, expected.contacts);
    expect_close(workspace.result().force, expected.force, 1e-12);
    expect_close(workspace.result().torque, expected.torque, 1e-12);
    within_onset += expected.within_onset;
    scaled += expected.weight > options.scaling_count ? 1 : 0;
  }
  EXPECT_GT(within_onset, 0) << "the grid's voxel gives the onset its depth";
  EXPECT_GE(scaled, 4) << "the poses exercise the L/ℓ scaling";
}

TEST(ContactQuery, TheOnsetKeepsTheForceContinuousAsPointsEnterContact) {
  // The unit sphere lowered onto the unit cube's top face in steps of 10 µm, tens of points in
  // contact and L = 10: under eq. 3.1 each point entering contact adds 1 to ℓ at no force, so
  // the L/ℓ-scaled force drops by about 1/ℓ of itself in one step; through the default onset
  // (0.1 voxel) a point's force and count grow from zero, and no step changes the force by more
  // than the press itself does.
  const PointTree& tree = fixture().sphere;
  const DistanceGrid& grid = unit_cube_grid();
  const auto largest_step = [&](const ContactOptions& options, double& onset_share) {
    ContactWorkspace workspace(tree, options);
    double largest = 0.0, previous = 0.0;
    std::int64_t within_onset = 0, in_contact = 0;
    for (int step = 0; step <= 1500; ++step) {
      const double depth = 0.005 + 1e-5 * step;
      ContactFrames frames;
      // Turned, so that no point's height is a round multiple of the step (the sphere's points
      // lie on a lattice of heights).
      frames.pointshell =
          pose(Eigen::Vector3d(0.3, -0.2, 0.1), Eigen::Vector3d(0.5, 0.5, 2.0 - depth));
      EXPECT_TRUE(query_contact(tree, grid, frames, workspace));
      const double force = workspace.result().force.norm();
      if (step > 0) largest = std::max(largest, std::abs(force - previous) / previous);
      previous = force;
      const BruteForce expected =
          brute_force(tree, nullptr, {}, grid, frames, options, tree.num_levels() - 1);
      if (step % 100 == 0) expect_close(workspace.result().force, expected.force, 1e-12);
      in_contact += expected.contacts;
      within_onset += expected.within_onset;
    }
    onset_share = static_cast<double>(within_onset) / static_cast<double>(in_contact);
    return largest;
  };
  ContactOptions step_count;
  step_count.onset_voxels = 0.0;
  double unused = 0.0, shallow = 0.0;
  const double without = largest_step(step_count, unused);
  const double with = largest_step(ContactOptions{}, shallow);
  EXPECT_GT(without, 0.02) << "eq. 3.1's count jumps";
  EXPECT_LT(with, 0.005) << "through the onset";
  EXPECT_GT(shallow, 0.0) << "some points in contact lie within the onset";
}

TEST(ContactQuery, DeformableTreeEqualsBruteForceWithReducedForces) {
  const DeformablePointTree& tree = fixture().cube;
  const ImplicitShape ball = Sphere(Eigen::Vector3d(0.0, 0.0, 0.0), 0.45);
  ContactOptions options;
  ContactWorkspace workspace(tree, options);
  std::mt19937 random(3);
  std::normal_distribution<double> gauss(0.0, 1.0);
  int touching = 0;
  for (int trial = 0; trial < 8; ++trial) {
    Eigen::VectorXd q(r);
    for (Eigen::Index j = 0; j < r; ++j) q[j] = 0.15 * trial * gauss(random);  // up to ~0.3 m
    ContactFrames frames;
    frames.pointshell = pose(Eigen::Vector3d(0.1 * trial, 0.2, 0.0), Eigen::Vector3d(0.1, 0, 0));
    frames.field = pose(Eigen::Vector3d::Zero(),
                        frames.pointshell * Eigen::Vector3d(1.2 - 0.06 * trial, 0.5, 0.4));
    frames.grasp_point = frames.field.translation();
    ASSERT_TRUE(query_contact(tree, q, ball, frames, workspace));
    const BruteForce expected =
        brute_force(tree.tree(), &tree, q, ball, frames, options, tree.tree().num_levels() - 1);
    const ContactResult& result = workspace.result();
    EXPECT_EQ(result.statistics.points_in_contact, expected.contacts);
    EXPECT_NEAR(result.statistics.deepest_penetration, expected.deepest_penetration, 1e-12);
    expect_close(result.force, expected.force, 1e-12);
    expect_close(result.torque, expected.torque, 1e-12);
    expect_close(result.pointshell_reduced_force, expected.reduced, 1e-12);
    touching += expected.contacts > 0 ? 1 : 0;
  }
  EXPECT_GE(touching, 5);
}

TEST(ContactQuery, DeformableAgainstDeformableAppliesTheReactionToBothObjects) {
  // The cube pointshell against a second, deformed cube (§3.12): its field from 40 proxies on
  // a 32³ rest field, the same volume mesh and a smaller random basis.
  const Fixture& f = fixture();
  const DeformablePointTree& tree = f.cube;
  DistanceFieldOptions grid_options;
  grid_options.cells = 32;
  const Eigen::MatrixXd field_basis = 0.1 * f.basis.leftCols(4);
  const DeformedDistanceField deformed(
      {signed_distance_field(test::unit_cube_surface(), grid_options)}, f.embedding, field_basis);
  DeformedFieldState field(deformed);
  ContactOptions options;
  // Temporal coherence measures the field's own deformation too (max_v ‖U_v‖·‖Δq‖): beyond the
  // declared 0 m per query, every query drops its skips.
  options.coherence.enabled = true;
  options.coherence.max_translation = 1.0;
  ContactWorkspace workspace(tree, options, deformed.dimension());
  Eigen::VectorXd q(r);
  q << 0.05, -0.02, 0.03, 0.01, -0.04, 0.02;
  int touching = 0;
  for (int trial = 0; trial < 6; ++trial) {
    ASSERT_TRUE(field.update(Eigen::Vector4d(0.3, -0.2, 0.1 * trial, 0.2)));
    ContactFrames frames;
    frames.field = pose(Eigen::Vector3d(0.1 * trial, 0.0, 0.2),
                        Eigen::Vector3d(0.95 - 0.02 * trial, 0.1, 0.05));
    frames.grasp_point = frames.field * Eigen::Vector3d(0.5, 0.5, 0.5);
    ASSERT_TRUE(query_contact(tree, q, field, frames, workspace));
    const ContactResult& result = workspace.result();
    const BruteForce expected =
        brute_force(tree.tree(), &tree, q, field, frames, options, tree.tree().num_levels() - 1);
    EXPECT_EQ(result.statistics.nodes_skipped, 0);
    EXPECT_EQ(result.statistics.coherence_reset, trial > 0);
    EXPECT_EQ(result.statistics.points_in_contact, expected.contacts);
    expect_close(result.force, expected.force, 1e-12);
    expect_close(result.torque, expected.torque, 1e-12);
    expect_close(result.pointshell_reduced_force, expected.reduced, 1e-12);
    // The reaction on the field object, projected at the nearest proxies, recomputed here.
    Eigen::VectorXd field_reduced = Eigen::VectorXd::Zero(deformed.dimension());
    const double scale = options.scaling_count / std::max(options.scaling_count, expected.weight);
    for (Eigen::Index s = 0; s < tree.tree().num_points(); ++s) {
      const Eigen::Vector3d x = frames.pointshell * tree.position(s, q);
      const Eigen::Vector3d body = frames.field.inverse() * x;
      const double d = field.distance(body);
      if (!(d < 0.0)) continue;
      const Eigen::Vector3d force_world =
          -options.stiffness * OnsetPush(-d, onset_of(options, field)).push * tree.normal(s, q);
      const Eigen::Index n = field.nearest_proxy(body);
      field_reduced += deformed.displacement_modes(n).transpose() *
                       (frames.field.linear().transpose() * (scale * force_world));
    }
    expect_close(result.field_reduced_force, field_reduced, 1e-12);
    touching += expected.contacts > 0 ? 1 : 0;
  }
  EXPECT_GE(touching, 4);
}

/// ContactGradients' check, for one haptic object and onset depth (m).
void expect_gradients_match_finite_differences(HapticObject held, double onset) {
  const ImplicitUnion field(
      {Sphere(Eigen::Vector3d(0.2, 0.0, 0.0), 0.6), Sphere(Eigen::Vector3d(-0.4, 0.3, 0.1), 0.3)});
  ContactOptions options;
  options.stiffness = 500.0;
  options.scaling_count = 1e9;
  options.haptic_object = held;
  options.onset_depth = onset;
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d(0.2, -0.1, 0.4), Eigen::Vector3d(0.1, 0.0, -0.2));
  frames.field = pose(Eigen::Vector3d(-0.3, 0.2, 0.1), Eigen::Vector3d(0.5, 0.6, 0.9));
  frames.grasp_point = Eigen::Vector3d(0.4, 0.2, 0.7);

  const PointTree& sphere = fixture().sphere;
  ContactWorkspace rigid(sphere, options);
  ASSERT_TRUE(query_contact(sphere, field, frames, rigid));
  ASSERT_GT(rigid.result().statistics.points_in_contact, 20);
  const ContactResult rigid_result = rigid.result();
  expect_gradients_match(rigid_result,
                         finite_differences(frames, held, [&](const ContactFrames& moved) {
                           query_contact(sphere, field, moved, rigid);
                           return rigid.result();
                         }));

  const DeformablePointTree& cube = fixture().cube;
  Eigen::VectorXd q(r);
  q << 0.2, -0.1, 0.05, 0.3, -0.2, 0.1;
  ContactWorkspace deformable(cube, options);
  ContactFrames cube_frames = frames;
  cube_frames.field =
      pose(Eigen::Vector3d(-0.3, 0.2, 0.1), frames.pointshell * Eigen::Vector3d(1.1, 0.6, 0.5));
  ASSERT_TRUE(query_contact(cube, q, field, cube_frames, deformable));
  ASSERT_GT(deformable.result().statistics.points_in_contact, 20);
  const ContactResult deformable_result = deformable.result();
  expect_gradients_match(deformable_result,
                         finite_differences(cube_frames, held, [&](const ContactFrames& moved) {
                           query_contact(cube, q, field, moved, deformable);
                           return deformable.result();
                         }));
}

class ContactGradients : public ::testing::TestWithParam<HapticObject> {};

TEST_P(ContactGradients, MatchFiniteDifferencesForRigidAndDeformablePointshells) {
  // A smooth field (a sphere) and L large: the force is differentiable and ℓ's jumps do not
  // scale it, so central differences see exactly what the gradients describe. Eq. 3.1, and a
  // contact onset deeper than some points in contact and shallower than others.
  for (const double onset : {0.0, 0.05}) {
    SCOPED_TRACE(testing::Message() << "onset depth " << onset);
    expect_gradients_match_finite_differences(GetParam(), onset);
  }
}

INSTANTIATE_TEST_SUITE_P(HapticObjects, ContactGradients,
                         ::testing::Values(HapticObject::distance_field, HapticObject::pointshell));

TEST(ContactQuery, HapticObjectChoiceFlipsForceAndTorqueOnly) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.3, -0.2, 0.85));
  frames.grasp_point = Eigen::Vector3d(0.3, -0.2, 0.85);
  ContactOptions on_field;
  ContactOptions on_pointshell;
  on_pointshell.haptic_object = HapticObject::pointshell;
  ContactWorkspace a(tree, on_field), b(tree, on_pointshell);
  ASSERT_TRUE(query_contact(tree, plane, frames, a));
  ASSERT_TRUE(query_contact(tree, plane, frames, b));
  EXPECT_LT(a.result().force.z(), 0.0) << "the plane (field object) is pushed away, down";
  EXPECT_EQ(a.result().force, -b.result().force);
  EXPECT_EQ(a.result().torque, -b.result().torque);
  EXPECT_EQ(a.result().force_by_rotation, b.result().force_by_rotation);
}

TEST(ContactQuery, NormalDirectionGradientsUseTheNormalForTheFieldGradient) {
  // Against a plane whose normal is the pointshell's normal at the contact, ∇d = N: both
  // gradient modes agree.
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.999));
  ContactOptions exact, approximate;
  approximate.gradient = ContactGradient::normal_direction;
  ContactWorkspace a(tree, exact), b(tree, approximate);
  ASSERT_TRUE(query_contact(tree, plane, frames, a));
  ASSERT_TRUE(query_contact(tree, plane, frames, b));
  ASSERT_GT(a.result().statistics.points_in_contact, 0);
  // Points of the cap have normals within a few degrees of the plane's.
  EXPECT_LE((a.result().force_by_translation - b.result().force_by_translation).norm(),
            0.01 * a.result().force_by_translation.norm());
  EXPECT_NE(a.result().force_by_translation, b.result().force_by_translation);
}

TEST(ContactQuery, ForceConvergesToTheAnalyticLimitLevelByLevel) {
  // §3.5.1: a unit-sphere pointshell sunk δ into a plane. With the L/ℓ scaling the force on
  // the plane is k L times the mean of d N over the cap (eq. 3.2). With c = cos θ measured from
  // the bottom, d = h − c (h = 1 − δ) and N_z = c on the cap c > h, and area is uniform in c:
  //   F_z = k L ∫ (h − c) c dc / ∫ dc over [h, 1] = −k L ((1 − h³)/3 − h(1 − h²)/2) / (1 − h).
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  const double depth = 0.3, h = 1.0 - depth;
  ContactOptions options;
  options.stiffness = 1.0;
  ContactFrames frames;
  // Turned, so the Fibonacci rings (uniform in z) do not line up with the plane.
  frames.pointshell = pose(Eigen::Vector3d(0.7, -0.4, 0.2), Eigen::Vector3d(0.0, 0.0, h));
  const double numerator = (1.0 - h * h * h) / 3.0 - h * (1.0 - h * h) / 2.0;
  const double limit = -options.stiffness * options.scaling_count * numerator / (1.0 - h);
  std::vector<double> errors;
  for (int level = 0; level < tree.num_levels(); ++level) {
    options.max_level = level;
    ContactWorkspace workspace(tree, options);
    ASSERT_TRUE(query_contact(tree, plane, frames, workspace));
    const double force = workspace.result().force.z();
    const auto contacts = static_cast<double>(workspace.result().statistics.points_in_contact);
    errors.push_back(std::abs(force - limit) / std::abs(limit));
    std::printf("level %d: %5.0f points in contact, F_z = %.6f, limit %.6f, error %.2e\n", level,
                contacts, force, limit, errors.back());
    // A Riemann sum over near-uniform points errs mostly along the cap's rim, where points enter
    // and leave: relative error ~ rim length × spacing / area ~ 1/√ℓ.
    EXPECT_LT(errors.back(), 1.5 / std::sqrt(contacts)) << "level " << level;
  }
  EXPECT_LT(errors.back(), 1e-3);
  EXPECT_LT(errors.back(), errors.front() / 100.0);
}

/// A recorded trajectory: the sphere pointshell sweeping through and past a box, each step
/// within the declared bounds (the sphere's centre moves up to 7 mm a step in the box's frame,
/// which turns 0.004 rad a step), then one jump beyond them.
std::vector<ContactFrames> sweep() {
  std::vector<ContactFrames> path;
  for (int step = 0; step <= 400; ++step) {
    const double t = step / 400.0;
    ContactFrames frames;
    frames.field = pose(Eigen::Vector3d(0.0, 0.0, 1.6 * t),
                        Eigen::Vector3d(-0.8 + 0.7 * t, 0.2 * t, 1.25 - 0.15 * t));
    frames.grasp_point = frames.field.translation();
    path.push_back(frames);
  }
  ContactFrames jump = path.back();
  jump.field.translation() = Eigen::Vector3d(0.0, 0.0, 1.2);  // a teleport
  path.push_back(jump);
  path.push_back(jump);
  return path;
}

TEST(ContactQuery, TemporalCoherenceChangesNoResultAndSkipsNodes) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape box = Box(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.3, 0.2));
  ContactOptions plain;
  ContactOptions coherent;
  coherent.coherence.enabled = true;
  coherent.coherence.max_translation = 7e-3;
  coherent.coherence.max_rotation = 4.001e-3;
  ContactWorkspace a(tree, plain), b(tree, coherent);
  std::int64_t traversed_plain = 0, traversed_coherent = 0, skipped = 0, contacts = 0;
  int resets = 0;
  for (const ContactFrames& frames : sweep()) {
    ASSERT_TRUE(query_contact(tree, box, frames, a));
    ASSERT_TRUE(query_contact(tree, box, frames, b));
    // Bit for bit: the same points in contact, summed in the same order.
    ASSERT_EQ(a.result().force, b.result().force);
    ASSERT_EQ(a.result().torque, b.result().torque);
    ASSERT_EQ(a.result().force_by_rotation, b.result().force_by_rotation);
    ASSERT_EQ(a.result().statistics.points_in_contact, b.result().statistics.points_in_contact);
    resets += b.result().statistics.coherence_reset ? 1 : 0;
    traversed_plain += a.result().statistics.nodes_traversed;
    traversed_coherent += b.result().statistics.nodes_traversed;
    skipped += b.result().statistics.nodes_skipped;
    contacts += a.result().statistics.points_in_contact;
  }
  EXPECT_GT(contacts, 1000);
  EXPECT_GT(skipped, 0);
  EXPECT_EQ(resets, 1);  // the teleport, and nothing else
  std::printf("nodes traversed: %lld without temporal coherence, %lld with (%lld skipped)\n",
              static_cast<long long>(traversed_plain), static_cast<long long>(traversed_coherent),
              static_cast<long long>(skipped));
  EXPECT_LT(static_cast<double>(traversed_coherent), 0.8 * static_cast<double>(traversed_plain));
}

TEST(ContactQuery, TemporalCoherenceFollowsADeformingPointshell) {
  const DeformablePointTree& tree = fixture().cube;
  const ImplicitShape ball = Sphere(Eigen::Vector3d::Zero(), 0.3);
  ContactOptions plain;
  ContactOptions coherent;
  coherent.coherence.enabled = true;
  coherent.coherence.max_translation = 2e-3;
  coherent.coherence.max_deformation = 0.0;  // measured below
  ContactWorkspace a(tree, plain);
  Eigen::VectorXd direction(r);
  direction << 1.0, -0.5, 0.3, 0.2, -0.7, 0.4;
  const double step = 0.002;  // of q per query
  coherent.coherence.max_deformation = tree.displacement_bound() * step * direction.norm();
  ContactWorkspace b(tree, coherent);
  std::int64_t skipped = 0, contacts = 0;
  for (int i = 0; i <= 300; ++i) {
    const Eigen::VectorXd q = (i * step) * direction;
    ContactFrames frames;
    frames.field = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.25 - 0.002 * i, 0.5, 0.5));
    ASSERT_TRUE(query_contact(tree, q, ball, frames, a));
    ASSERT_TRUE(query_contact(tree, q, ball, frames, b));
    ASSERT_EQ(a.result().force, b.result().force) << "query " << i;
    ASSERT_EQ(a.result().pointshell_reduced_force, b.result().pointshell_reduced_force);
    skipped += b.result().statistics.nodes_skipped;
    contacts += a.result().statistics.points_in_contact;
  }
  EXPECT_GT(contacts, 100);
  EXPECT_GT(skipped, 0);
}

TEST(ContactQuery, DegradationCompletesLevelsOrDoesNotStartThem) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d(0.3, 0.1, 0.0), Eigen::Vector3d(0.0, 0.0, 0.5));
  ContactOptions full;
  ContactWorkspace reference(tree, full);
  ASSERT_TRUE(query_contact(tree, plane, frames, reference));
  const std::int64_t all_nodes = reference.result().statistics.nodes_traversed;

  for (const double fraction : {0.05, 0.2, 0.5}) {
    ContactOptions options;
    options.degradation.mode = DegradationOptions::Mode::node_count;
    options.degradation.warm_threshold = fraction * static_cast<double>(all_nodes);
    ContactWorkspace workspace(tree, options);
    for (int repeat = 0; repeat < 3; ++repeat) {
      ASSERT_TRUE(query_contact(tree, plane, frames, workspace));
      const ContactStatistics& stats = workspace.result().statistics;
      EXPECT_FALSE(stats.complete);
      EXPECT_LE(static_cast<double>(stats.nodes_traversed), options.degradation.warm_threshold);
      // Exactly the force of every point of the levels rendered.
      const BruteForce expected =
          brute_force(tree, nullptr, {}, plane, frames, options, stats.deepest_level);
      EXPECT_EQ(stats.points_in_contact, expected.contacts);
      EXPECT_NEAR(stats.deepest_penetration, expected.deepest_penetration, 1e-12);
      EXPECT_GT(stats.deepest_penetration, 0.0);
      expect_close(workspace.result().force, expected.force, 1e-12);
    }
  }
}

// The planner counts only the queued nodes temporal coherence will visit. The sphere comes down
// onto a plane slowly; a threshold 40 % above the most any coherent query visits on the way (the
// cold threshold is 80 % of it) lets every query render every level, as without degradation.
// Counting the queued nodes coherence skips too would predict several times that and cut.
TEST(ContactQuery, DegradationCountsOnlyTheNodesCoherenceWillVisit) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactOptions coherent;
  coherent.coherence.enabled = true;
  coherent.coherence.max_translation = 2e-3;
  const auto path = [](int i) {
    ContactFrames frames;
    frames.pointshell =
        pose(Eigen::Vector3d(0.3, 0.1, 0.0), Eigen::Vector3d(0.0, 0.0, 1.3 - 1.65e-3 * i));
    return frames;
  };
  constexpr int steps = 200;  // down to z = 0.97
  ContactWorkspace reference(tree, coherent);
  std::int64_t most_visited = 0, skipped = 0;
  for (int i = 0; i < steps; ++i) {
    ASSERT_TRUE(query_contact(tree, plane, path(i), reference));
    most_visited = std::max(most_visited, reference.result().statistics.nodes_traversed);
    skipped += reference.result().statistics.nodes_skipped;
  }
  ASSERT_GT(reference.result().statistics.points_in_contact, 0);
  ASSERT_GT(skipped, 10 * most_visited) << "coherence skips many nodes";

  ContactOptions options = coherent;
  options.degradation.mode = DegradationOptions::Mode::node_count;
  options.degradation.warm_threshold = 1.4 * static_cast<double>(most_visited);
  ContactWorkspace workspace(tree, options);
  ContactWorkspace again(tree, coherent);
  for (int i = 0; i < steps; ++i) {
    ASSERT_TRUE(query_contact(tree, plane, path(i), workspace));
    ASSERT_TRUE(query_contact(tree, plane, path(i), again));
    ASSERT_TRUE(workspace.result().statistics.complete) << "query " << i;
    ASSERT_EQ(workspace.result().force, again.result().force) << "query " << i;
  }
}

TEST(ContactQuery, ColdThresholdIsStricterThanTheWarmOne) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames deep, shallow;
  deep.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.6));
  shallow.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.98));
  ContactWorkspace reference(tree, ContactOptions{});
  ASSERT_TRUE(query_contact(tree, plane, deep, reference));
  const double all_nodes = static_cast<double>(reference.result().statistics.nodes_traversed);

  // Between V_C and V_W: a cold workspace stops short, one that rendered every level just
  // before (shallow contact) keeps the levels warm and renders them all.
  ContactOptions options;
  options.degradation.mode = DegradationOptions::Mode::node_count;
  options.degradation.warm_threshold = all_nodes / 0.9;
  ContactWorkspace cold(tree, options), warm(tree, options);
  ASSERT_TRUE(query_contact(tree, plane, deep, cold));
  EXPECT_FALSE(cold.result().statistics.complete);
  ASSERT_TRUE(query_contact(tree, plane, shallow, warm));
  ASSERT_TRUE(warm.result().statistics.complete);
  ASSERT_TRUE(query_contact(tree, plane, deep, warm));
  EXPECT_TRUE(warm.result().statistics.complete);
  EXPECT_EQ(warm.result().force, reference.result().force);
}

TEST(ContactQuery, TimeBudgetStopsEarlyWhenTight) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.5));
  ContactOptions tight, generous;
  tight.degradation.mode = generous.degradation.mode = DegradationOptions::Mode::time_budget;
  tight.degradation.budget_microseconds = 0.5;
  generous.degradation.budget_microseconds = 1e6;
  ContactWorkspace a(tree, tight), b(tree, generous);
  for (int repeat = 0; repeat < 3; ++repeat) {
    ASSERT_TRUE(query_contact(tree, plane, frames, a));
    ASSERT_TRUE(query_contact(tree, plane, frames, b));
    EXPECT_EQ(a.result().statistics.deepest_level, 0);
    EXPECT_FALSE(a.result().statistics.complete);
    EXPECT_TRUE(b.result().statistics.complete);
  }
}

/// A clock for DegradationOptions::clock that only LookupTimed fields move, by 1 µs per lookup: a
/// query's time is its number of lookups, the same in every run.
struct LookupClock {
  static inline std::int64_t lookups = 0;
  static double now() noexcept { return 1e-6 * static_cast<double>(lookups); }
};

/// An analytic shape whose every lookup costs 1 µs on LookupClock.
struct LookupTimed {
  ImplicitShape shape;
  double distance(const Eigen::Vector3d& p) const noexcept {
    ++LookupClock::lookups;
    return shape.distance(p);
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& g) const noexcept {
    ++LookupClock::lookups;
    return shape.distance_and_gradient(p, g);
  }
};

/// Every ContactResult member, exactly.
void expect_identical(const ContactResult& a, const ContactResult& b) {
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.torque, b.torque);
  EXPECT_EQ(a.force_by_translation, b.force_by_translation);
  EXPECT_EQ(a.force_by_rotation, b.force_by_rotation);
  EXPECT_EQ(a.torque_by_translation, b.torque_by_translation);
  EXPECT_EQ(a.torque_by_rotation, b.torque_by_rotation);
  EXPECT_EQ(a.pointshell_reduced_force, b.pointshell_reduced_force);
  EXPECT_EQ(a.statistics.points_in_contact, b.statistics.points_in_contact);
  EXPECT_EQ(a.statistics.deepest_penetration, b.statistics.deepest_penetration);
  EXPECT_EQ(a.statistics.deepest_level, b.statistics.deepest_level);
  EXPECT_EQ(a.statistics.complete, b.statistics.complete);
}

// Issue 19 item 3: a time budget cuts only queries that do not fit it. On a clock that only
// lookups move, a budget half a lookup above a query's full cost never cuts it (the result is
// the full traversal's, bit for bit); below it the query returns within one clock interval
// (2 batches of 16 lookups) past the budget, either complete (its last level ended in that
// interval) or with the levels it completed, bit for bit as max_level would. Rigid and
// deformable pointshells, several poses, budgets from a fifth of the cost up; and the cold
// threshold.
TEST(ContactQuery, TimeBudgetCutsExactlyTheQueriesThatDoNotFit) {
  const auto check = [](const auto& tree, const auto& query) {
    const auto run = [&](const ContactOptions& options) {
      ContactWorkspace workspace(tree, options);  // new: no contact floor from an earlier query
      const std::int64_t before = LookupClock::lookups;
      EXPECT_TRUE(query(workspace));
      return std::pair(workspace.result(), LookupClock::lookups - before);
    };
    const auto [full, cost] = run(ContactOptions{});
    ASSERT_GT(full.statistics.points_in_contact, 0);
    ASSERT_GT(full.statistics.deepest_level, 1);
    int cut = 0;
    for (const double budget : {0.2 * static_cast<double>(cost), 0.5 * static_cast<double>(cost),
                                static_cast<double>(cost) - 0.5, static_cast<double>(cost) + 0.5}) {
      ContactOptions options;
      options.degradation.mode = DegradationOptions::Mode::time_budget;
      options.degradation.budget_microseconds = budget;
      options.degradation.clock = &LookupClock::now;
      options.degradation.cold_fraction = 1.0;  // a new workspace's levels are all cold
      const auto [budgeted, spent] = run(options);
      if (budget > static_cast<double>(cost)) {
        expect_identical(budgeted, full);
        continue;
      }
      // Within one clock interval of the budget, having completed what it could.
      EXPECT_LE(static_cast<double>(spent), budget + 2 * 16) << "budget " << budget;
      EXPECT_LE(budgeted.statistics.microseconds, budget + 2 * 16);
      if (budgeted.statistics.complete) {
        EXPECT_GT(budget, static_cast<double>(cost) - 2 * 16) << "not cut, " << cost;
        expect_identical(budgeted, full);
        continue;
      }
      ++cut;
      ContactOptions fixed;
      fixed.max_level = budgeted.statistics.deepest_level;
      expect_identical(budgeted, run(fixed).first);
    }
    EXPECT_GE(cut, 2);
    // With the cold threshold, a level the previous query did not render must fit in that
    // share of the budget: the level of detail goes finer only with room to spare.
    ContactOptions cold;
    cold.degradation.mode = DegradationOptions::Mode::time_budget;
    cold.degradation.budget_microseconds = static_cast<double>(cost) / 0.9;
    cold.degradation.clock = &LookupClock::now;
    cold.degradation.cold_fraction = 0.8;
    EXPECT_FALSE(run(cold).first.statistics.complete);
    cold.degradation.cold_fraction = 0.95;
    expect_identical(run(cold).first, full);
  };
  const PointTree& sphere = fixture().sphere;
  const LookupTimed plane{ground()};
  for (const double height : {0.9, 0.7, 0.5}) {
    ContactFrames frames;
    frames.pointshell = pose(Eigen::Vector3d(0.3, 0.1, 0.0), Eigen::Vector3d(0.0, 0.0, height));
    check(sphere, [&](ContactWorkspace& w) { return query_contact(sphere, plane, frames, w); });
  }
  const DeformablePointTree& cube = fixture().cube;
  const LookupTimed ball{Sphere(Eigen::Vector3d::Zero(), 0.45)};
  std::mt19937 random(5);
  std::normal_distribution<double> gauss(0.0, 0.1);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd q(r);
    for (Eigen::Index j = 0; j < r; ++j) q[j] = gauss(random);
    ContactFrames frames;
    frames.field = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.1 - 0.1 * trial, 0.5, 0.4));
    frames.grasp_point = frames.field.translation();
    check(cube, [&](ContactWorkspace& w) { return query_contact(cube, q, ball, frames, w); });
  }
}

TEST(ContactQuery, AreaWeightsScaleEachPointAndCountTowardsL) {
  const PointTree& tree = fixture().sphere;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.9));
  ContactOptions options;
  options.scaling_count = 1e9;
  ContactWorkspace unit(tree, options), doubled(tree, options);
  doubled.set_area_weights(std::vector<double>(static_cast<std::size_t>(tree.num_points()), 2.0));
  ASSERT_TRUE(query_contact(tree, plane, frames, unit));
  ASSERT_TRUE(query_contact(tree, plane, frames, doubled));
  expect_close(doubled.result().force, 2.0 * unit.result().force, 1e-14);
  // With L in effect, uniform weights cancel in L/ℓ.
  options.scaling_count = 10.0;
  unit.set_options(options);
  doubled.set_options(options);
  ASSERT_TRUE(query_contact(tree, plane, frames, unit));
  ASSERT_TRUE(query_contact(tree, plane, frames, doubled));
  ASSERT_GT(unit.result().statistics.points_in_contact, 20);
  expect_close(doubled.result().force, unit.result().force, 1e-14);
  EXPECT_THROW(doubled.set_area_weights({1.0, 2.0}), Error);
  std::vector<double> bad(static_cast<std::size_t>(tree.num_points()), 1.0);
  bad[7] = 0.0;
  EXPECT_THROW(doubled.set_area_weights(bad), Error);
}

TEST(ContactQuery, ARigidQueryOnADeformablePairsWorkspaceLeavesNoReducedForce) {
  const DeformablePointTree& cube = fixture().cube;
  const ImplicitShape ball = Sphere(Eigen::Vector3d::Zero(), 0.45);
  ContactWorkspace workspace(cube, ContactOptions{});
  ContactFrames frames;
  frames.field = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.2, 0.5, 0.4));
  ASSERT_TRUE(
      query_contact(cube, Eigen::VectorXd(Eigen::VectorXd::Zero(r)), ball, frames, workspace));
  ASSERT_GT(workspace.result().pointshell_reduced_force.norm(), 0.0);
  ASSERT_TRUE(query_contact(cube.tree(), ball, frames, workspace));
  EXPECT_GT(workspace.result().statistics.points_in_contact, 0);
  EXPECT_EQ(workspace.result().pointshell_reduced_force, Eigen::VectorXd::Zero(r));
}

TEST(ContactQuery, RejectsBadInputWithoutThrowingAndAllocatesNothing) {
  const PointTree& sphere = fixture().sphere;
  const DeformablePointTree& cube = fixture().cube;
  const ImplicitShape plane = ground();
  ContactFrames frames;
  frames.pointshell = pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.5));
  ContactOptions options;
  options.coherence.enabled = true;
  options.coherence.max_translation = 1e-3;
  options.degradation.mode = DegradationOptions::Mode::time_budget;
  ContactWorkspace rigid(sphere, options), deformable(cube, options);
  ASSERT_TRUE(query_contact(sphere, plane, frames, rigid));
  Eigen::VectorXd q = Eigen::VectorXd::Constant(r, 0.01);
  ASSERT_TRUE(query_contact(cube, q, plane, frames, deformable));
  test::allocation_count = 0;
  EXPECT_TRUE(query_contact(sphere, plane, frames, rigid));
  EXPECT_TRUE(query_contact(cube, q, plane, frames, deformable));
  EXPECT_EQ(test::allocation_count.load(), 0U);
  EXPECT_FALSE(query_contact(cube.tree(), plane, frames, rigid));  // another tree
  EXPECT_EQ(rigid.result().force, Eigen::Vector3d::Zero());
  EXPECT_FALSE(query_contact(cube, Eigen::VectorXd(Eigen::VectorXd::Zero(r + 1)), plane, frames,
                             deformable));
  q[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(query_contact(cube, q, plane, frames, deformable));
  ContactFrames broken = frames;
  broken.grasp_point.x() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(query_contact(sphere, plane, broken, rigid));
  EXPECT_EQ(rigid.result().statistics.nodes_traversed, 0);

  ContactOptions bad;
  bad.stiffness = -1.0;
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { ContactWorkspace w(sphere, bad); }, "stiffness"));
  bad = ContactOptions{};
  bad.degradation.cold_fraction = 1.5;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { rigid.set_options(bad); }, "cold_fraction"));
}

}  // namespace
}  // namespace khz::contact
