#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/query/detail/cross_matrix.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/world/world.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

namespace khz::haptic {

namespace {

bool has_pointshell(const Body& body) noexcept {
  return !std::holds_alternative<std::monostate>(body.pointshell);
}
bool has_field(const Body& body) noexcept {
  return !std::holds_alternative<std::monostate>(body.field);
}

/// r of a body's deformable tree and of its deformed field (0 where rigid or absent).
Eigen::Index pointshell_dimension(const Body& body) noexcept {
  const auto* tree = std::get_if<const contact::DeformablePointTree*>(&body.pointshell);
  return tree != nullptr ? (*tree)->dimension() : 0;
}
Eigen::Index field_dimension(const Body& body) noexcept {
  auto* const* state = std::get_if<contact::DeformedFieldState*>(&body.field);
  return state != nullptr ? (*state)->dimension() : 0;
}

/// The grid spacing penetration is counted in (m): a grid's, the finest domain's of a deformed
/// field (contact::CellSizedDistanceField); 0 for analytic fields, which have none.
double voxel_size(const Body& body) noexcept {
  return std::visit(
      [](const auto& field) noexcept -> double {
        if constexpr (requires { field->cell_size(); }) {
          return field->cell_size();
        } else {
          return 0.0;
        }
      },
      body.field);
}

}  // namespace

struct World::Data {
  struct HandState {
    Hand hand;
    VirtualCoupling coupling;
    DeviceState device_state;
    Eigen::Vector3d grasp_point = Eigen::Vector3d::Zero();  // where the body was placed (world)
    contact::ContactWrench wrench;                          // Σ over the hand's pairs
    bool contact_ok = true;
    Wrench rendered;                  // zero unless the hand's whole chain succeeds
    double penetration_voxels = 0.0;  // deepest over the hand's pairs with a grid
    CycleMetrics metrics;
    std::uint32_t buttons = 0;  // the device's buttons at the last read
    Pose previous_grasp;        // the grasp frame at the start of the last cycle
    // How the grasp frame moved over the last cycle (m/s, rad/s, world).
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  };
  struct DynamicState {
    FreeBodyMotion motion;
    contact::ContactWrench wrench;  // Σ over its queries, about its centre of mass
    // Σ over its queries of s K, each pair's 6×6 stiffness scaled by s = 1 + β / h where the
    // pair is damped (DynamicsOptions::contact_damping), and of K u_o over the undamped pairs
    // with a free body that is awake, u_o its motion seen as a motion of this one
    // (add_to_step()): the step's matrix M − h² Σ s K and its right side h (f + h Σ s K u −
    // h Σ K u_o) are backward Euler, linearized, for the contact springs and their damping β K,
    // on the motion relative to what the body touches.
    Eigen::Matrix<double, 6, 6> stepped_stiffness = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> carried = Eigen::Matrix<double, 6, 1>::Zero();
    double gyration_radius = 0.0;  // √(trace I / m), m: turning speed as a point speed
    double still_time = 0.0;       // s below DynamicsOptions::sleep_speed
    bool asleep = false;
    // Woken by a query this cycle: some of its pairs may have been passed over while it slept,
    // so it waits for the next cycle, which queries them all, before it moves.
    bool woken = false;
    int hand = -1;                                              // the hand that grasped it, or −1
    Eigen::Isometry3d in_hand = Eigen::Isometry3d::Identity();  // held body ← it, while grasped
  };
  struct PairState {
    std::unique_ptr<contact::ContactWorkspace> workspace;
    double voxel = 0.0;  // the field's grid spacing (m), 0 for an analytic field
    std::optional<contact::FrictionOptions> friction;  // set_pair_friction()'s, if given
    int group = 0;             // the geometric pair: both queries of a pair share it
    bool had_contact = false;  // points in contact at its last query
  };

  std::vector<Body> bodies;
  std::vector<HandState> hands;
  std::vector<CycleRecord> records;
  std::vector<WorldPair> pairs;
  std::vector<PairState> pair_states;
  std::vector<Eigen::VectorXd> reduced_forces;  // per body, Σ over its pairs (r, or empty)
  contact::ContactOptions contact_options;      // the last given, before per-pair roles
  std::vector<int> holder;                      // per body: the hand holding it, or −1
  std::vector<int> dynamic_index;               // per body: its index in `dynamics`, or −1
  std::vector<DynamicState> dynamics;
  DynamicsOptions dynamics_options;
  std::vector<char> group_applied;  // per geometric pair: its reduced forces added this cycle

