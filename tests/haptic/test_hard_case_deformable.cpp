// Hard case 8 of the haptic loop (thesis ch. 4 with §3.6): a reduced deformable pointshell pushed
// hard by a held rigid object and released. Separate from test_hard_cases.cpp because it builds a
// reduced model.
#include "hard_case_fixtures.hpp"

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <numbers>

namespace khz::haptic::hard_cases {
namespace {

constexpr double beam_length = 0.2, beam_side = 0.02;  // m
constexpr double ball_radius = 0.015;                  // m, the held sphere

/// A clamped 20 × 2 × 2 cm plastic beam (E = 100 MPa: 24 Hz, 500 N/m at the tip), an r = 6
/// modal-derivative model, its reduced integrator (Rayleigh damping α = 2/s, β = 2e-4 s), and a
/// 2,000-point pointshell on its surface in ×4 levels.
struct DeformableBeam {
  test::Cantilever beam{beam_length, beam_side, 2, reduced::Material::stvk(1e8, 0.45, 1100.0)};
  reduced::ReducedModel model;
  reduced::PolynomialForces forces;
  std::unique_ptr<reduced::ReducedIntegrator> integrator;
  contact::DeformablePointTree tree;

  DeformableBeam()
      : model(reduced::ReducedModel::precompute(beam.model, basis(beam))),
        forces(model.energy_polynomial()),
        integrator(reduced::make_reduced_newmark(forces, model.mass(), newmark())),
        tree(surface_tree(), reduced::MeshEmbedding(beam.model.mesh()), model.basis().vectors) {}

