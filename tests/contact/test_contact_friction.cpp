// Coulomb friction on the distributed contact (FrictionOptions, issue 20 item 1): the stick and
// slip laws against their closed forms on a flat patch, the force and its four gradients against
// central differences in both regimes, anchors across levels graceful degradation did not render
// and across temporal-coherence skips, dissipation over a closed path, the tangential reaction in
// a deformable pointshell's reduced force, and no allocation.

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include "query_test_fixture.hpp"

#include <cmath>
#include <vector>

namespace khz::contact {
namespace {

using query_test::Differences;
using query_test::expect_gradients_match;
using query_test::finite_differences;
using query_test::fixture;
using query_test::ground;
using query_test::pose;

ContactOptions friction_options(double static_coefficient, double kinetic_coefficient) {
  ContactOptions options;
  options.stiffness = 500.0;
  options.scaling_count = 1e9;  // no L/ℓ scaling: the sums are the closed forms
  options.friction.static_coefficient = static_coefficient;
  options.friction.kinetic_coefficient = kinetic_coefficient;
  options.friction.stick_distance = 1e-4;  // the fields are analytic: no voxel for the default
  return options;
}

/// A flat square patch of n × n points 1 cm apart in the plane z = 0 of its body, inward normal
/// +z (the bottom face of a body above it), one level.
PointTree flat_patch(int n) {
  Pointshell shell;
  shell.points.resize(n * n, 3);
  shell.normals.resize(n * n, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      shell.points.row(i * n + j) << 0.01 * i, 0.01 * j, 0.0;
      shell.normals.row(i * n + j) << 0.0, 0.0, 1.0;
    }
  }
  shell.level_ends = {n * n};
  return PointTree(shell);
}

/// The patch pressed `depth` into the ground (z < 0) and moved by `slide` along it.
ContactFrames patch_frames(double depth, const Eigen::Vector3d& slide) {
  ContactFrames frames;
  frames.pointshell.translation() = Eigen::Vector3d(0.0, 0.0, -depth) + slide;
  frames.grasp_point = frames.pointshell.translation();
  return frames;
}

TEST(ContactFriction, FlatPatchSticksUpToTheStaticLimitThenSlidesAtTheKineticOne) {
  constexpr int n = 5;
  constexpr double depth = 1e-3;
  const PointTree patch = flat_patch(n);
  const ImplicitShape floor = ground();
  ContactOptions options = friction_options(0.5, 0.3);
  options.friction.stick_distance = 2e-4;
  options.haptic_object = HapticObject::pointshell;
  const double k = options.stiffness;
  const double k_t = 0.5 * k * depth / options.friction.stick_distance;  // μ_s |f_n| / δ
  const double points = n * n;
  const double normal = points * k * depth;  // |F_n| of the whole patch
  // Stuck while k_t Δ ≤ μ_s k d per point: Δ ≤ δ.
  const double breakaway = options.friction.stick_distance;

  ContactWorkspace workspace(patch, options);
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(depth, Eigen::Vector3d::Zero()), workspace));
  EXPECT_EQ(workspace.result().statistics.points_in_contact, n * n);
  EXPECT_NEAR(workspace.result().force.x(), 0.0, 1e-15) << "a point anchors where it enters";
  EXPECT_EQ(workspace.friction_state(0), FrictionState::anchored);

  // Just below the static limit: the anchors hold, pulling back with k_t Δ each.
  const double stuck = 0.99 * breakaway;
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(depth, {stuck, 0.0, 0.0}), workspace));
  EXPECT_EQ(workspace.result().statistics.points_sliding, 0);
  EXPECT_EQ(workspace.friction_state(n), FrictionState::stuck);
  EXPECT_NEAR(workspace.result().force.x(), -points * k_t * stuck, 1e-12 * normal);
  EXPECT_NEAR(workspace.result().force.z(), normal, 1e-12 * normal);
  EXPECT_NEAR(workspace.result().force_by_translation(0, 0), -points * k_t, 1e-9 * k_t);

  // Just past it: every point slides, held at μ_k |f_n|.
  ASSERT_TRUE(
      query_contact(patch, floor, patch_frames(depth, {1.01 * breakaway, 0.0, 0.0}), workspace));
  EXPECT_EQ(workspace.result().statistics.points_sliding, n * n);
  EXPECT_EQ(workspace.friction_state(n), FrictionState::sliding);
  EXPECT_NEAR(workspace.result().force.x(), -0.3 * normal, 1e-12 * normal);
  // Sliding on: the kinetic pull, whatever the distance.
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(depth, {0.01, 0.002, 0.0}), workspace));
  EXPECT_EQ(workspace.result().statistics.points_sliding, n * n);
  const Eigen::Vector3d slid(workspace.result().force.x(), workspace.result().force.y(), 0.0);
  EXPECT_NEAR(slid.head<2>().norm(), 0.3 * normal, 1e-12 * normal);
  // The kinetic pull points against the motion since the anchors were dragged.
  const Eigen::Vector2d motion =
      Eigen::Vector2d(0.01, 0.002) - Eigen::Vector2d(1.01 * breakaway, 0);
  EXPECT_GT(-slid.head<2>().normalized().dot(motion.normalized()), 0.99);

  // A step back less than the kinetic spring's stretch (μ_k δ / μ_s = 0.12 mm): it sticks
  // again, the pull now the spring's, smaller than the kinetic limit.
  const Eigen::Vector3d dragged = -slid.normalized();  // the anchors trail the points along it
  const Eigen::Vector3d back = Eigen::Vector3d(0.01, 0.002, 0.0) - 0.5e-4 * dragged;
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(depth, back), workspace));
  EXPECT_EQ(workspace.result().statistics.points_sliding, 0);
  EXPECT_NEAR(workspace.result().force.head<2>().norm(),
              points * k_t * (0.3 / 0.5 * breakaway - 0.5e-4), 1e-9 * normal);

  // Lifted off, then pressed again: the anchors are gone, nothing pulls sideways.
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(-0.01, back), workspace));
  EXPECT_EQ(workspace.result().statistics.points_in_contact, 0);
  EXPECT_EQ(workspace.friction_state(0), FrictionState::none);
  ASSERT_TRUE(query_contact(patch, floor, patch_frames(depth, back), workspace));
  EXPECT_NEAR(workspace.result().force.head<2>().norm(), 0.0, 1e-15);
}