  DynamicState* dynamic(int body) noexcept {
    const int index = dynamic_index[static_cast<std::size_t>(body)];
    return index < 0 ? nullptr : &dynamics[static_cast<std::size_t>(index)];
  }
  /// The hand whose wrench a query moving `body` feeds: its holder or the hand that grasped it;
  /// −1 for a free dynamic body (or a fixed one).
  int hand_of(int body) const noexcept {
    const int holding = holder[static_cast<std::size_t>(body)];
    if (holding >= 0) return holding;
    const int index = dynamic_index[static_cast<std::size_t>(body)];
    return index < 0 ? -1 : dynamics[static_cast<std::size_t>(index)].hand;
  }
  /// The velocity (m/s) at world point `point` and the angular velocity (rad/s) of `body` now:
  /// its hand's grasp frame's over the last cycle while held or grasped, a free dynamic body's
  /// own, zero for a fixed or sleeping body.
  Eigen::Matrix<double, 6, 1> velocity_at(int body, const Eigen::Vector3d& point) const noexcept {
    Eigen::Matrix<double, 6, 1> u = Eigen::Matrix<double, 6, 1>::Zero();
    const int hand = hand_of(body);
    if (hand >= 0) {
      const HandState& holding = hands[static_cast<std::size_t>(hand)];
      u << holding.velocity + holding.angular_velocity.cross(point - holding.grasp_point),
          holding.angular_velocity;
      return u;
    }
    const int index = dynamic_index[static_cast<std::size_t>(body)];
    if (index < 0) return u;
    const FreeBodyMotion& motion = dynamics[static_cast<std::size_t>(index)].motion;
    const Eigen::Vector3d omega = motion.angular_velocity();
    u << motion.velocity() + omega.cross(point - motion.centre()), omega;
    return u;
  }
  /// Whether `body` moves this cycle: held, grasped, or dynamic and awake.
  bool moving(int body) const noexcept {
    if (hand_of(body) >= 0) return true;
    const int index = dynamic_index[static_cast<std::size_t>(body)];
    return index >= 0 && !dynamics[static_cast<std::size_t>(index)].asleep;
  }
  /// Whether pair query `index` runs this cycle: its body moves, and the pair is not inside one
  /// hand's grasp.
  bool runs(const WorldPair& pair) const noexcept {
    const int other = pair.body == pair.pointshell ? pair.field : pair.pointshell;
    const int hand = hand_of(pair.body);
    if (hand >= 0 && hand_of(other) == hand) return false;
    return moving(pair.body);
  }

  std::string body_name(int index) const {
    const std::string& name = bodies[static_cast<std::size_t>(index)].name;
    return name.empty() ? "body " + std::to_string(index) : "body '" + name + "'";
  }

  bool query(int index) noexcept;
  void add_to_step(DynamicState& body, int other, const contact::ContactResult& result) noexcept;