  static reduced::Basis basis(const test::Cantilever& beam) {
    reduced::ModalDerivativeBasisOptions options;
    options.modes.num_modes = 3;
    options.basis_size = 6;
    return reduced::modal_derivative_basis(beam.model, beam.clamped, options);
  }
  static reduced::ReducedNewmarkOptions newmark() {
    reduced::ReducedNewmarkOptions options;
    options.newmark.time_step = Harness::period;
    options.newmark.mass_damping = 2.0;
    options.newmark.stiffness_damping = 2e-4;
    return options;
  }
  /// The beam's rest surface.
  static reduced::TriangleMesh surface() {
    reduced::TriangleMesh mesh = test::unit_cube_surface();
    mesh.vertices = mesh.vertices * Eigen::Vector3d(beam_length, beam_side, beam_side).asDiagonal();
    return mesh;
  }
  static contact::PointTree surface_tree() {
    return nested_tree(contact::random_pointshell(surface(), 2000, 8), 8);
  }
  double energy() const { return integrator->kinetic_energy() + integrator->strain_energy(); }
};

/// Each case runs frictionless, as in the thesis, and with friction μ_s = 0.5, μ_k = 0.4
/// (issue 20; rubbings()); friction's tangential reaction enters the reduced forces too, and
/// every case must stay as stable with it.
class HardCases : public RubbingCases {};

INSTANTIATE_TEST_SUITE_P(, HardCases, ::testing::ValuesIn(rubbings()), RubbingName());

TEST_P(HardCases, DeformablePointshellPushedHardAndReleased) {
  DeformableBeam b;
  // The held object: a 1.5 cm ball (the distance-field object, the thesis's convention), grasped
  // at its centre. The hand comes down on the beam 3 cm from its tip, pushes 3 cm past its top
  // face (far beyond what the saturated coupling transmits), holds, and lets go at t = 0.8 s.
  const contact::ImplicitShape ball = contact::Sphere(Eigen::Vector3d::Zero(), ball_radius);
  const PairScene scene(b.tree, ball, analytic_options(contact::HapticObject::distance_field),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity(), b.integrator.get());
  const Eigen::Vector3d above(0.17, 0.01, beam_side + ball_radius + 0.01);
  const TargetFunction target = keyframe_target({{0.0, at(above)},
                                                 {0.3, at(above - Eigen::Vector3d(0, 0, 0.04))},
                                                 {0.8, at(above - Eigen::Vector3d(0, 0, 0.04))},
                                                 {0.82, at(above + Eigen::Vector3d(0, 0, 0.1))}});
  // Penetration as the contact sees it: the deepest deformed beam point inside the ball.
  const auto penetration = [&](const Pose& grasp) {
    double deepest = 0.0;
    const Eigen::VectorXd& q = b.integrator->coordinates();
    for (Eigen::Index s = 0; s < b.tree.tree().num_points(); ++s) {
      deepest = std::max(deepest, -ball.distance(b.tree.position(s, q) - grasp.position));
    }
    return deepest;
  };
  Harness harness(target, scene, coupling_options(ball_radius), penetration);

  harness.run(800);
  const std::vector<Sample>& pushed = harness.trace();
  // While pushed: the coupling saturates at F_VC,max, so the beam takes at most that force
  // (scaled by L/ℓ, never above it), bends, and the ball stays within one voxel of its surface.
  const double strongest_contact = largest(
      pushed, 0, pushed.size(), [](const Sample& s) { return s.record.contact.force.norm(); });
  EXPECT_GT(strongest_contact, 0.5 * saturation_force) << "the ball reached the beam";
  EXPECT_LE(strongest_contact, saturation_force * (1.0 + 1e-9));
  const Eigen::VectorXd q_held = b.integrator->coordinates();
  EXPECT_GT(q_held.norm(), 0.0);
  const double energy_held = b.energy();
  EXPECT_GT(energy_held, 1e-6) << "the beam was bent";
  // Rendered stiffness at the held pose, as §4.7 defines it (fixed deformation).
  EXPECT_LE(
      quasi_static_stiffness(harness.coupling(), harness.world(), pushed.back().record.manipulandum,
                             Eigen::Vector3d::UnitZ(), 1e-4),
      coupling_stiffness * (1.0 + 1e-6));

  // Released: once the ball has left, the beam's energy only decays (damping; no contact feeds
  // it), and the beam returns to rest.
  std::vector<double> energy;
  std::size_t free_from = 0;
  for (int i = 0; i < 1500; ++i) {
    const Sample& s = harness.step();
    energy.push_back(b.energy());
    if (free_from == 0 && s.record.contact.statistics.points_in_contact == 0 && i > 20) {
      free_from = energy.size() - 1;
    }
  }
  const std::vector<Sample>& trace = harness.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  for (const Sample& s : trace) {
    ASSERT_TRUE(s.record.integrators_ok && s.record.contact_valid && s.record.coupling_valid);
  }
  EXPECT_LE(largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }), voxel);
  ASSERT_GT(free_from, 0U) << "the ball let go";
  for (std::size_t i = free_from + 1; i < energy.size(); ++i) {
    ASSERT_LE(energy[i], energy[i - 1] * (1.0 + 1e-9) + 1e-15)
        << "energy grew " << i << " cycles after release";
  }
  EXPECT_LT(energy.back(), 0.01 * energy[free_from]);
  std::printf(
      "pushed: contact ≤ %.3f N, beam energy %.3e J, ‖q‖ %.3e; released at cycle %zu "
      "(energy %.3e J), final energy %.3e J, ‖q‖ %.3e; deepest penetration %.3f mm\n",
      strongest_contact, energy_held, q_held.norm(), free_from, energy[free_from], energy.back(),
      b.integrator->coordinates().norm(),
      1e3 * largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }));
  EXPECT_LT(b.integrator->coordinates().norm(), 0.1 * q_held.norm());
  // The hand, lifted away, comes to rest too.
  EXPECT_LT(trace.back().device_energy, 1e-6);
}