// The patch pressed into a floor tilted about x, so that its rows along x are pressed from 1.8
// down to 0.2 mm deep, then pushed along x (keeping every depth): every point gives the same
// distance before it slides, so the patch sticks up to μ_s times its whole normal force and breaks
// loose there, however unevenly the load is shared (the reference: μ_s Σ k |d| over the points,
// from their depths).
TEST(ContactFriction, AnUnevenlyLoadedPatchBreaksLooseAtTheStaticLimitOfItsWholeLoad) {
  constexpr int n = 5;
  const PointTree patch = flat_patch(n);
  const double tilt = 0.04;  // rad: the floor rises 0.4 mm per 1 cm along y
  const ImplicitShape floor = HalfSpace(Eigen::Vector3d(0.0, std::sin(tilt), std::cos(tilt)), 0.0);
  ContactOptions options = friction_options(0.5, 0.3);
  options.haptic_object = HapticObject::pointshell;
  double normal = 0.0;
  for (int j = 0; j < n; ++j) {
    normal += n * options.stiffness * (1.8e-3 * std::cos(tilt) - 0.01 * j * std::sin(tilt));
  }
  ContactWorkspace workspace(patch, options);
  ASSERT_TRUE(
      query_contact(patch, floor, patch_frames(1.8e-3, Eigen::Vector3d::Zero()), workspace));
  ASSERT_EQ(workspace.result().statistics.points_in_contact, n * n);
  ASSERT_NEAR(workspace.result().force.z(), normal, 1e-12 * normal);
  double largest = 0.0;
  for (double slide = 0.0; slide < 3.0 * options.friction.stick_distance; slide += 0.5e-6) {
    ASSERT_TRUE(query_contact(patch, floor, patch_frames(1.8e-3, {slide, 0.0, 0.0}), workspace));
    largest = std::max(largest, -workspace.result().force.x());
    if (slide < 0.99 * options.friction.stick_distance) {
      EXPECT_EQ(workspace.result().statistics.points_sliding, 0) << slide;
    }
  }
  EXPECT_NEAR(largest, 0.5 * normal, 0.01 * 0.5 * normal);
  EXPECT_EQ(workspace.result().statistics.points_sliding, n * n);
  EXPECT_NEAR(-workspace.result().force.x(), 0.3 * normal, 1e-9 * normal);
}

