#pragma once
// Shared fixtures of the hard-case stability tests (test_haptic_hard_cases.cpp): pointshells of
// simple solids, analytic environments sampled onto distance grids, the contact and coupling
// settings every case shares (thesis §3.5, §4.6–§4.9), and a harness that runs a one-pair World
// in simulated time and records every cycle.

#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/test/sphere_points.hpp>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace khz::haptic::hard_cases {

// ---------------------------------------------------------------------------------------------
// Settings every case shares.

/// k_C (N/m) per point in contact, and L of §3.5: at full contact the contact is L k_C = 20 kN/m,
/// forty times the coupling, so the coupling, not the contact, decides what the device feels.
constexpr double point_stiffness = 2000.0;
constexpr double scaling_count = 10.0;
/// The voxel h (m): the spacing of the grids the environments are sampled on (a 2 mm grid is
/// what a 10–20 cm scene gets at 64–128 cells, §3.11), the unit of allowed penetration.
constexpr double voxel = 2e-3;
/// F_VC,max of §4.9: the force one point produces at half a voxel of penetration, k_C h / 2. A
/// saturated coupling cannot push a single point deeper than h/2 at rest (more points only admit
/// shallower penetrations), which leaves the other half voxel for transients.
constexpr double saturation_force = point_stiffness * voxel / 2.0;
/// k_VC (N/m): below the simulated device's 3500 N/m (§4.7).
constexpr double coupling_stiffness = 500.0;

/// How the contact of a run of the hard cases rubs: every case runs frictionless, the thesis's
/// contact, and with Coulomb friction (issue 20). A gtest parameter (TestWithParam).
struct Rubbing {
  const char* name;                   ///< The test name's suffix.
  contact::FrictionOptions friction;  ///< Off (μ_s = 0), or on for every contact.
};

/// gtest prints a Rubbing by its name.
inline void PrintTo(const Rubbing& rubbing, std::ostream* out) { *out << rubbing.name; }

/// The two runs of each hard case: frictionless, and μ_s = 0.5, μ_k = 0.4 with the default stick
/// distance, δ = μ_s h from the field's voxel (1 mm on the cases' 2 mm grids). (With 0.1 mm the
/// ball turned in its tight socket is thrown out of it and never settles, the passivity observer
/// falling below zero.)
inline std::vector<Rubbing> rubbings() {
  contact::FrictionOptions rough;
  rough.static_coefficient = 0.5;
  rough.kinetic_coefficient = 0.4;
  return {{"Frictionless", {}}, {"WithFriction", rough}};
}

/// `friction` against an analytic shape, which has no voxel for the default stick distance to
/// come from: δ = μ_s h given, what the default chooses on the cases' grids.
inline contact::FrictionOptions on_analytic_field(contact::FrictionOptions friction) {
  if (friction.stick_distance == 0.0) friction.stick_distance = friction.static_coefficient * voxel;
  return friction;
}

/// Names a run of a test parameterized by Rubbing (INSTANTIATE_TEST_SUITE_P's name generator).
struct RubbingName {
  template <typename ParamInfo>
  std::string operator()(const ParamInfo& run) const {
    return run.param.name;
  }
};

/// The contact options of every case: k_C, L, the held object and the friction as given.
inline contact::ContactOptions contact_options(contact::HapticObject held,
                                               const contact::FrictionOptions& friction = {}) {
  contact::ContactOptions options;
  options.stiffness = point_stiffness;
  options.scaling_count = scaling_count;
  options.haptic_object = held;
  options.friction = friction;
  return options;
}

/// The fixture of the cases run once per Rubbing (TEST_P): the cases' contact options with this
/// run's friction.
class RubbingCases : public ::testing::TestWithParam<Rubbing> {
 protected:
  bool frictionless() const { return !GetParam().friction.enabled(); }
  /// contact_options() with this run's friction.
  contact::ContactOptions options(contact::HapticObject held) const {
    return contact_options(held, GetParam().friction);
  }
  /// The same against an analytic field (on_analytic_field()).
  contact::ContactOptions analytic_options(contact::HapticObject held) const {
    return contact_options(held, on_analytic_field(GetParam().friction));
  }
};

