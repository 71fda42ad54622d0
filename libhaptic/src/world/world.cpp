#include <khz/contact/query/contact_query.hpp>
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
/// field; 0 for analytic fields, which have none.
double voxel_size(const Body& body) noexcept {
  if (const auto* grid = std::get_if<const contact::DistanceGrid*>(&body.field)) {
    return (*grid)->geometry().spacing;
  }
  if (auto* const* state = std::get_if<contact::DeformedFieldState*>(&body.field)) {
    const contact::DeformedDistanceField& field = (*state)->field();
    double finest = field.field(0).geometry().spacing;
    for (Eigen::Index domain = 1; domain < field.num_domains(); ++domain) {
      finest = std::min(finest, field.field(domain).geometry().spacing);
    }
    return finest;
  }
  return 0.0;
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
  };
  struct PairState {
    std::unique_ptr<contact::ContactWorkspace> workspace;
    double voxel = 0.0;  // the field's grid spacing (m), 0 for an analytic field
    std::optional<contact::FrictionOptions> friction;  // set_pair_friction()'s, if given
  };

  std::vector<Body> bodies;
  std::vector<HandState> hands;
  std::vector<CycleRecord> records;
  std::vector<WorldPair> pairs;
  std::vector<PairState> pair_states;
  std::vector<Eigen::VectorXd> reduced_forces;  // per body, Σ over its pairs (r, or empty)
  contact::ContactOptions contact_options;      // the last given, before per-pair roles

  std::string body_name(int index) const {
    const std::string& name = bodies[static_cast<std::size_t>(index)].name;
    return name.empty() ? "body " + std::to_string(index) : "body '" + name + "'";
  }

  bool query(int index) noexcept;

  /// `options` with the haptic object of pair `index` (the role of its hand's body) and the
  /// pair's own friction, if it has one.
  contact::ContactOptions pair_options(
      const contact::ContactOptions& options, const WorldPair& pair,
      const std::optional<contact::FrictionOptions>& friction = std::nullopt) const {
    contact::ContactOptions result = options;
    if (friction) result.friction = *friction;
    result.haptic_object = hands[static_cast<std::size_t>(pair.hand)].hand.body == pair.pointshell
                               ? contact::HapticObject::pointshell
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
  frames.grasp_point = hands[static_cast<std::size_t>(pair.hand)].grasp_point;
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
  }

  // Hands: one body each, with a device.
  std::vector<int> holder(static_cast<std::size_t>(body_count), -1);
  for (std::size_t h = 0; h < hands.size(); ++h) {
    const Hand& hand = hands[h];
    const std::string which = "World: hand " + std::to_string(h);
    if (hand.body < 0 || hand.body >= body_count) {
      throw Error(which + " holds body " + std::to_string(hand.body) + ", but there are " +
                  std::to_string(body_count) + " bodies");
    }
    if (holder[static_cast<std::size_t>(hand.body)] >= 0) {
      throw Error(which + " holds " + d.body_name(hand.body) + ", which hand " +
                  std::to_string(holder[static_cast<std::size_t>(hand.body)]) + " holds already");
    }
    if (hand.device == nullptr) throw Error(which + " has no device");
    if (!hand.grasp_in_body.allFinite()) throw Error(which + "'s grasp point is not finite");
    const Body& body = d.bodies[static_cast<std::size_t>(hand.body)];
    if (!has_pointshell(body) && !has_field(body)) {
      throw Error(which + " holds " + d.body_name(hand.body) +
                  ", which has neither a pointshell nor a distance field to touch with");
    }
    holder[static_cast<std::size_t>(hand.body)] = static_cast<int>(h);
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
                                      CycleMetrics(hand.metrics)});
  }
  d.records.resize(d.hands.size());

  // Pairs: every body pair with a holder, in one geometric assignment (pointshell of one against
  // the field of the other), queried once per hand holding one of the two.
  for (int a = 0; a < body_count; ++a) {
    for (int b = a + 1; b < body_count; ++b) {
      const int holder_a = holder[static_cast<std::size_t>(a)];
      const int holder_b = holder[static_cast<std::size_t>(b)];
      if (holder_a < 0 && holder_b < 0) continue;
      if (filter && !filter(a, b)) continue;
      const Body& body_a = d.bodies[static_cast<std::size_t>(a)];
      const Body& body_b = d.bodies[static_cast<std::size_t>(b)];
      // The first holder's body touches with its preferred role where it can.
      const int first = holder_a >= 0 ? a : b;
      const int other = first == a ? b : a;
      const Body& held = first == a ? body_a : body_b;
      const Body& against = first == a ? body_b : body_a;
      const bool held_as_pointshell = has_pointshell(held) && has_field(against);
      const bool held_as_field = has_field(held) && has_pointshell(against);
      if (!held_as_pointshell && !held_as_field) continue;
      const std::optional<contact::HapticObject>& role =
          d.hands[static_cast<std::size_t>(holder[static_cast<std::size_t>(first)])].hand.role;
      const bool prefer_pointshell =
          role.value_or(options.haptic_object) == contact::HapticObject::pointshell;
      const bool pointshell_first = held_as_pointshell && (prefer_pointshell || !held_as_field);
      const int pointshell = pointshell_first ? first : other;
      const int field = pointshell_first ? other : first;
      bool applies = true;
      for (const int holder_index :
           {holder[static_cast<std::size_t>(first)], holder[static_cast<std::size_t>(other)]}) {
        if (holder_index < 0) continue;
        const WorldPair pair{pointshell, field, holder_index, applies};
        d.pair_states.push_back({make_workspace(d.bodies[static_cast<std::size_t>(pointshell)],
                                                d.bodies[static_cast<std::size_t>(field)],
                                                d.pair_options(options, pair)),
                                 voxel_size(d.bodies[static_cast<std::size_t>(field)]),
                                 std::nullopt});
        d.pairs.push_back(pair);
        applies = false;
      }
    }
  }
  if (d.pairs.empty()) {
    throw Error(
        "World: no held body can touch another body (a contact needs one body's "
        "pointshell and the other's distance field, and a hand holding one of them)");
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
  // 1–2. Read every device; place every held body at its simulation pose.
  for (std::size_t h = 0; h < hand_count; ++h) {
    Data::HandState& hand = d.hands[h];
    CycleRecord& r = d.records[h];
    r = CycleRecord{};  // a cycle reports its own contact, never the last one's
    r.time = now;
    r.device_valid = hand.hand.device->read(hand.device_state);
    r.manipulandum = hand.device_state.pose;
    place_held_body(h, hand.coupling.simulation_pose());
  }
  // 3. Every pair; each hand's wrench and each body's reduced force summed over its pairs.
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
  // 5. Each reduced body, once, under its summed reduced force.
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
  // 6. Each device gets its rendered wrench (zero unless its whole chain succeeded).
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

void World::place_held_body(std::size_t hand, const Pose& grasp) noexcept {
  Data::HandState& held = m_data->hands[hand];
  held.grasp_point = grasp.position;
  m_data->bodies[static_cast<std::size_t>(held.hand.body)].pose =
      held_body_pose(grasp, held.hand.grasp_in_body);
}

bool World::query_pairs() noexcept {
  Data& d = *m_data;
  for (Data::HandState& hand : d.hands) {
    hand.wrench = contact::ContactWrench{};
    hand.contact_ok = true;
    hand.penetration_voxels = 0.0;
  }
  for (Eigen::VectorXd& force : d.reduced_forces) force.setZero();
  bool all_ok = true;
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    const WorldPair& pair = d.pairs[p];
    Data::HandState& hand = d.hands[static_cast<std::size_t>(pair.hand)];
    if (!d.query(static_cast<int>(p))) {
      hand.contact_ok = false;
      all_ok = false;
      continue;
    }
    const contact::ContactResult& result = d.pair_states[p].workspace->result();
    hand.wrench.accumulate(result);
    if (d.pair_states[p].voxel > 0.0) {
      hand.penetration_voxels = std::max(
          hand.penetration_voxels, result.statistics.deepest_penetration / d.pair_states[p].voxel);
    }
    if (!pair.applies_reduced_forces) continue;
    Eigen::VectorXd& on_pointshell = d.reduced_forces[static_cast<std::size_t>(pair.pointshell)];
    if (on_pointshell.size() > 0) on_pointshell += result.pointshell_reduced_force;
    Eigen::VectorXd& on_field = d.reduced_forces[static_cast<std::size_t>(pair.field)];
    if (on_field.size() > 0) on_field += result.field_reduced_force;
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

void World::reset_contact() noexcept {
  for (Data::PairState& pair : m_data->pair_states) pair.workspace->reset();
}

void World::set_contact_options(const contact::ContactOptions& options) {
  Data& d = *m_data;
  options.validate();
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    d.pair_states[p].workspace->set_options(
        d.pair_options(options, d.pairs[p], d.pair_states[p].friction));
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
  bool found = false;
  for (std::size_t p = 0; p < d.pairs.size(); ++p) {
    const WorldPair& pair = d.pairs[p];
    if (!((pair.pointshell == body_a && pair.field == body_b) ||
          (pair.pointshell == body_b && pair.field == body_a))) {
      continue;
    }
    d.pair_states[p].friction = friction;
    d.pair_states[p].workspace->set_options(d.pair_options(d.contact_options, pair, friction));
    found = true;
  }
  if (!found) {
    throw Error("World::set_pair_friction: " + d.body_name(body_a) + " and " + d.body_name(body_b) +
                " never touch (no hand holds either, or their roles do not meet)");
  }
}

const contact::FrictionOptions& World::pair_friction(int index) const noexcept {
  return m_data->pair_states[static_cast<std::size_t>(index)].workspace->options().friction;
}

contact::FrictionState World::friction_state(int index, Eigen::Index point) const noexcept {
  return m_data->pair_states[static_cast<std::size_t>(index)].workspace->friction_state(point);
}

}  // namespace khz::haptic
