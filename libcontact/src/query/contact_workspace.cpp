#include <khz/contact/query/contact_workspace.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace khz::contact {
namespace {

/// Queries with fewer cost units than this do not update the typical cost per unit: fixed
/// costs would dominate it.
constexpr double min_measured_units = 64.0;
/// The typical cost per unit (the contact floor's) moves towards the measured one by at most
/// this factor per query, up or down.
constexpr double typical_cost_step = 1.0 + 1.0 / 32.0;

Eigen::Index widest_level(const PointTree& tree) {
  Eigen::Index widest = 0;
  for (int level = 0; level < tree.num_levels(); ++level) {
    widest = std::max(widest, tree.level_end(level) - tree.level_begin(level));
  }
  return widest;
}

Eigen::Vector3d bounding_box_centre(const PointMatrix& points) {
  if (points.rows() == 0) return Eigen::Vector3d::Zero();
  return 0.5 * (points.colwise().minCoeff() + points.colwise().maxCoeff()).transpose();
}

}  // namespace

ContactWorkspace::ContactWorkspace(const PointTree& tree, const ContactOptions& options,
                                   Eigen::Index field_dimension)
    : ContactWorkspace(tree, options, 0, field_dimension) {}

ContactWorkspace::ContactWorkspace(const DeformablePointTree& tree, const ContactOptions& options,
                                   Eigen::Index field_dimension)
    : ContactWorkspace(tree.tree(), options, tree.dimension(), field_dimension) {
  m_modes_norm = tree.displacement_bound();
}

ContactWorkspace::ContactWorkspace(const PointTree& tree, const ContactOptions& options,
                                   Eigen::Index pointshell_dimension, Eigen::Index field_dimension)
    : m_options(options),
      m_tree_identity(&tree),
      m_nodes(tree.num_nodes()),
      m_points(tree.num_points()),
      m_pointshell_dimension(pointshell_dimension),
      m_field_dimension(field_dimension) {
  options.validate();
  if (field_dimension < 0) {
    throw Error("ContactWorkspace: field_dimension must be ≥ 0, got " +
                std::to_string(field_dimension));
  }
  const auto widest = static_cast<std::size_t>(widest_level(tree));
  m_point_distance.assign(static_cast<std::size_t>(m_points), 0.0);
  m_current.assign(widest, 0);
  m_next.assign(widest, 0);
  m_skip_until.assign(static_cast<std::size_t>(m_nodes), 0);
  m_level_rendered.assign(static_cast<std::size_t>(tree.num_levels()), 0);
  m_abs_q = Eigen::VectorXd::Zero(pointshell_dimension);
  m_previous_q = Eigen::VectorXd::Zero(pointshell_dimension);
  m_previous_field_q = Eigen::VectorXd::Zero(field_dimension);
  m_contact_reduced_force = Eigen::VectorXd::Zero(pointshell_dimension);
  m_kept_contact_reduced_force = Eigen::VectorXd::Zero(pointshell_dimension);
  m_kept_field_reduced_force = Eigen::VectorXd::Zero(field_dimension);
  m_result.pointshell_reduced_force = Eigen::VectorXd::Zero(pointshell_dimension);
  m_result.field_reduced_force = Eigen::VectorXd::Zero(field_dimension);
  m_previous_rotation.setIdentity();
  m_previous_reference.setZero();
  const PointMatrix& points = tree.pointshell().points;
  m_reference_point = bounding_box_centre(points);
  if (points.rows() > 0) {
    m_rest_reach = (points.rowwise() - m_reference_point.transpose()).rowwise().norm().maxCoeff();
  }
  size_friction();
  reset();
}

void ContactWorkspace::set_options(const ContactOptions& options) {
  options.validate();
  m_options = options;
  size_friction();
  reset();
}

void ContactWorkspace::size_friction() {
  if (!m_options.friction.enabled()) {
    m_anchors = {};
    return;
  }
  m_anchors.resize(static_cast<std::size_t>(m_points));
}

FrictionState ContactWorkspace::friction_state(Eigen::Index point) const noexcept {
  if (point < 0 || static_cast<std::size_t>(point) >= m_anchors.size()) return FrictionState::none;
  const detail::FrictionAnchor& anchor = m_anchors[static_cast<std::size_t>(point)];
  return anchor.query != 0 && anchor.query == m_friction_query ? anchor.state : FrictionState::none;
}

void ContactWorkspace::begin_friction() noexcept {
  // Near the count's end, start over: every anchor is dropped once in 2³² queries (50 days at
  // 1 kHz).
  if (m_friction_query == std::numeric_limits<std::uint32_t>::max()) {
    std::fill(m_anchors.begin(), m_anchors.end(), detail::FrictionAnchor{});
    std::fill(m_level_rendered.begin(), m_level_rendered.end(), 0U);
    m_friction_query = 0;
  }
  ++m_friction_query;
}