/// The coupling options of every case: k_VC, saturation to F_VC,max with the torque plateau
/// F_VC,max × object_radius (§4.9), the thesis's α = 0.5 and speed limits (§4.6, §4.8), the
/// device's limits; §4.10's metres per radian default to the object's size.
inline CouplingOptions coupling_options(double object_radius) {
  CouplingOptions options;
  options.stiffness = coupling_stiffness;
  options.saturation_force = saturation_force;
  options.object_radius = object_radius;
  const DeviceCapabilities device = SimulatedOperatorOptions::phantom_premium_like();
  options.max_rendered_force = device.max_force;
  options.max_rendered_torque = device.max_torque;
  options.device_max_stiffness = device.max_stiffness;
  return options;
}

// ---------------------------------------------------------------------------------------------
// Poses and geometry.

inline Pose at(const Eigen::Vector3d& position,
               const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity()) {
  return {position, orientation};
}

inline Eigen::Quaterniond turned(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

/// A flat pointshell cut into nested levels of 4× growth from `first_level` points (§3.9.1).
inline contact::PointTree nested_tree(const contact::Pointshell& flat, Eigen::Index first_level) {
  contact::NestedLevelOptions options;
  options.schedule = contact::LevelSchedule::quadrupling(first_level);
  return contact::PointTree(contact::nested_pointshell(flat, options));
}

/// `count` near-uniform points on a sphere of `radius` about the origin (golden spiral), inward
/// normals, one level.
inline contact::Pointshell sphere_pointshell(double radius, Eigen::Index count) {
  contact::Pointshell shell;
  shell.normals = -test::fibonacci_sphere_points(count);
  shell.points = -radius * shell.normals;
  shell.level_ends = {count};
  return shell;
}

/// Points on the six faces of the box centre ± half_extents at the centres of a grid of about
/// `spacing` on each face (no point on an edge, so every normal is its face's), inward normals,
/// one level.
inline contact::Pointshell box_pointshell(const Eigen::Vector3d& center,
                                          const Eigen::Vector3d& half_extents, double spacing) {
  std::vector<Eigen::Vector3d> points, normals;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = std::max(1, static_cast<int>(std::lround(2.0 * half_extents[u] / spacing)));
    const int nv = std::max(1, static_cast<int>(std::lround(2.0 * half_extents[v] / spacing)));
    for (const double side : {-1.0, 1.0}) {
      for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
          Eigen::Vector3d p = center;
          p[axis] += side * half_extents[axis];
          p[u] += half_extents[u] * (2.0 * (i + 0.5) / nu - 1.0);
          p[v] += half_extents[v] * (2.0 * (j + 0.5) / nv - 1.0);
          points.push_back(p);
          normals.push_back(-side * Eigen::Vector3d::Unit(axis));
        }
      }
    }
  }
  contact::Pointshell shell;
  const auto count = static_cast<Eigen::Index>(points.size());
  shell.points.resize(count, 3);
  shell.normals.resize(count, 3);
  for (Eigen::Index i = 0; i < count; ++i) {
    shell.points.row(i) = points[static_cast<std::size_t>(i)].transpose();
    shell.normals.row(i) = normals[static_cast<std::size_t>(i)].transpose();
  }
  shell.level_ends = {count};
  return shell;
}

/// Any signed distance d(p) (a callable, or anything with distance(p)) sampled at the nodes of
/// `geometry`: the distance grid the query then interpolates, with voxel geometry.spacing.
template <typename Distance>
contact::DistanceGrid sampled_field(const Distance& distance,
                                    const contact::GridGeometry& geometry) {
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (int k = 0; k <= geometry.cells; ++k) {
    for (int j = 0; j <= geometry.cells; ++j) {
      for (int i = 0; i <= geometry.cells; ++i) {
        const Eigen::Vector3d p = geometry.node_position(i, j, k);
        double d;
        if constexpr (requires { distance.distance(p); }) {
          d = distance.distance(p);
        } else {
          d = distance(p);
        }
        values[static_cast<std::size_t>(geometry.node_index(i, j, k))] = static_cast<float>(d);
      }
    }
  }
  return contact::DistanceGrid(geometry, std::move(values), true);
}

/// The grid of spacing `voxel` covering at least [low, high] (a cube, as GridGeometry is).
inline contact::GridGeometry voxel_grid(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  contact::GridGeometry geometry;
  geometry.spacing = voxel;
  geometry.cells = static_cast<int>(std::ceil((high - low).maxCoeff() / voxel));
  geometry.origin = low;
  return geometry;
}