// Lifted off, the query stops at level 0 (every deeper node culled): the deeper levels' points
// lose their anchors too, so pressed again a little further on, every point anchors anew and
// nothing pulls sideways.
TEST(ContactFriction, LiftingOffDropsTheAnchorsOfEveryLevel) {
  const PointTree& sphere = fixture().sphere;
  const ImplicitShape floor = ground();
  ContactWorkspace workspace(sphere, friction_options(0.5, 0.4));
  ASSERT_TRUE(query_contact(sphere, floor, patch_frames(0.03, {0.0, 0.0, 1.0}), workspace));
  ASSERT_EQ(workspace.result().statistics.deepest_level, sphere.num_levels() - 1);
  ASSERT_TRUE(query_contact(sphere, floor, patch_frames(-3.0, {0.0, 0.0, 1.0}), workspace));
  ASSERT_EQ(workspace.result().statistics.deepest_level, 0);
  ASSERT_TRUE(query_contact(sphere, floor, patch_frames(0.03, {0.005, 0.0, 1.0}), workspace));
  EXPECT_GT(workspace.result().statistics.points_in_contact, 50);
  ContactWorkspace frictionless(sphere, friction_options(0.0, 0.0));
  ASSERT_TRUE(query_contact(sphere, floor, patch_frames(0.03, {0.005, 0.0, 1.0}), frictionless));
  EXPECT_EQ(workspace.result().force, frictionless.result().force);
  for (Eigen::Index s = 0; s < sphere.num_points(); ++s) {
    const FrictionState state = workspace.friction_state(s);
    EXPECT_TRUE(state == FrictionState::none || state == FrictionState::anchored) << "point " << s;
  }
}

TEST(ContactFriction, ZeroCoefficientsAreTheFrictionlessQuery) {
  const PointTree& sphere = fixture().sphere;
  const ImplicitShape floor = ground();
  ContactOptions frictionless = friction_options(0.0, 0.0);
  ContactOptions stiff_but_off = friction_options(0.0, 0.0);
  stiff_but_off.friction.stick_distance = 1e-6;  // no effect while μ_s = 0
  ContactWorkspace a(sphere, frictionless), b(sphere, stiff_but_off);
  for (double x : {0.0, 0.01, 0.03}) {
    const ContactFrames frames = patch_frames(0.05, {x, 0.0, 1.0});
    ASSERT_TRUE(query_contact(sphere, floor, frames, a));
    ASSERT_TRUE(query_contact(sphere, floor, frames, b));
    EXPECT_EQ(a.result().force, b.result().force);
    EXPECT_EQ(a.result().force_by_rotation, b.result().force_by_rotation);
    EXPECT_EQ(b.result().statistics.points_sliding, 0);
    EXPECT_EQ(b.friction_state(0), FrictionState::none);
  }
}

/// The gradients of the force a query returns, from the anchors as that query found them: the
/// workspace is copied before each differenced query.
class FrictionGradients : public ::testing::TestWithParam<HapticObject> {};