TEST_P(HardCases, DeformableToolAgainstDeformableBeam) {
  // Deformable against deformable (§3.12): the hand holds a second beam by its clamped end,
  // pointing down, as the distance-field object (its deformed field from 40 proxies on a 48³
  // rest field), and presses its tip onto the first beam near its tip, then lifts it away. The
  // contact force goes, with opposite signs, into both reduced models.
  DeformableBeam beam, tool;
  contact::DistanceFieldOptions grid;
  grid.cells = 48;
  const contact::DeformedDistanceField tool_field(
      {contact::signed_distance_field(DeformableBeam::surface(), grid)},
      reduced::MeshEmbedding(tool.beam.model.mesh()), tool.model.basis().vectors);
  contact::DeformedFieldState tool_state(tool_field);
  const PairScene scene(beam.tree, tool_state, options(contact::HapticObject::distance_field),
                        Eigen::Vector3d(0.0, beam_side / 2, beam_side / 2),
                        Eigen::Isometry3d::Identity(), beam.integrator.get(),
                        tool.integrator.get());
  // Tool axis x turned onto world −z; its tip starts 1 cm above the beam at x = 17 cm.
  const Eigen::Quaterniond down(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d above(0.17, beam_side / 2, beam_side + beam_length + 0.01);
  const TargetFunction target =
      keyframe_target({{0.0, at(above, down)},
                       {0.3, at(above - Eigen::Vector3d(0, 0, 0.03), down)},
                       {0.6, at(above - Eigen::Vector3d(0, 0, 0.03), down)},
                       {0.62, at(above + Eigen::Vector3d(0, 0, 0.1), down)}});
  const auto penetration = [&](const Pose& grasp) {
    const Eigen::Isometry3d body =
        held_body_pose(grasp, Eigen::Vector3d(0.0, beam_side / 2, beam_side / 2));
    double deepest = 0.0;
    for (Eigen::Index s = 0; s < beam.tree.tree().num_points(); ++s) {
      const Eigen::Vector3d p = beam.tree.position(s, beam.integrator->coordinates());
      deepest = std::max(deepest, -tool_state.distance(body.inverse() * p));
    }
    return deepest;
  };
  Harness harness(target, scene, coupling_options(beam_length), penetration);
  harness.run(600);
  const std::vector<Sample>& pushed = harness.trace();
  EXPECT_GT(largest(pushed, 0, pushed.size(),
                    [](const Sample& s) { return s.record.contact.statistics.points_in_contact; }),
            0.0);
  // Both objects took their share: each was bent (or compressed) by the contact, and the tool's
  // field follows its integrator.
  const double beam_energy = beam.energy(), tool_energy = tool.energy();
  EXPECT_GT(beam_energy, 1e-6);
  EXPECT_GT(tool_energy, 0.0);
  EXPECT_EQ(tool_state.coordinates(), tool.integrator->coordinates());
  harness.run(1500);
  const std::vector<Sample>& trace = harness.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  for (const Sample& s : trace) {
    ASSERT_TRUE(s.record.integrators_ok && s.record.contact_valid && s.record.coupling_valid);
  }
  EXPECT_LE(largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }), voxel);
  // Released, both come to rest.
  EXPECT_LT(beam.energy(), 0.01 * beam_energy);
  EXPECT_LT(tool.energy(), 0.01 * std::max(tool_energy, 1e-12) + 1e-12);
  std::printf(
      "tool on beam: beam energy %.3e J, tool energy %.3e J while pressed; %.3e and "
      "%.3e J at the end\n",
      beam_energy, tool_energy, beam.energy(), tool.energy());
}

/// A clock for DegradationOptions::clock that runs like the steady clock, but loses
/// `stall_per_reading` seconds at every reading while that is set: to the contact query, the
/// machine suddenly became that much slower (a preempted thread, a slow machine).
struct StallingClock {
  static inline double lost = 0.0;
  static inline double stall_per_reading = 0.0;
  static double now() noexcept {
    lost += stall_per_reading;
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
               .count() +
           lost;
  }
};