  /// `options` with the haptic object of pair `index` (the role of its hand's body) and the
  /// pair's own friction, if it has one.
  /// @throws Error if that friction leaves the stick distance to the field's voxel and the
  ///         pair's field has none (the query would refuse every cycle).
  contact::ContactOptions pair_options(
      const contact::ContactOptions& options, const WorldPair& pair,
      const std::optional<contact::FrictionOptions>& friction = std::nullopt) const {
    contact::ContactOptions result = options;
    if (friction) result.friction = *friction;
    const Body& field = bodies[static_cast<std::size_t>(pair.field)];
    if (result.friction.enabled() && result.friction.stick_distance_for(voxel_size(field)) <= 0.0) {
      throw Error("World: friction between " + body_name(pair.pointshell) + " and " +
                  body_name(pair.field) + " needs a stick_distance: the field of " +
                  body_name(pair.field) +
                  " is an analytic shape, with no voxel h to choose the default μ_s h from");
    }
    result.haptic_object = pair.body == pair.pointshell ? contact::HapticObject::pointshell
                                                        : contact::HapticObject::distance_field;
    return result;
  }
};

bool World::Data::query(int index) noexcept {
  const WorldPair& pair = pairs[static_cast<std::size_t>(index)];
  const Body& pointshell = bodies[static_cast<std::size_t>(pair.pointshell)];
  const Body& field = bodies[static_cast<std::size_t>(pair.field)];
  contact::ContactFrames frames;
  frames.pointshell = pointshell.pose;
  frames.field = field.pose;
  const int hand = hand_of(pair.body);
  frames.grasp_point =
      hand >= 0
          ? hands[static_cast<std::size_t>(hand)].grasp_point
          : dynamics[static_cast<std::size_t>(dynamic_index[static_cast<std::size_t>(pair.body)])]
                .motion.centre();
  contact::ContactWorkspace& workspace = *pair_states[static_cast<std::size_t>(index)].workspace;
  // One variant dispatch per pair and cycle; the query itself is compiled per field type.
  const auto with_field = [&](const auto& run) {
    return std::visit(
        [&](const auto& alternative) noexcept {
          if constexpr (std::is_same_v<std::decay_t<decltype(alternative)>, std::monostate>) {
            return false;  // not reached: pairs are made of bodies with their roles
          } else {
            return run(*alternative);
          }
        },
        field.field);
  };
  if (const auto* tree = std::get_if<const contact::DeformablePointTree*>(&pointshell.pointshell)) {
    return with_field([&](const auto& f) {
      return contact::query_contact(**tree, pointshell.integrator->coordinates(), f, frames,
                                    workspace);
    });
  }
  const contact::PointTree& tree = *std::get<const contact::PointTree*>(pointshell.pointshell);
  return with_field(
      [&](const auto& f) { return contact::query_contact(tree, f, frames, workspace); });
}

namespace {

/// The ContactWorkspace of a pair, sized for its pointshell and its field's r.
std::unique_ptr<contact::ContactWorkspace> make_workspace(const Body& pointshell, const Body& field,
                                                          const contact::ContactOptions& options) {
  const Eigen::Index r_field = field_dimension(field);
  if (const auto* tree = std::get_if<const contact::DeformablePointTree*>(&pointshell.pointshell)) {
    return std::make_unique<contact::ContactWorkspace>(**tree, options, r_field);
  }
  return std::make_unique<contact::ContactWorkspace>(
      *std::get<const contact::PointTree*>(pointshell.pointshell), options, r_field);
}

}  // namespace

World::World(std::vector<Body> bodies, std::vector<Hand> hands,
             const contact::ContactOptions& options, PairFilter filter)
    : m_data(std::make_unique<Data>()) {
  Data& d = *m_data;
  d.bodies = std::move(bodies);
  const int body_count = static_cast<int>(d.bodies.size());
  options.validate();
  d.contact_options = options;

  // Bodies: a reduced body's integrator matches its tree's and field's r.
  for (int i = 0; i < body_count; ++i) {
    const Body& body = d.bodies[static_cast<std::size_t>(i)];
    const Eigen::Index r_tree = pointshell_dimension(body), r_field = field_dimension(body);
    if (r_tree > 0 && r_field > 0 && r_tree != r_field) {
      throw Error("World: " + d.body_name(i) +
                  " has a deformable pointshell with r = " + std::to_string(r_tree) +
                  " but a deformed field with r = " + std::to_string(r_field));
    }
    const Eigen::Index r = std::max(r_tree, r_field);
    if (r > 0 && (body.integrator == nullptr || body.integrator->dimension() != r)) {
      throw Error("World: " + d.body_name(i) +
                  " is reduced and needs an integrator with r = " + std::to_string(r) +
                  (body.integrator == nullptr
                       ? std::string(" (none given)")
                       : " (it has r = " + std::to_string(body.integrator->dimension()) + ")"));
    }
    if (r == 0 && body.integrator != nullptr) {
      throw Error("World: " + d.body_name(i) +
                  " has an integrator but neither a deformable pointshell nor a deformed field");
    }
    d.reduced_forces.push_back(Eigen::VectorXd::Zero(r));
    d.dynamic_index.push_back(-1);
    if (!body.dynamics) continue;
    if (r > 0) {
      throw Error("World: " + d.body_name(i) +
                  " is dynamic and reduced; dynamic bodies are rigid (no integrator, deformable "
                  "pointshell or deformed field)");
    }
    const BodyDynamics& dynamics = *body.dynamics;
    try {
      d.dynamics.push_back(Data::DynamicState{
          FreeBodyMotion(dynamics.inertia, body.pose, dynamics.velocity, dynamics.angular_velocity),
          {},
          Eigen::Matrix<double, 6, 6>::Zero(),
          Eigen::Matrix<double, 6, 1>::Zero(),
          std::sqrt(dynamics.inertia.inertia.trace() / dynamics.inertia.mass)});
    } catch (const Error& error) {
      throw Error("World: " + d.body_name(i) + ": " + error.what());
    }
    d.dynamic_index.back() = static_cast<int>(d.dynamics.size()) - 1;
  }

  // Hands: one body each, with a device.
  d.holder.assign(static_cast<std::size_t>(body_count), -1);
  for (std::size_t h = 0; h < hands.size(); ++h) {
    const Hand& hand = hands[h];
    const std::string which = "World: hand " + std::to_string(h);
    if (hand.body < 0 || hand.body >= body_count) {
      throw Error(which + " holds body " + std::to_string(hand.body) + ", but there are " +
                  std::to_string(body_count) + " bodies");
    }
    const int holding = d.holder[static_cast<std::size_t>(hand.body)];
    if (holding >= 0) {
      throw Error(which + " holds " + d.body_name(hand.body) + ", which hand " +
                  std::to_string(holding) + " holds already");
    }
    if (hand.device == nullptr) throw Error(which + " has no device");
    if (!hand.grasp_in_body.allFinite()) throw Error(which + "'s grasp point is not finite");
    if (hand.grasp_button < -1 || hand.grasp_button > 31 ||
        (hand.grasp_button >= 0 && hand.grasp_button == hand.device->options().index_button)) {
      throw Error(which + "'s grasp button " + std::to_string(hand.grasp_button) +
                  " must be -1 or a bit index in [0, 31] other than its index button");
    }
    const Body& body = d.bodies[static_cast<std::size_t>(hand.body)];
    if (!has_pointshell(body) && !has_field(body)) {
      throw Error(which + " holds " + d.body_name(hand.body) +
                  ", which has neither a pointshell nor a distance field to touch with");
    }
    if (body.dynamics) {
      throw Error(which + " holds " + d.body_name(hand.body) +
                  ", which is dynamic: a hand holds a body of its own and grasps dynamic ones "
                  "(Hand::grasp_button, World::grasp())");
    }
    d.holder[static_cast<std::size_t>(hand.body)] = static_cast<int>(h);
    // The coupling starts with the simulation object at the body's pose.
    Pose start;
    start.orientation = Eigen::Quaterniond(body.pose.linear());
    start.position = body.pose * hand.grasp_in_body;
    d.hands.push_back(Data::HandState{hand,
                                      VirtualCoupling(hand.coupling, start),
                                      {},
                                      start.position,
                                      {},
                                      true,
                                      {},
                                      0.0,
                                      CycleMetrics(hand.metrics),
                                      0,
                                      start});
  }
  d.records.resize(d.hands.size());

  // Pairs: every body pair with a moving body (held or dynamic), in one geometric assignment
  // (pointshell of one against the field of the other), queried once for each moving body.
  const auto moves = [&](int body) {
    return d.holder[static_cast<std::size_t>(body)] >= 0 ||
           d.bodies[static_cast<std::size_t>(body)].dynamics.has_value();
  };
  int groups = 0;
  for (int a = 0; a < body_count; ++a) {
    for (int b = a + 1; b < body_count; ++b) {
      if (!moves(a) && !moves(b)) continue;
      if (filter && !filter(a, b)) continue;
      // The first moving body touches with its preferred role where it can.
      const int first = moves(a) ? a : b;
      const int other = first == a ? b : a;
      const Body& mover = d.bodies[static_cast<std::size_t>(first)];
      const Body& against = d.bodies[static_cast<std::size_t>(other)];
      const bool mover_as_pointshell = has_pointshell(mover) && has_field(against);
      const bool mover_as_field = has_field(mover) && has_pointshell(against);
      if (!mover_as_pointshell && !mover_as_field) continue;
      const int holding = d.holder[static_cast<std::size_t>(first)];
      const std::optional<contact::HapticObject> role =
          holding >= 0 ? d.hands[static_cast<std::size_t>(holding)].hand.role : std::nullopt;
      const bool prefer_pointshell =
          role.value_or(options.haptic_object) == contact::HapticObject::pointshell;
      const bool pointshell_first = mover_as_pointshell && (prefer_pointshell || !mover_as_field);
      const int pointshell = pointshell_first ? first : other;
      const int field = pointshell_first ? other : first;
      bool applies = true;
      for (const int moving : {first, other}) {
        if (!moves(moving)) continue;
        const WorldPair pair{pointshell, field, moving, applies};
        d.pair_states.push_back({make_workspace(d.bodies[static_cast<std::size_t>(pointshell)],
                                                d.bodies[static_cast<std::size_t>(field)],
                                                d.pair_options(options, pair)),
                                 voxel_size(d.bodies[static_cast<std::size_t>(field)]),
                                 std::nullopt, groups});
        d.pairs.push_back(pair);
        applies = false;
      }
      ++groups;
    }
  }
  d.group_applied.assign(static_cast<std::size_t>(groups), 0);
  if (d.pairs.empty()) {
    throw Error(
        "World: no moving body can touch another body (a contact needs one body's pointshell "
        "and the other's distance field, and one of the two held by a hand or dynamic)");
  }
}

World::~World() = default;

void World::begin_cycle(double deadline) noexcept {
  for (Data::HandState& hand : m_data->hands) hand.hand.device->begin_cycle(deadline);
}

void World::end_cycle(double now) noexcept {
  for (Data::HandState& hand : m_data->hands) hand.hand.device->end_cycle(now);
}

void World::step(double now) noexcept {
  Data& d = *m_data;
  const std::size_t hand_count = d.hands.size();
  // 1–2. Read every device (and its grasp button); place every held body at its simulation pose
  // and the bodies it grasped with it.
  for (std::size_t h = 0; h < hand_count; ++h) {
    Data::HandState& hand = d.hands[h];
    CycleRecord& r = d.records[h];
    r = CycleRecord{};  // a cycle reports its own contact, never the last one's
    r.time = now;
    r.device_valid = hand.hand.device->read(hand.device_state);
    r.manipulandum = hand.device_state.pose;
    const Pose& simulation = hand.coupling.simulation_pose();
    hand.velocity =
        (simulation.position - hand.previous_grasp.position) / d.dynamics_options.time_step;
    hand.angular_velocity =
        rotation_vector(simulation.orientation * hand.previous_grasp.orientation.conjugate()) /
        d.dynamics_options.time_step;
    hand.previous_grasp = simulation;
    if (r.device_valid && hand.hand.grasp_button >= 0) {
      const std::uint32_t bit = 1u << hand.hand.grasp_button;
      const std::uint32_t pressed = hand.device_state.buttons & bit;
      if (pressed != 0 && (hand.buttons & bit) == 0) grasp(static_cast<int>(h));
      if (pressed == 0 && (hand.buttons & bit) != 0) release(static_cast<int>(h));
      hand.buttons = hand.device_state.buttons;
    }
    place_held_body(h, simulation);
  }
  // 3. Every pair; each hand's and dynamic body's wrench and each body's reduced force summed
  // over its pairs.
  query_pairs();
  // 4. Each hand's coupling.
  for (std::size_t h = 0; h < hand_count; ++h) {
    Data::HandState& hand = d.hands[h];
    CycleRecord& r = d.records[h];
    r.contact_valid = hand.contact_ok;
    r.contact = hand.wrench;
    r.penetration_voxels = hand.penetration_voxels;
    hand.rendered = Wrench{};
    if (!r.device_valid || !r.contact_valid) continue;
    const CouplingStep step = hand.coupling.step(hand.device_state.pose, hand.wrench);
    r.coupling_valid = step.valid;
    r.degenerate_dimension = step.degenerate_dimension;
    r.coupling_saturated = step.coupling_saturated;
    if (!step.valid) continue;
    hand.rendered = step.rendered;
    r.residual = step.residual;
  }
  // 5. Each free dynamic body that is awake.
  step_dynamic_bodies();
  // 6. Each reduced body, once, under its summed reduced force.
  bool integrators_ok = true;
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    Body& body = d.bodies[i];
    if (body.integrator == nullptr) continue;
    integrators_ok =
        body.integrator->step(d.reduced_forces[i]).status != reduced::ReducedStepStatus::failed &&
        integrators_ok;
    if (auto* const* state = std::get_if<contact::DeformedFieldState*>(&body.field)) {
      integrators_ok = (*state)->update(body.integrator->coordinates()) && integrators_ok;
    }
  }
  // 7. Each device gets its rendered wrench (zero unless its whole chain succeeded).
  for (std::size_t h = 0; h < hand_count; ++h) {
    Data::HandState& hand = d.hands[h];
    CycleRecord& r = d.records[h];
    r.integrators_ok = integrators_ok;
    r.simulation = hand.coupling.simulation_pose();
    // The contact wrench on the held body is what the coupling renders once it has stretched:
    // the wait for a small force (after the start or a device fault) waits for it too.
    Wrench pending;
    pending.force = hand.wrench.force;
    pending.torque = hand.wrench.torque;
    hand.hand.device->write(hand.rendered, pending);
    r.rendered = hand.hand.device->last_output();
    r.observed_energy = hand.metrics.record(r, hand.hand.device->mapping());
  }
}