TEST_P(FrictionGradients, MatchFiniteDifferencesInStickAndInSlip) {
  // Smooth fields (spheres) and no L/ℓ scaling, as in ContactGradients.
  const ImplicitUnion field(
      {Sphere(Eigen::Vector3d(0.2, 0.0, 0.0), 0.6), Sphere(Eigen::Vector3d(-0.4, 0.3, 0.1), 0.3)});
  ContactOptions options = friction_options(0.6, 0.4);
  options.friction.stick_distance = 0.01;  // scaled to the 1 m sphere: the small move sticks
  options.haptic_object = GetParam();
  ContactFrames start;
  start.pointshell = pose(Eigen::Vector3d(0.2, -0.1, 0.4), Eigen::Vector3d(0.1, 0.0, -0.2));
  start.field = pose(Eigen::Vector3d(-0.3, 0.2, 0.1), Eigen::Vector3d(0.5, 0.6, 0.9));
  start.grasp_point = Eigen::Vector3d(0.4, 0.2, 0.7);

  const auto check = [&](const auto& tree, Eigen::Index points, const auto& query,
                         const ContactFrames& first) {
    ContactWorkspace anchored(tree, options);
    ASSERT_TRUE(query(first, anchored));
    const std::int64_t contacts = anchored.result().statistics.points_in_contact;
    ASSERT_GT(contacts, 20);
    // Moved a little (most points stick) and far (most slide), turned too.
    for (const double scale : {2e-4, 0.16}) {
      ContactFrames moved = first;
      moved.pointshell =
          pose(Eigen::Vector3d(0.5, -0.3, 0.2) * scale, Eigen::Vector3d(0.4, 1.0, -0.7) * scale) *
          first.pointshell;
      ContactWorkspace at_moved = anchored;
      ASSERT_TRUE(query(moved, at_moved));
      const ContactResult result = at_moved.result();
      // Of the points that held an anchor (the others entered contact and pull nothing yet).
      std::int64_t stuck = 0;
      for (Eigen::Index s = 0; s < points; ++s) {
        stuck += at_moved.friction_state(s) == FrictionState::stuck ? 1 : 0;
      }
      const std::int64_t sliding = result.statistics.points_sliding;
      SCOPED_TRACE(testing::Message()
                   << "scale " << scale << ": " << sliding << " sliding, " << stuck << " stuck");
      if (scale < 1e-3) {
        EXPECT_LT(4 * sliding, stuck);
      } else {
        EXPECT_GT(sliding, stuck);
      }
      // Not vacuous: friction moves the force.
      ContactOptions frictionless = options;
      frictionless.friction = {};
      ContactWorkspace without(tree, frictionless);
      ASSERT_TRUE(query(moved, without));
      EXPECT_GT((result.force - without.result().force).norm(), 1e-3 * result.force.norm());
      expect_gradients_match(
          result, finite_differences(moved, GetParam(), [&](const ContactFrames& differenced) {
            ContactWorkspace copy = anchored;
            query(differenced, copy);
            return ContactResult(copy.result());
          }));
    }
  };

  const PointTree& sphere = fixture().sphere;
  check(
      sphere, sphere.num_points(),
      [&](const ContactFrames& frames, ContactWorkspace& workspace) {
        return query_contact(sphere, field, frames, workspace);
      },
      start);

  const DeformablePointTree& cube = fixture().cube;
  Eigen::VectorXd q(query_test::r);
  q << 0.2, -0.1, 0.05, 0.3, -0.2, 0.1;
  ContactFrames cube_start = start;
  cube_start.field =
      pose(Eigen::Vector3d(-0.3, 0.2, 0.1), start.pointshell * Eigen::Vector3d(1.1, 0.6, 0.5));
  check(
      cube, cube.tree().num_points(),
      [&](const ContactFrames& frames, ContactWorkspace& workspace) {
        return query_contact(cube, q, field, frames, workspace);
      },
      cube_start);
}

INSTANTIATE_TEST_SUITE_P(HapticObjects, FrictionGradients,
                         ::testing::Values(HapticObject::distance_field, HapticObject::pointshell));