/// How deep the deepest point of `points` (body frame, #P×3) lies inside `field` with the body at
/// `body` (m, ≥ 0): the penetration the contact sees, since it sees exactly these points.
template <typename Field>
double deepest_penetration(const contact::PointMatrix& points, const Field& field,
                           const Eigen::Isometry3d& body) {
  double deepest = 0.0;
  for (Eigen::Index s = 0; s < points.rows(); ++s) {
    const Eigen::Vector3d p = body * Eigen::Vector3d(points.row(s).transpose());
    deepest = std::max(deepest, -field.distance(p));
  }
  return deepest;
}

// ---------------------------------------------------------------------------------------------
// The closed loop in simulated time.

/// Everything finite that a cycle reports.
inline bool finite(const CycleRecord& r) {
  return r.manipulandum.position.allFinite() && r.manipulandum.orientation.coeffs().allFinite() &&
         r.simulation.position.allFinite() && r.simulation.orientation.coeffs().allFinite() &&
         r.contact.force.allFinite() && r.contact.torque.allFinite() &&
         r.rendered.force.allFinite() && r.rendered.torque.allFinite();
}

/// One cycle's record and what the harness measured after it.
struct Sample {
  CycleRecord record;
  double device_energy = 0.0;  ///< SimulatedOperator::kinetic_energy() (J).
  double penetration = 0.0;    ///< The Harness's penetration measure at the simulation pose (m).
  Pose device;                 ///< The device's true pose (also while its reads fail).
};

/// The two bodies of a one-pair World: a pointshell body (a PointTree, or a DeformablePointTree
/// with its integrator) and a distance-field body (any of Body's field kinds; a
/// DeformedFieldState with its integrator). The one ContactOptions::haptic_object names is held
/// (body 0, placed by the Harness), the other fixed at `fixed_pose` (body 1).
struct PairScene {
  template <typename Tree, typename Field>
  PairScene(const Tree& tree, Field& field, const contact::ContactOptions& options,
            const Eigen::Vector3d& grasp, const Eigen::Isometry3d& fixed_pose,
            reduced::ReducedIntegrator* integrator = nullptr,
            reduced::ReducedIntegrator* field_integrator = nullptr)
      : contact(options), grasp_in_body(grasp) {
    Body pointshell_body;
    pointshell_body.name = "pointshell";
    pointshell_body.pointshell = &tree;
    pointshell_body.integrator = integrator;
    Body field_body;
    field_body.name = "field";
    field_body.field = &field;
    field_body.integrator = field_integrator;
    if (options.haptic_object == contact::HapticObject::pointshell) {
      field_body.pose = fixed_pose;
      bodies = {pointshell_body, field_body};
    } else {
      pointshell_body.pose = fixed_pose;
      bodies = {field_body, pointshell_body};
    }
  }

  std::vector<Body> bodies;
  contact::ContactOptions contact;
  Eigen::Vector3d grasp_in_body;
};

/// A hand holding body 0 of a World at `grasp_in_body` through `device`.
inline Hand holding_body_0(SafeDevice& device, const CouplingOptions& coupling,
                           const Eigen::Vector3d& grasp_in_body = Eigen::Vector3d::Zero()) {
  Hand hand;
  hand.body = 0;
  hand.grasp_in_body = grasp_in_body;
  hand.device = &device;
  hand.coupling = coupling;
  return hand;
}

/// A simulated hand on a simulated device, its safety layer, and a World of `scene`'s two bodies
/// whose one hand holds body 0, its coupling starting at the target's first pose, run at 1 kHz in
/// simulated time. Every cycle's record is kept in trace().
class Harness {
 public:
  /// @param penetration how deep the held object is at a simulation pose (m); may be empty.
  Harness(TargetFunction target, const PairScene& scene, const CouplingOptions& coupling,
          std::function<double(const Pose&)> penetration = {}, const SafetyOptions& safety = {},
          const SimulatedOperatorOptions& hand = {})
      : m_device(target, hand),
        m_safe(m_device, safety),
        m_world(held_at(scene.bodies, held_body_pose(target(0.0), scene.grasp_in_body)),
                {holding_body_0(m_safe, coupling, scene.grasp_in_body)}, scene.contact),
        m_penetration(std::move(penetration)) {
    m_safe.open();
  }