// Graceful degradation never lets an object through (issue 19 item 3). The beam, held at its
// centre as the pointshell object, is pressed flat onto a 4 mm plate (two voxels) 3 cm past
// contact, far beyond the coupling's saturation, under a 20 ms budget: every level fits, even in
// a sanitizer build on a loaded machine (the floor holds a level while it fits at the machine's
// typical speed, so the budget must). Then, while the beam rests on the plate, the clock stalls
// 25 ms at every reading (at least 25 ms per query, past the budget) for 20 cycles: the query
// measures a machine a thousand times slower. The levels the contact was rendered at are kept
// (the contact floor), so in every one of five runs, in every cycle, the deepest level never
// drops while in contact, penetration stays ≤ 1 voxel and the contact force never points into
// the plate. Without the floor the level drops in the first stalled cycle.
TEST_P(HardCases, AContactOnAThinPlateIsNeverHandedToACoarserLevelWhenTheClockStalls) {
  constexpr double half_thickness = voxel;  // the plate: |z| ≤ 2 mm
  const contact::DistanceGrid plate = sampled_field(
      [](const Eigen::Vector3d& p) { return std::abs(p.z()) - half_thickness; },
      voxel_grid(Eigen::Vector3d(-0.05, -0.05, -0.03), Eigen::Vector3d(0.25, 0.07, 0.05)));
  const Eigen::Vector3d grasp_in_body(beam_length / 2, beam_side / 2, beam_side / 2);
  const Eigen::Vector3d above(beam_length / 2, beam_side / 2,
                              half_thickness + 0.01 + beam_side / 2);
  const TargetFunction target = keyframe_target({{0.0, at(above)},
                                                 {0.3, at(above - Eigen::Vector3d(0, 0, 0.04))},
                                                 {0.8, at(above - Eigen::Vector3d(0, 0, 0.04))}});
  constexpr int stall_begin = 400, stall_end = 420;

  for (int repeat = 0; repeat < 5; ++repeat) {
    DeformableBeam b;
    contact::ContactOptions budgeted = options(contact::HapticObject::pointshell);
    budgeted.degradation.mode = contact::DegradationOptions::Mode::time_budget;
    budgeted.degradation.budget_microseconds = 20000.0;
    budgeted.degradation.clock = &StallingClock::now;
    const PairScene scene(b.tree, plate, budgeted, grasp_in_body, Eigen::Isometry3d::Identity(),
                          b.integrator.get());
    const auto penetration = [&](const Pose& grasp) {
      const Eigen::Isometry3d body = held_body_pose(grasp, grasp_in_body);
      double deepest = 0.0;
      for (Eigen::Index s = 0; s < b.tree.tree().num_points(); ++s) {
        const Eigen::Vector3d p = body * b.tree.position(s, b.integrator->coordinates());
        deepest = std::max(deepest, -plate.distance(p));
      }
      return deepest;
    };
    Harness harness(target, scene, coupling_options(beam_length), penetration);
    for (int i = 0; i < 800; ++i) {
      StallingClock::stall_per_reading = i >= stall_begin && i < stall_end ? 2.5e-2 : 0.0;
      harness.step();
    }
    StallingClock::stall_per_reading = 0.0;
    const std::vector<Sample>& trace = harness.trace();
    ASSERT_EQ(first_non_finite(trace), trace.size());
    double strongest = 0.0, deepest = 0.0, slowest_stalled = 0.0;
    for (std::size_t i = 0; i < trace.size(); ++i) {
      const contact::ContactStatistics& stats = trace[i].record.contact.statistics;
      ASSERT_TRUE(trace[i].record.integrators_ok && trace[i].record.contact_valid);
      ASSERT_GE(trace[i].record.contact.force.z(), -1e-9)
          << "run " << repeat << ": the force points into the plate, cycle " << i;
      ASSERT_LE(trace[i].penetration, voxel) << "run " << repeat << ": sank in, cycle " << i;
      if (i > 0 && trace[i - 1].record.contact.statistics.points_in_contact > 0) {
        ASSERT_GE(stats.deepest_level, trace[i - 1].record.contact.statistics.deepest_level)
            << "run " << repeat << ": a contact was handed to a coarser level, cycle " << i;
      }
      strongest = std::max(strongest, trace[i].record.contact.force.norm());
      deepest = std::max(deepest, trace[i].penetration);
      if (static_cast<int>(i) >= stall_begin && static_cast<int>(i) < stall_end) {
        slowest_stalled = std::max(slowest_stalled, stats.microseconds);
      }
    }
    EXPECT_GT(strongest, 0.5 * saturation_force) << "the beam reached the plate";
    EXPECT_GT(trace[stall_begin].record.contact.statistics.points_in_contact, 0)
        << "the stall came in contact";
    EXPECT_GT(slowest_stalled, 20000.0) << "the query measured the stall, beyond the budget";
    std::printf("run %d: contact up to %.2f N, deepest %.3f mm, stalled queries up to %.0f us\n",
                repeat, strongest, 1e3 * deepest, slowest_stalled);
  }
}

}  // namespace
}  // namespace khz::haptic::hard_cases