// A level graceful degradation does not render keeps its points' anchors: when a later query
// renders it again, they continue stuck from where they were (not anchored anew), as in a
// workspace that rendered the level throughout. Their pull is not that workspace's: it brought
// its stuck points to the deep press's load as it happened (their stretch shrank, FrictionOptions),
// these only when their level is rendered again, to the load the pair was last measured with.
TEST(ContactFriction, AnchorsOfALevelNotRenderedHoldUntilItIsRenderedAgain) {
  const PointTree& sphere = fixture().sphere;
  const ImplicitShape floor = ground();
  ContactOptions full = friction_options(0.8, 0.6);
  full.scaling_count = 10.0;            // as the scenes run it
  full.friction.stick_distance = 0.01;  // scaled to the 1 m sphere: its 0.2 mm moves stick
  const int last = sphere.num_levels() - 1;
  // A shallow press renders every level; a deeper one costs more than the threshold at the last
  // level: set the threshold between the two full traversals.
  const ContactFrames shallow = patch_frames(0.02, {0.0, 0.0, 1.0});
  const ContactFrames deep = patch_frames(0.05, {1e-4, 0.0, 1.0});
  const ContactFrames back = patch_frames(0.02, {2e-4, 0.0, 1.0});
  ContactWorkspace reference(sphere, full);
  ASSERT_TRUE(query_contact(sphere, floor, deep, reference));
  const double deep_cost = static_cast<double>(reference.result().statistics.nodes_traversed);
  ASSERT_TRUE(query_contact(sphere, floor, shallow, reference));
  const double shallow_cost = static_cast<double>(reference.result().statistics.nodes_traversed);
  ASSERT_LT(shallow_cost, deep_cost);
  ContactOptions degraded = full;
  degraded.degradation.mode = DegradationOptions::Mode::node_count;
  degraded.degradation.warm_threshold = 0.5 * (shallow_cost + deep_cost);
  degraded.degradation.cold_fraction = 1.0;

  reference = ContactWorkspace(sphere, full);
  ContactWorkspace workspace(sphere, degraded);
  const int expected_deepest[] = {last, last - 1, last};  // the deep press cuts the last level
  int k = 0;
  for (const ContactFrames& frames : {shallow, deep, back}) {
    ASSERT_TRUE(query_contact(sphere, floor, frames, reference));
    ASSERT_TRUE(query_contact(sphere, floor, frames, workspace));
    ASSERT_EQ(workspace.result().statistics.deepest_level, expected_deepest[k++]);
  }
  // The last level's points in contact continue from their anchors (anchored anew, they would
  // pull nothing).
  int stuck_on_last = 0;
  for (Eigen::Index s = sphere.pointshell().level_begin(last); s < sphere.num_points(); ++s) {
    EXPECT_EQ(workspace.friction_state(s), reference.friction_state(s)) << "point " << s;
    stuck_on_last += workspace.friction_state(s) == FrictionState::stuck ? 1 : 0;
  }
  EXPECT_GT(stuck_on_last, 10);
}

// Temporal coherence skips only nodes apart from the surface, so it changes no friction result.
TEST(ContactFriction, TemporalCoherenceChangesNoResult) {
  const PointTree& sphere = fixture().sphere;
  const ImplicitShape floor = ground();
  const ContactOptions plain = friction_options(0.5, 0.4);
  ContactOptions coherent = plain;
  coherent.coherence.enabled = true;
  coherent.coherence.max_translation = 6e-3;
  ContactWorkspace a(sphere, plain), b(sphere, coherent);
  std::int64_t skipped = 0, sliding = 0;
  for (int step = 0; step < 60; ++step) {
    // A slide with a press that deepens and eases: points enter, stick, slide and leave.
    const double depth = 0.03 + 0.02 * std::sin(0.2 * step);
    const ContactFrames frames = patch_frames(depth, {1.5e-3 * step, 0.0, 1.0});
    ASSERT_TRUE(query_contact(sphere, floor, frames, a));
    ASSERT_TRUE(query_contact(sphere, floor, frames, b));
    EXPECT_EQ(a.result().force, b.result().force) << "step " << step;
    EXPECT_EQ(a.result().torque, b.result().torque) << "step " << step;
    skipped += b.result().statistics.nodes_skipped;
    sliding += a.result().statistics.points_sliding;
  }
  EXPECT_GT(skipped, 1000);
  EXPECT_GT(sliding, 100);
}

