#include <khz/contact/query/contact_query.hpp>
#include <khz/run/scene_contact.hpp>

#include <algorithm>
#include <string>
#include <utility>

namespace khz::run {
namespace {

bool has_tree(const ContactBody& body) noexcept {
  return !std::holds_alternative<std::monostate>(body.tree);
}
bool has_field(const ContactBody& body) noexcept {
  return !std::holds_alternative<std::monostate>(body.field);
}

/// r of the object's deformable tree or field, 0 for a rigid one.
Eigen::Index tree_dimension(const ContactBody& body) noexcept {
  const auto* tree = std::get_if<const contact::DeformablePointTree*>(&body.tree);
  return tree != nullptr ? (*tree)->dimension() : 0;
}
Eigen::Index field_dimension(const ContactBody& body) noexcept {
  auto* const* state = std::get_if<contact::DeformedFieldState*>(&body.field);
  return state != nullptr ? (*state)->dimension() : 0;
}

std::unique_ptr<contact::ContactWorkspace> make_workspace(const ContactBody& pointshell,
                                                          const ContactBody& field,
                                                          const contact::ContactOptions& options) {
  const Eigen::Index r_field = field_dimension(field);
  if (const auto* tree = std::get_if<const contact::DeformablePointTree*>(&pointshell.tree)) {
    return std::make_unique<contact::ContactWorkspace>(**tree, options, r_field);
  }
  return std::make_unique<contact::ContactWorkspace>(
      *std::get<const contact::PointTree*>(pointshell.tree), options, r_field);
}

}  // namespace

SceneContact::SceneContact(std::vector<ContactBody> bodies, int held,
                           const Eigen::Vector3d& grasp_in_body,
                           const contact::ContactOptions& options)
    : m_bodies(std::move(bodies)), m_held(held), m_grasp_in_body(grasp_in_body) {
  const int count = static_cast<int>(m_bodies.size());
  if (held < 0 || held >= count) {
    throw reduced::Error("SceneContact: held object " + std::to_string(held) + " of " +
                         std::to_string(count));
  }
  const bool held_is_pointshell = options.haptic_object == contact::HapticObject::pointshell;
  const ContactBody& held_body = m_bodies[static_cast<std::size_t>(held)];
  if (held_is_pointshell ? !has_tree(held_body) : !has_field(held_body)) {
    throw reduced::Error(std::string("SceneContact: the held object has no ") +
                         (held_is_pointshell ? "pointshell" : "distance field"));
  }
  m_reduced_forces.resize(m_bodies.size());
  for (int i = 0; i < count; ++i) {
    ContactBody& body = m_bodies[static_cast<std::size_t>(i)];
    const Eigen::Index r = std::max(tree_dimension(body), field_dimension(body));
    if (r > 0 && (body.integrator == nullptr || body.integrator->dimension() != r)) {
      throw reduced::Error("SceneContact: object " + std::to_string(i) +
                           " is deformable and needs an integrator with r = " + std::to_string(r));
    }
    m_reduced_forces[static_cast<std::size_t>(i)] = Eigen::VectorXd::Zero(r);
    if (i == held) continue;
    if (held_is_pointshell && has_field(body)) {
      m_pairs.push_back({held, i, make_workspace(held_body, body, options)});
    } else if (!held_is_pointshell && has_tree(body)) {
      m_pairs.push_back({i, held, make_workspace(body, held_body, options)});
    }
  }
  if (m_pairs.empty()) {
    throw reduced::Error(std::string("SceneContact: no other object has a ") +
                         (held_is_pointshell ? "distance field" : "pointshell") +
                         " for the held object to touch");
  }
}

SceneContact::~SceneContact() = default;

bool SceneContact::query_pair(Pair& pair, const Eigen::Vector3d& grasp_point) noexcept {
  const ContactBody& pointshell = m_bodies[static_cast<std::size_t>(pair.pointshell)];
  const ContactBody& field = m_bodies[static_cast<std::size_t>(pair.field)];
  contact::ContactFrames frames;
  frames.pointshell = pointshell.pose;
  frames.field = field.pose;
  frames.grasp_point = grasp_point;
  contact::ContactWorkspace& workspace = *pair.workspace;
  const auto with_field = [&](const auto& query) {
    if (const auto* grid = std::get_if<const contact::DistanceGrid*>(&field.field)) {
      return query(**grid);
    }
    return query(*std::get<contact::DeformedFieldState*>(field.field));
  };
  if (const auto* tree = std::get_if<const contact::DeformablePointTree*>(&pointshell.tree)) {
    return with_field([&](const auto& f) {
      return contact::query_contact(**tree, pointshell.integrator->coordinates(), f, frames,
                                    workspace);
    });
  }
  const contact::PointTree& tree = *std::get<const contact::PointTree*>(pointshell.tree);
  return with_field(
      [&](const auto& f) { return contact::query_contact(tree, f, frames, workspace); });
}

const contact::ContactResult* SceneContact::query(const haptic::Pose& grasp) noexcept {
  Eigen::Isometry3d& held = m_bodies[static_cast<std::size_t>(m_held)].pose;
  held.linear() = grasp.orientation.normalized().toRotationMatrix();
  held.translation() = grasp.position - held.linear() * m_grasp_in_body;

  contact::ContactResult& sum = m_result;
  sum = contact::ContactResult{};  // its reduced-force vectors stay empty: nothing allocates
  for (Eigen::VectorXd& force : m_reduced_forces) force.setZero();

  bool ok = true;
  for (Pair& pair : m_pairs) {
    ok = query_pair(pair, grasp.position) && ok;
    const contact::ContactResult& r = pair.workspace->result();
    sum.accumulate(r);
    Eigen::VectorXd& on_pointshell = m_reduced_forces[static_cast<std::size_t>(pair.pointshell)];
    if (on_pointshell.size() > 0) on_pointshell += r.pointshell_reduced_force;
    Eigen::VectorXd& on_field = m_reduced_forces[static_cast<std::size_t>(pair.field)];
    if (on_field.size() > 0) on_field += r.field_reduced_force;
  }
  return ok ? &m_result : nullptr;
}

bool SceneContact::advance() noexcept {
  bool ok = true;
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    ContactBody& body = m_bodies[i];
    if (body.integrator == nullptr) continue;
    ok = body.integrator->step(m_reduced_forces[i]).status != reduced::ReducedStepStatus::failed &&
         ok;
    if (auto* const* state = std::get_if<contact::DeformedFieldState*>(&body.field)) {
      ok = (*state)->update(body.integrator->coordinates()) && ok;
    }
  }
  return ok;
}

const contact::ContactResult& SceneContact::pair_result(int pair) const noexcept {
  return m_pairs[static_cast<std::size_t>(pair)].workspace->result();
}

std::pair<int, int> SceneContact::pair_objects(int pair) const noexcept {
  const Pair& p = m_pairs[static_cast<std::size_t>(pair)];
  return {p.pointshell, p.field};
}

void SceneContact::reset() noexcept {
  for (Pair& pair : m_pairs) pair.workspace->reset();
}

void SceneContact::set_options(const contact::ContactOptions& options) {
  for (Pair& pair : m_pairs) pair.workspace->set_options(options);
}

}  // namespace khz::run