void World::step_dynamic_bodies() noexcept {
  Data& d = *m_data;
  const DynamicsOptions& options = d.dynamics_options;
  for (Data::DynamicState& body : d.dynamics) {
    const bool woken = std::exchange(body.woken, false);
    if (body.hand >= 0 || body.asleep || woken) continue;
    const contact::ContactWrench& w = body.wrench;
    const Eigen::Vector3d force = w.force - options.time_step * body.carried.head<3>();
    const Eigen::Vector3d torque = w.torque - options.time_step * body.carried.tail<3>();
    const Eigen::Matrix<double, 6, 6>& stiffness = body.stepped_stiffness;
    // A step that fails (a non-finite wrench) leaves the body where it was, at rest.
    if (!body.motion.step(options.time_step, force, torque, stiffness, options.gravity)) {
      body.motion.set_state(body.motion.pose(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    }
    const double speed = std::max(body.motion.velocity().norm(),
                                  body.motion.angular_velocity().norm() * body.gyration_radius);
    body.still_time = speed < options.sleep_speed ? body.still_time + options.time_step : 0.0;
    if (options.sleep_speed > 0.0 && body.still_time >= options.sleep_time) {
      body.asleep = true;
      body.motion.set_state(body.motion.pose(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    }
  }
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    if (const Data::DynamicState* body = d.dynamic(static_cast<int>(i))) {
      if (body->hand < 0) d.bodies[i].pose = body->motion.pose();
    }
  }
}

void World::place_held_body(std::size_t hand, const Pose& grasp) noexcept {
  Data& d = *m_data;
  Data::HandState& held = d.hands[hand];
  held.grasp_point = grasp.position;
  Eigen::Isometry3d& pose = d.bodies[static_cast<std::size_t>(held.hand.body)].pose;
  pose = held_body_pose(grasp, held.hand.grasp_in_body);
  // Its grasped bodies ride along, their motion moving as the hand's grasp frame does.
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    Data::DynamicState* body = d.dynamic(static_cast<int>(i));
    if (body == nullptr || body->hand != static_cast<int>(hand)) continue;
    d.bodies[i].pose = pose * body->in_hand;
    const Eigen::Matrix<double, 6, 1> u =
        d.velocity_at(static_cast<int>(i), d.bodies[i].pose * body->motion.inertia().centre);
    body->motion.set_state(d.bodies[i].pose, u.head<3>(), u.tail<3>());
  }
}

/// Adds a free dynamic body's query against body `other` to what its step solves with
/// (DynamicState::stepped_stiffness, carried):
/// - against a fixed or sleeping body, the contact is damped (β K, DynamicsOptions::
///   contact_damping): s = 1 + β / h;
/// - against a free dynamic body that is awake, the other's motion is taken as given (u_o; the
///   two steps are solved apart, which keeps their momentum to about 1 % over a collision at
///   1 kHz), undamped: damping would add as much again to that error;
/// - against a held or grasped body, its motion is not taken into account and the contact is
///   undamped: the coupling's simulation pose moves too roughly from cycle to cycle to be
///   differentiated into a velocity that stiffness or damping may multiply.
void World::Data::add_to_step(DynamicState& body, int other,
                              const contact::ContactResult& result) noexcept {
  Eigen::Matrix<double, 6, 6> stiffness;
  stiffness << result.force_by_translation, result.force_by_rotation, result.torque_by_translation,
      result.torque_by_rotation;
  const DynamicState* touched = dynamic(other);
  if (hand_of(other) >= 0) {
    body.stepped_stiffness += stiffness;
  } else if (touched != nullptr && !touched->asleep) {
    body.stepped_stiffness += stiffness;
    body.carried += stiffness * velocity_at(other, body.motion.centre());
  } else {
    body.stepped_stiffness +=
        (1.0 + dynamics_options.contact_damping / dynamics_options.time_step) * stiffness;
  }
}

bool World::query_pairs() noexcept {
  Data& d = *m_data;
  for (Data::HandState& hand : d.hands) {
    hand.wrench = contact::ContactWrench{};
    hand.contact_ok = true;
    hand.penetration_voxels = 0.0;
  }
  for (Data::DynamicState& body : d.dynamics) {
    body.wrench = contact::ContactWrench{};
    body.stepped_stiffness.setZero();
    body.carried.setZero();
  }
  for (Eigen::VectorXd& force : d.reduced_forces) force.setZero();
  std::fill(d.group_applied.begin(), d.group_applied.end(), 0);
  bool all_ok = true;
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    const WorldPair& pair = d.pairs[p];
    Data::PairState& state = d.pair_states[p];
    if (!d.runs(pair)) continue;
    const int hand_index = d.hand_of(pair.body);
    Data::HandState* hand =
        hand_index >= 0 ? &d.hands[static_cast<std::size_t>(hand_index)] : nullptr;
    Data::DynamicState* dynamic = hand == nullptr ? d.dynamic(pair.body) : nullptr;
    if (!d.query(static_cast<int>(p))) {
      if (hand != nullptr) hand->contact_ok = false;
      all_ok = false;
      continue;
    }
    const contact::ContactResult& result = state.workspace->result();
    // A sleeping body wakes when a moving one touches it or stops touching it.
    const bool contact = result.statistics.points_in_contact > 0;
    const int other = pair.body == pair.pointshell ? pair.field : pair.pointshell;
    if (Data::DynamicState* touched = d.dynamic(other);
        touched != nullptr && touched->asleep && (contact || state.had_contact)) {
      touched->asleep = false;
      touched->woken = true;
      touched->still_time = 0.0;
    }
    state.had_contact = contact;
    if (hand != nullptr) {
      hand->wrench.accumulate(result);
      if (state.voxel > 0.0) {
        hand->penetration_voxels =
            std::max(hand->penetration_voxels, result.statistics.deepest_penetration / state.voxel);
      }
    } else if (dynamic != nullptr) {
      dynamic->wrench.accumulate(result);
      d.add_to_step(*dynamic, other, result);
    }
    char& applied = d.group_applied[static_cast<std::size_t>(state.group)];
    if (applied != 0) continue;
    applied = 1;
    Eigen::VectorXd& on_pointshell = d.reduced_forces[static_cast<std::size_t>(pair.pointshell)];
    if (on_pointshell.size() > 0) on_pointshell += result.pointshell_reduced_force;
    Eigen::VectorXd& on_field = d.reduced_forces[static_cast<std::size_t>(pair.field)];
    if (on_field.size() > 0) on_field += result.field_reduced_force;
  }
  // The weight of each grasped body, on its hand about the grasp point: T = r × m g, and turning
  // the hand by Δω turns r, so ∂T/∂ω = [m g]× [r]×.
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    const Data::DynamicState* body = d.dynamic(static_cast<int>(i));
    if (body == nullptr || body->hand < 0) continue;
    Data::HandState& hand = d.hands[static_cast<std::size_t>(body->hand)];
    const Eigen::Vector3d weight = body->motion.inertia().mass * d.dynamics_options.gravity;
    const Eigen::Vector3d arm = d.bodies[i].pose * body->motion.inertia().centre - hand.grasp_point;
    hand.wrench.force += weight;
    hand.wrench.torque += arm.cross(weight);
    hand.wrench.torque_by_rotation +=
        contact::detail::cross_matrix(weight) * contact::detail::cross_matrix(arm);
  }
  return all_ok;
}
bool World::probe(std::span<const Pose> grasps) noexcept {
  if (grasps.size() != m_data->hands.size()) return false;
  for (std::size_t h = 0; h < grasps.size(); ++h) place_held_body(h, grasps[h]);
  return query_pairs();
}