// Friction only dissipates: over a closed path pressed along the ground, the contact does
// negative work on the pointshell (and none, to round-off, without friction).
TEST(ContactFriction, ClosedPathDissipates) {
  const PointTree& sphere = fixture().sphere;
  const ImplicitShape floor = ground();
  const auto work_around_square = [&](const ContactOptions& options) {
    ContactOptions on_pointshell = options;
    on_pointshell.haptic_object = HapticObject::pointshell;
    ContactWorkspace workspace(sphere, on_pointshell);
    constexpr int steps_per_side = 200;
    constexpr double side = 0.02;
    std::vector<Eigen::Vector3d> path;
    const Eigen::Vector3d corners[] = {{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0}};
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < steps_per_side; ++k) {
        path.push_back(corners[c] + (corners[(c + 1) % 4] - corners[c]) * k / steps_per_side);
      }
    }
    path.push_back(corners[0]);
    double work = 0.0;
    Eigen::Vector3d previous_force = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < path.size(); ++i) {
      const Eigen::Vector3d at = path[i] + Eigen::Vector3d(0.0, 0.0, 1.0);
      EXPECT_TRUE(query_contact(sphere, floor, patch_frames(0.03, at), workspace));
      const Eigen::Vector3d force = workspace.result().force;
      if (i > 0) work += 0.5 * (force + previous_force).dot(path[i] - path[i - 1]);
      previous_force = force;
    }
    return work;
  };
  const double frictionless = work_around_square(friction_options(0.0, 0.0));
  const double with_friction = work_around_square(friction_options(0.5, 0.4));
  // The normal force here is about k · ℓ-scaled depth ~ 10 N; friction's loss ~ μ F · 8 cm.
  EXPECT_LT(std::abs(frictionless), 1e-6);
  EXPECT_LT(with_friction, -0.1);
}

// Friction gives back no energy it did not take when the press changes too: one point slid along
// the ground, pressed deeper, slid back and released, round and round (a rectangle in slide and
// depth). The anchor spring stiffens with the load (k_t ∝ |f_n|); were its stretch kept as the
// point is pressed, every round would return ½ Δk_t s² more than it took (measured with that
// model: +9.375e-7 J a round, exactly that). Pressed harder, a stuck contact keeps its pull
// instead (its stretch shrinks by the ratio of the pair's total load), so every round takes
// energy, sticking or sliding (measured: 9.37e-7 J stuck, 3.2e-5 J sliding).
TEST(ContactFriction, PressingASlidPointDeeperAndReleasingItGivesBackNothingItDidNotTake) {
  const PointTree point = flat_patch(1);
  const ImplicitShape floor = ground();
  ContactOptions options = friction_options(0.5, 0.4);
  options.haptic_object = HapticObject::pointshell;
  const double d1 = 1e-4, d2 = 4e-4;                                    // depths (m)
  for (const double slide : {0.5 * options.friction.stick_distance,     // stuck throughout
                             4.0 * options.friction.stick_distance}) {  // slides too
    SCOPED_TRACE(slide);
    ContactWorkspace workspace(point, options);
    const Eigen::Vector2d corners[] = {{0.0, d1}, {slide, d1}, {slide, d2}, {0.0, d2}};
    std::vector<Eigen::Vector2d> path;  // (slide, depth)
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < 100; ++k) {
        path.push_back(corners[c] + (corners[(c + 1) % 4] - corners[c]) * k / 100.0);
      }
    }
    path.push_back(corners[0]);
    const double energy_scale = options.stiffness * d2 * d2;
    for (int round = 0; round < 3; ++round) {
      double work = 0.0;  // done by the contact force on the point (> 0: the point gained)
      Eigen::Vector3d previous_force, previous_position;
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Eigen::Vector3d position(path[i].x(), 0.0, -path[i].y());
        ASSERT_TRUE(
            query_contact(point, floor, patch_frames(path[i].y(), {path[i].x(), 0, 0}), workspace));
        const Eigen::Vector3d force = workspace.result().force;
        if (i > 0) work += 0.5 * (force + previous_force).dot(position - previous_position);
        previous_force = force;
        previous_position = position;
      }
      EXPECT_LE(work, 1e-12 * energy_scale) << "round " << round;
      std::printf("slide %.0f um, round %d: the contact's work %.3e J\n", 1e6 * slide, round, work);
    }
  }
}

/// The three rigid translations of a mesh of `vertices` vertices as modes (3·vertices × 3).
Eigen::MatrixXd rigid_translations(Eigen::Index vertices) {
  Eigen::MatrixXd translations = Eigen::MatrixXd::Zero(3 * vertices, 3);
  for (Eigen::Index v = 0; v < vertices; ++v) translations.block<3, 3>(3 * v, 0).setIdentity();
  return translations;
}