void ContactWorkspace::set_area_weights(std::vector<double> weights) {
  if (!weights.empty()) {
    if (static_cast<Eigen::Index>(weights.size()) != m_points) {
      throw Error("ContactWorkspace::set_area_weights: " + std::to_string(weights.size()) +
                  " weights for " + std::to_string(m_points) + " points");
    }
    for (std::size_t s = 0; s < weights.size(); ++s) {
      if (!(std::isfinite(weights[s]) && weights[s] > 0.0)) {
        throw Error("ContactWorkspace::set_area_weights: the weight of point " + std::to_string(s) +
                    " must be finite and > 0, got " + std::to_string(weights[s]));
      }
    }
  }
  m_area_weights = std::move(weights);
}

void ContactWorkspace::reset() noexcept {
  std::fill(m_skip_until.begin(), m_skip_until.end(), 0U);
  m_cycle = 0;
  m_have_previous = false;
  m_warm_level = -1;
  m_contact_floor = -1;
  m_typical_seconds_per_unit = 0.0;
  std::fill(m_anchors.begin(), m_anchors.end(), detail::FrictionAnchor{});
  std::fill(m_level_rendered.begin(), m_level_rendered.end(), 0U);
  m_friction_query = 0;
  m_last_normal_load = 0.0;
}

bool ContactWorkspace::begin_coherence(const Eigen::Matrix3d& rotation,
                                       const Eigen::Vector3d& translation, const double* q,
                                       const double* field_q, double field_bound) noexcept {
  const CoherenceOptions& bounds = m_options.coherence;
  const auto max_skip = static_cast<std::uint32_t>(bounds.max_skip);
  // Skips are at most max_skip + 1 queries ahead; near the counter's end, start over.
  if (m_cycle >= std::numeric_limits<std::uint32_t>::max() - 4 * (max_skip + 1)) {
    std::fill(m_skip_until.begin(), m_skip_until.end(), 0U);
    m_cycle = 0;
  }
  ++m_cycle;
  const Eigen::Vector3d reference = rotation * m_reference_point + translation;
  bool dropped = false;
  if (m_have_previous) {
    // A point p moves by (R − R')(p − c) + (reference − reference'): the spectral norm of R − R'
    // (2 sin θ/2 for a rotation by θ, ‖R − R'‖_F / √2) bounds the first part per metre of ρ;
    // a deformation moves it by ‖U_s Δq‖ ≤ max_s ‖U_s‖_F ‖Δq‖.
    const double moved = (reference - m_previous_reference).norm();
    const double turned = (rotation - m_previous_rotation).norm() / std::sqrt(2.0);
    double deformed = 0.0;
    if (q != nullptr) {
      deformed =
          m_modes_norm *
          (Eigen::Map<const Eigen::VectorXd>(q, m_pointshell_dimension) - m_previous_q).norm();
    }
    double field_deformed = 0.0;
    if (field_q != nullptr) {
      field_deformed =
          field_bound *
          (Eigen::Map<const Eigen::VectorXd>(field_q, m_field_dimension) - m_previous_field_q)
              .norm();
    }
    if (!(moved <= bounds.max_translation && turned <= bounds.max_rotation &&
          deformed <= bounds.max_deformation && field_deformed <= bounds.max_field_deformation)) {
      // Every skip ends by m_cycle + max_skip: jumping past that drops them all in O(1).
      m_cycle += max_skip + 1;
      dropped = true;
    }
  }
  m_have_previous = true;
  m_previous_rotation = rotation;
  m_previous_reference = reference;
  // Every point is within ρ = max_s ‖P_s − c‖ + max_s ‖U_s‖·‖q‖ of the reference point c, so
  // none moves more than this per query while the bounds hold.
  double reach = m_rest_reach;
  if (q != nullptr) {
    const Eigen::Map<const Eigen::VectorXd> current(q, m_pointshell_dimension);
    m_previous_q = current;
    reach += m_modes_norm * current.norm();
  }
  if (field_q != nullptr) {
    m_previous_field_q = Eigen::Map<const Eigen::VectorXd>(field_q, m_field_dimension);
  }
  m_motion_per_query = bounds.max_translation + bounds.max_deformation +
                       bounds.max_field_deformation + bounds.max_rotation * reach;
  return dropped;
}

std::uint32_t ContactWorkspace::coherent_skip_until(double gap) const noexcept {
  double skips = m_options.coherence.max_skip;
  // k queries later the gap has shrunk by at most k·motion: skip the k with k·motion < gap.
  if (m_motion_per_query > 0.0) skips = std::min(skips, std::ceil(gap / m_motion_per_query) - 1.0);
  return m_cycle + 1 + static_cast<std::uint32_t>(std::max(skips, 0.0));
}

void ContactWorkspace::end_degradation(int deepest_level, bool in_contact, double seconds,
                                       double cost_units) noexcept {
  m_warm_level = deepest_level;
  m_contact_floor = in_contact ? deepest_level : -1;
  if (cost_units < min_measured_units) return;
  const double measured = seconds / cost_units;
  m_typical_seconds_per_unit =
      m_typical_seconds_per_unit == 0.0
          ? measured
          : std::clamp(measured, m_typical_seconds_per_unit / typical_cost_step,
                       m_typical_seconds_per_unit * typical_cost_step);
}

}  // namespace khz::contact