std::span<const CycleRecord> World::records() const noexcept { return m_data->records; }
std::span<const Body> World::bodies() const noexcept { return m_data->bodies; }
int World::hand_count() const noexcept { return static_cast<int>(m_data->hands.size()); }
const Hand& World::hand(int index) const noexcept {
  return m_data->hands[static_cast<std::size_t>(index)].hand;
}
VirtualCoupling& World::coupling(int index) noexcept {
  return m_data->hands[static_cast<std::size_t>(index)].coupling;
}
const VirtualCoupling& World::coupling(int index) const noexcept {
  return m_data->hands[static_cast<std::size_t>(index)].coupling;
}
std::span<const WorldPair> World::pairs() const noexcept { return m_data->pairs; }
const contact::ContactResult& World::pair_result(int index) const noexcept {
  return m_data->pair_states[static_cast<std::size_t>(index)].workspace->result();
}
const Eigen::VectorXd& World::reduced_force(int index) const noexcept {
  return m_data->reduced_forces[static_cast<std::size_t>(index)];
}
const contact::ContactWrench& World::wrench(int index) const noexcept {
  return m_data->hands[static_cast<std::size_t>(index)].wrench;
}
CycleMetricsSummary World::metrics(int index) const noexcept {
  return m_data->hands[static_cast<std::size_t>(index)].metrics.summary();
}
void World::reset_metrics() noexcept {
  for (Data::HandState& hand : m_data->hands) hand.metrics.clear();
}