// A deformable pointshell's reduced force carries the tangential reaction: with the three rigid
// translations as its modes, U_sᵀ f_s sums to the force on it in its body frame.
TEST(ContactFriction, ReducedForceCarriesTheTangentialReaction) {
  const query_test::Fixture& f = fixture();
  const Eigen::MatrixXd translations = rigid_translations(f.volume.num_vertices());
  const DeformablePointTree cube(f.cube.tree(), f.embedding, translations);
  ContactOptions options = friction_options(0.5, 0.4);
  options.haptic_object = HapticObject::pointshell;
  ContactWorkspace workspace(cube, options);
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
  const ImplicitShape floor = ground();
  const Eigen::Isometry3d turned = pose(Eigen::Vector3d(0.1, 0.2, 0.0), Eigen::Vector3d::Zero());
  for (double x : {0.0, 0.002, 0.02}) {
    ContactFrames frames;
    frames.pointshell = Eigen::Translation3d(x, 0.0, -0.03) * turned;
    ASSERT_TRUE(query_contact(cube, q, floor, frames, workspace));
  }
  const ContactResult& result = workspace.result();
  ASSERT_GT(result.statistics.points_sliding, 10);
  ASSERT_GT(std::hypot(result.force.x(), result.force.y()), 0.1 * result.force.z());
  const Eigen::Vector3d body_force = turned.linear().transpose() * result.force;
  EXPECT_LE((result.pointshell_reduced_force - body_force).norm(), 1e-12 * body_force.norm());
}

// A deformed field's reduced force too: with the three translations as the modes of every
// proxy, the reaction projected at the nearest proxies sums to the force on the field object in
// its body frame.
TEST(ContactFriction, DeformedFieldsReducedForceCarriesTheTangentialReaction) {
  const query_test::Fixture& f = fixture();
  const Eigen::MatrixXd translations = rigid_translations(f.volume.num_vertices());
  DistanceFieldOptions grid_options;
  grid_options.cells = 32;
  const DeformedDistanceField deformed(
      {signed_distance_field(test::unit_cube_surface(), grid_options)}, f.embedding, translations);
  DeformedFieldState field(deformed);
  ASSERT_TRUE(field.update(Eigen::Vector3d::Zero()));
  ContactWorkspace workspace(f.sphere, friction_options(0.5, 0.4), deformed.dimension());
  ContactFrames frames;
  frames.field = pose(Eigen::Vector3d(0.1, -0.2, 0.05), Eigen::Vector3d(0.3, 0.2, -1.3));
  for (double x : {0.0, 0.002, 0.02}) {
    // The unit sphere's bottom pressed 0.1 into the cube's top face, sliding along it.
    frames.pointshell.translation() = frames.field * Eigen::Vector3d(0.5 + x, 0.5, 1.9);
    frames.grasp_point = frames.field * Eigen::Vector3d(0.5, 0.5, 0.5);
    ASSERT_TRUE(query_contact(f.sphere, field, frames, workspace));
  }
  const ContactResult& result = workspace.result();
  ASSERT_GT(result.statistics.points_sliding, 10);
  const Eigen::Vector3d body_force = frames.field.linear().transpose() * result.force;
  ASSERT_GT(std::hypot(body_force.x(), body_force.y()), 0.1 * std::abs(body_force.z()));
  EXPECT_LE((result.field_reduced_force - body_force).norm(), 1e-12 * body_force.norm());
}

// The ground sampled on a grid of voxel h = 2 mm (its node values exact: d = z is trilinear).
DistanceGrid gridded_ground(double h) {
  GridGeometry geometry;
  geometry.cells = 50;
  geometry.spacing = h;
  geometry.origin = Eigen::Vector3d::Constant(-25.0 * h);
  const int n = geometry.cells + 1;
  std::vector<float> values;
  values.reserve(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i)
        values.push_back(static_cast<float>(geometry.node_position(i, j, k).z()));
    }
  }
  return DistanceGrid(geometry, std::move(values), true);
}