  /// Runs `count` cycles.
  void run(int count) {
    for (int i = 0; i < count; ++i) step();
  }
  /// Makes the next cycle stall for `periods` periods before it ends: it ends late (a deadline
  /// miss for the safety layer), the device holds its output through the stall
  /// (SimulatedOperator::inject_stall()), and every later cycle starts that much later.
  void stall(int periods) { m_pending_stall = periods; }
  /// Runs one cycle and returns its sample.
  const Sample& step() {
    const double now = static_cast<double>(m_trace.size() + m_stalled_periods) * period;
    const double late = static_cast<double>(m_pending_stall) * period;
    Sample sample;
    sample.record = m_world.cycle(now, now + period, [&] { return now + 0.1 * period + late; })[0];
    m_device.inject_stall(m_pending_stall);
    m_stalled_periods += m_pending_stall;
    m_pending_stall = 0;
    sample.device_energy = m_device.kinetic_energy();
    sample.device = m_device.pose();
    if (m_penetration) sample.penetration = m_penetration(sample.record.simulation);
    m_trace.push_back(sample);
    return m_trace.back();
  }

  const std::vector<Sample>& trace() const { return m_trace; }
  SimulatedOperator& device() { return m_device; }
  VirtualCoupling& coupling() { return m_world.coupling(0); }
  SafeDevice& safe() { return m_safe; }
  World& world() { return m_world; }

  static constexpr double period = 1e-3;  ///< s, the simulated device's 1 kHz

 private:
  static std::vector<Body> held_at(std::vector<Body> bodies, const Eigen::Isometry3d& pose) {
    bodies[0].pose = pose;
    return bodies;
  }

  SimulatedOperator m_device;
  SafeDevice m_safe;
  World m_world;
  std::function<double(const Pose&)> m_penetration;
  std::vector<Sample> m_trace;
  int m_pending_stall = 0;    // periods the next cycle stalls
  int m_stalled_periods = 0;  // periods lost to stalls so far
};

/// The first cycle of a trace with anything non-finite, or trace.size().
inline std::size_t first_non_finite(const std::vector<Sample>& trace) {
  for (std::size_t i = 0; i < trace.size(); ++i) {
    if (!finite(trace[i].record) || !std::isfinite(trace[i].device_energy) ||
        !std::isfinite(trace[i].penetration)) {
      return i;
    }
  }
  return trace.size();
}

/// The largest of f(sample) over cycles [begin, end).
template <typename F>
double largest(const std::vector<Sample>& trace, std::size_t begin, std::size_t end, F&& f) {
  double result = -std::numeric_limits<double>::infinity();
  for (std::size_t i = begin; i < std::min(end, trace.size()); ++i) {
    result = std::max(result, static_cast<double>(f(trace[i])));
  }
  return result;
}

/// The rendered stiffness of §4.7 at a manipulandum pose, measured as the theorem defines it:
/// the coupling (a copy, so the run is not disturbed) is stepped against fresh queries of the
/// world's one hand (World::probe(), which steps nothing) at a fixed manipulandum until the
/// simulation object is at rest (static virtual coupling's quasi-static equilibrium, what
/// continuous time control would render), the manipulandum is moved by `delta` along
/// `direction` and the equilibrium found again: ‖Δ rendered force‖ / delta (N/m).
inline double quasi_static_stiffness(VirtualCoupling coupling, World& world,
                                     const Pose& manipulandum, const Eigen::Vector3d& direction,
                                     double delta, int iterations = 400) {
  const auto settle = [&](const Pose& m) {
    Eigen::Vector3d rendered = Eigen::Vector3d::Constant(std::nan(""));
    for (int i = 0; i < iterations; ++i) {
      const Pose grasp = coupling.simulation_pose();
      if (!world.probe(std::span(&grasp, 1))) break;
      rendered = coupling.step(m, world.wrench(0)).rendered.force;
    }
    return rendered;
  };
  const Eigen::Vector3d before = settle(manipulandum);
  Pose moved = manipulandum;
  moved.position += delta * direction.normalized();
  const Eigen::Vector3d after = settle(moved);
  return (after - before).norm() / delta;
}

}  // namespace khz::haptic::hard_cases