void World::set_dynamics(const DynamicsOptions& options) {
  options.validate();
  m_data->dynamics_options = options;
}
const DynamicsOptions& World::dynamics() const noexcept { return m_data->dynamics_options; }
const FreeBodyMotion* World::motion(int index) const noexcept {
  if (index < 0 || index >= static_cast<int>(m_data->bodies.size())) return nullptr;
  const Data::DynamicState* body = m_data->dynamic(index);
  return body == nullptr ? nullptr : &body->motion;
}
bool World::asleep(int index) const noexcept {
  const FreeBodyMotion* body = motion(index);
  return body != nullptr && m_data->dynamic(index)->asleep;
}
const contact::ContactWrench& World::body_wrench(int index) const noexcept {
  static const contact::ContactWrench none;
  return motion(index) == nullptr ? none : m_data->dynamic(index)->wrench;
}
int World::hand_of(int index) const noexcept {
  if (index < 0 || index >= static_cast<int>(m_data->bodies.size())) return -1;
  return m_data->hand_of(index);
}

int World::grasp(int hand) noexcept {
  Data& d = *m_data;
  if (hand < 0 || hand >= static_cast<int>(d.hands.size())) return -1;
  const int held = d.hands[static_cast<std::size_t>(hand)].hand.body;
  int chosen = -1;
  double hardest = 0.0;
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    const WorldPair& pair = d.pairs[p];
    if (pair.body != held) continue;
    const int other = pair.field == held ? pair.pointshell : pair.field;
    const Data::DynamicState* body = d.dynamic(other);
    if (body == nullptr || body->hand >= 0 || !d.pair_states[p].had_contact) continue;
    const double force = d.pair_states[p].workspace->result().force.norm();
    if (chosen < 0 || force > hardest) {
      chosen = other;
      hardest = force;
    }
  }
  if (chosen < 0) return -1;
  Data::DynamicState& body = *d.dynamic(chosen);
  body.hand = hand;
  body.asleep = false;
  body.still_time = 0.0;
  body.in_hand = d.bodies[static_cast<std::size_t>(held)].pose.inverse(Eigen::Isometry) *
                 d.bodies[static_cast<std::size_t>(chosen)].pose;
  return chosen;
}