// Left at 0, the stick distance is μ_s h of the field queried: on a 2 mm grid with μ_s = 0.5
// the patch breaks loose after δ = 1 mm, exactly as with that δ given; against an analytic
// field, which has no voxel, the query refuses until δ is given.
TEST(ContactFriction, TheDefaultStickDistanceIsTheStaticCoefficientTimesTheFieldsVoxel) {
  constexpr int n = 5;
  constexpr double depth = 1e-3, h = 2e-3;
  const PointTree patch = flat_patch(n);
  const DistanceGrid floor = gridded_ground(h);
  EXPECT_EQ(floor.cell_size(), h);
  ContactOptions automatic = friction_options(0.5, 0.3);
  automatic.friction.stick_distance = 0.0;
  automatic.haptic_object = HapticObject::pointshell;
  ContactOptions given = automatic;
  given.friction.stick_distance = 0.5 * h;
  EXPECT_EQ(automatic.friction.stick_distance_for(h), given.friction.stick_distance);

  ContactWorkspace by_default(patch, automatic), by_hand(patch, given);
  for (const double slide : {0.0, 0.5 * 0.99 * h, 0.5 * 1.01 * h, 0.5 * 1.5 * h}) {
    const ContactFrames frames = patch_frames(depth, {slide, 0.0, 0.0});
    ASSERT_TRUE(query_contact(patch, floor, frames, by_default));
    ASSERT_TRUE(query_contact(patch, floor, frames, by_hand));
    EXPECT_EQ(by_default.result().force, by_hand.result().force) << slide;
    EXPECT_EQ(by_default.result().force_by_translation, by_hand.result().force_by_translation);
    EXPECT_EQ(by_default.result().statistics.points_sliding,
              by_hand.result().statistics.points_sliding);
    // Stuck below μ_s h, sliding past it (the breakaway distance is δ; the closed forms are
    // FlatPatchSticksUpToTheStaticLimitThenSlidesAtTheKineticOne's).
    EXPECT_EQ(by_default.result().statistics.points_sliding, slide > 0.5 * h ? n * n : 0) << slide;
  }

  const ImplicitShape analytic = ground();
  ContactWorkspace refused(patch, automatic);
  EXPECT_FALSE(
      query_contact(patch, analytic, patch_frames(depth, Eigen::Vector3d::Zero()), refused));
  EXPECT_EQ(refused.result().force, Eigen::Vector3d::Zero());
  ContactWorkspace accepted(patch, given);
  EXPECT_TRUE(
      query_contact(patch, analytic, patch_frames(depth, Eigen::Vector3d::Zero()), accepted));
  // Without friction the default needs no voxel.
  ContactOptions frictionless = automatic;
  frictionless.friction.static_coefficient = frictionless.friction.kinetic_coefficient = 0.0;
  ContactWorkspace plain(patch, frictionless);
  EXPECT_TRUE(query_contact(patch, analytic, patch_frames(depth, Eigen::Vector3d::Zero()), plain));
}

TEST(ContactFriction, RejectsBadCoefficientsAndAllocatesNothingPerQuery) {
  const PointTree& sphere = fixture().sphere;
  for (const auto& [mu_s, mu_k, ratio] :
       std::vector<std::tuple<double, double, double>>{{-0.1, 0.0, 1.0},
                                                       {0.3, 0.4, 1.0},
                                                       {0.5, -0.1, 1.0},
                                                       {0.5, 0.4, -1e-4},
                                                       {std::nan(""), 0.0, 1.0},
                                                       {0.5, 0.4, INFINITY}}) {
    ContactOptions options;
    options.friction = {mu_s, mu_k, ratio};
    EXPECT_THROW(ContactWorkspace(sphere, options), Error) << mu_s << " " << mu_k << " " << ratio;
  }
  ContactOptions kinetic_above;
  kinetic_above.friction = {0.3, 0.4, 1.0};
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { kinetic_above.validate(); },
      "friction.kinetic_coefficient must be finite, ≥ 0 and at most friction.static_coefficient"));

  const ImplicitShape floor = ground();
  ContactWorkspace workspace(sphere, friction_options(0.5, 0.4));
  ASSERT_TRUE(query_contact(sphere, floor, patch_frames(0.03, {0.0, 0.0, 1.0}), workspace));
  test::allocation_count = 0;
  for (int step = 1; step < 20; ++step) {
    query_contact(sphere, floor, patch_frames(0.03, {2e-3 * step, 0.0, 1.0}), workspace);
  }
  EXPECT_EQ(test::allocation_count.load(), 0U);
  EXPECT_GT(workspace.result().statistics.points_sliding, 0);
}

}  // namespace
}  // namespace khz::contact