int World::release(int hand) noexcept {
  Data& d = *m_data;
  if (hand < 0 || hand >= static_cast<int>(d.hands.size())) return 0;
  int released = 0;
  for (std::size_t i = 0; i < d.bodies.size(); ++i) {
    Data::DynamicState* body = d.dynamic(static_cast<int>(i));
    if (body == nullptr || body->hand != hand) continue;
    // It leaves moving as the hand's body moved over the last cycle.
    const Eigen::Matrix<double, 6, 1> u =
        d.velocity_at(static_cast<int>(i), d.bodies[i].pose * body->motion.inertia().centre);
    body->motion.set_state(d.bodies[i].pose, u.head<3>(), u.tail<3>());
    body->hand = -1;
    body->asleep = false;
    body->still_time = 0.0;
    ++released;
  }
  return released;
}

bool World::place_free_body(int index, const Eigen::Isometry3d& pose) noexcept {
  Data& d = *m_data;
  if (index < 0 || index >= static_cast<int>(d.bodies.size())) return false;
  Data::DynamicState* body = d.dynamic(index);
  if (body == nullptr || body->hand >= 0 ||
      !body->motion.set_state(pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())) {
    return false;
  }
  d.bodies[static_cast<std::size_t>(index)].pose = pose;
  body->asleep = false;
  body->still_time = 0.0;
  return true;
}

void World::reset_contact() noexcept {
  for (Data::PairState& pair : m_data->pair_states) pair.workspace->reset();
}

void World::set_contact_options(const contact::ContactOptions& options) {
  Data& d = *m_data;
  options.validate();
  std::vector<contact::ContactOptions> per_pair;  // all checked before any pair changes
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    per_pair.push_back(d.pair_options(options, d.pairs[p], d.pair_states[p].friction));
  }
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    d.pair_states[p].workspace->set_options(per_pair[p]);
  }
  d.contact_options = options;
}

const contact::ContactOptions& World::contact_options() const noexcept {
  return m_data->contact_options;
}

void World::set_pair_friction(int body_a, int body_b, const contact::FrictionOptions& friction) {
  Data& d = *m_data;
  const int body_count = static_cast<int>(d.bodies.size());
  if (body_a < 0 || body_a >= body_count || body_b < 0 || body_b >= body_count) {
    throw Error("World::set_pair_friction: bodies " + std::to_string(body_a) + " and " +
                std::to_string(body_b) + " (there are " + std::to_string(body_count) + ")");
  }
  if (body_a == body_b) {
    throw Error("World::set_pair_friction: " + d.body_name(body_a) + " given twice");
  }
  contact::ContactOptions checked = d.contact_options;
  checked.friction = friction;
  checked.validate();
  std::vector<std::pair<std::size_t, contact::ContactOptions>> joined;  // all checked first
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    const WorldPair& pair = d.pairs[p];
    if ((pair.pointshell == body_a && pair.field == body_b) ||
        (pair.pointshell == body_b && pair.field == body_a)) {
      joined.emplace_back(p, d.pair_options(d.contact_options, pair, friction));
    }
  }
  for (const auto& [p, options] : joined) {
    d.pair_states[p].friction = friction;
    d.pair_states[p].workspace->set_options(options);
  }
  if (joined.empty()) {
    throw Error("World::set_pair_friction: " + d.body_name(body_a) + " and " + d.body_name(body_b) +
                " never touch (neither is held or dynamic, or their roles do not meet)");
  }
}

const contact::FrictionOptions& World::pair_friction(int index) const noexcept {
  return m_data->pair_states[static_cast<std::size_t>(index)].workspace->options().friction;
}

contact::FrictionState World::friction_state(int index, Eigen::Index point) const noexcept {
  return m_data->pair_states[static_cast<std::size_t>(index)].workspace->friction_state(point);
}

}  // namespace khz::haptic
