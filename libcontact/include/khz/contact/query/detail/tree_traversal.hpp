#pragma once
// The traversal behind query_contact() (thesis §3.10). Not part of the public interface: include
// <khz/contact/query/contact_query.hpp>.

#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/query/contact_frames.hpp>
#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/query/contact_workspace.hpp>
#include <khz/contact/query/detail/cross_matrix.hpp>
#include <khz/contact/query/detail/point_friction.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <span>
#include <utility>

namespace khz::contact::detail {

/// A rigid pointshell's points as the traversal reads them.
class RigidPoints {
 public:
  static constexpr bool deformable = false;
  explicit RigidPoints(const PointTree& tree) noexcept
      : m_tree(tree),
        m_positions(tree.pointshell().points.data()),
        m_normals(tree.pointshell().normals.data()) {}
  const PointTree& tree() const noexcept { return m_tree; }
  Eigen::Vector3d position(Eigen::Index s) const noexcept {
    return Eigen::Map<const Eigen::Vector3d>(m_positions + 3 * s);
  }
  double radius(Eigen::Index node) const noexcept { return m_tree.node(node).rest_radius; }
  Eigen::Vector3d normal(Eigen::Index s) const noexcept {
    return Eigen::Map<const Eigen::Vector3d>(m_normals + 3 * s);
  }
  /// Rigid points are read in memory order; the hardware prefetches them.
  void prefetch(Eigen::Index) const noexcept {}
  /// A rigid pointshell takes no reduced force.
  void add_reduced_force(Eigen::Index, const Eigen::Vector3d&, Eigen::VectorXd&) const noexcept {}

 private:
  const PointTree& m_tree;
  const double* m_positions;
  const double* m_normals;
};

/// A reduced deformable pointshell's points in configuration q (eq. 3.6, 3.8, 3.12).
class DeformablePoints {
 public:
  static constexpr bool deformable = true;
  /// `abs_q`: |q|, r entries, alive for the traversal.
  DeformablePoints(const DeformablePointTree& tree, const Eigen::Ref<const Eigen::VectorXd>& q,
                   const double* abs_q) noexcept
      : m_deformable(tree),
        m_tree(tree.tree()),
        m_q(q),
        m_abs_q(abs_q),
        m_r(tree.dimension()),
        m_internal(tree.tree().num_internal_nodes()) {}
  const PointTree& tree() const noexcept { return m_tree; }
  Eigen::Vector3d position(Eigen::Index s) const noexcept { return m_deformable.position(s, m_q); }
  double radius(Eigen::Index node) const noexcept {
    double radius = m_tree.node(node).rest_radius;
    if (node >= m_internal) return radius;
    const double* a = m_deformable.radius_coefficients(node).data();
    for (Eigen::Index j = 0; j < m_r; ++j) radius += a[j] * m_abs_q[j];
    return radius;
  }
  Eigen::Vector3d normal(Eigen::Index s) const noexcept { return m_deformable.normal(s, m_q); }
  const double* q_data() const noexcept { return m_q.data(); }
  /// Starts loading what node `node` will need: its point's U_s (3r doubles, several cache lines
  /// the traversal would otherwise wait for one after another) and its radius coefficients.
  void prefetch(Eigen::Index node) const noexcept {
    const char* modes = reinterpret_cast<const char*>(
        m_deformable.displacement_modes(m_tree.node(node).point).data());
    for (Eigen::Index byte = 0; byte < 24 * m_r; byte += 64) __builtin_prefetch(modes + byte);
    if (node < m_internal) {
      const char* a = reinterpret_cast<const char*>(m_deformable.radius_coefficients(node).data());
      for (Eigen::Index byte = 0; byte < 8 * m_r; byte += 64) __builtin_prefetch(a + byte);
    }
  }
  /// reduced += U_sᵀ f (f in the pointshell's body frame).
  void add_reduced_force(Eigen::Index s, const Eigen::Vector3d& f,
                         Eigen::VectorXd& reduced) const noexcept {
    const double* x = m_deformable.displacement_modes(s).data();
    const double* y = x + m_r;
    const double* z = y + m_r;
    double* out = reduced.data();
    for (Eigen::Index j = 0; j < m_r; ++j) out[j] += x[j] * f.x() + y[j] * f.y() + z[j] * f.z();
  }

 private:
  const DeformablePointTree& m_deformable;
  const PointTree& m_tree;
  const Eigen::Ref<const Eigen::VectorXd>& m_q;
  const double* m_abs_q;
  Eigen::Index m_r;
  Eigen::Index m_internal;
};

/// A point at depth d < 0 through the contact onset of depth δ ≥ 0 (ContactOptions::onset_depth):
/// its force is c · slope · depth along its normal, its stiffness c · slope and its share of ℓ
/// w · slope, c = w k_C. Shallower than δ: slope = −d/δ and depth = d/2 (force −c d²/(2δ));
/// deeper: slope = 1 and depth = d + δ/2. Continuous with its derivative at −δ; δ = 0 gives
/// eq. 3.1 (slope 1, depth d).
struct ContactOnset {
  double slope = 1.0;
  double depth = 0.0;
  ContactOnset(double d, double onset) noexcept {
    if (-d < onset) {
      slope = -d / onset;
      depth = 0.5 * d;
    } else {
      depth = d + 0.5 * onset;
    }
  }
};

/// Sums of the per-point contributions before the L/ℓ scaling, for the field object (§4.1–§4.2).
///
/// A point in contact at r from the grasp point (world), with depth d < 0, inward normal N
/// (world), field gradient g (world; N under ContactGradient::normal_direction) and weight w
/// pushes the field object with f = c d N, c = w k_C (through ContactOnset: d is the onset's
/// depth and c its stiffness). Moving the point by (−Δx, −Δω) about the grasp point with its
/// normal turning along (eq. 4.4: ∂p/∂x = −I, ∂p/∂ω = r̃, ∂N/∂ω = Ñ) gives
///   ∂f/∂x = −c N gᵀ                 ∂f/∂ω = c N (g × r)ᵀ + f̃
///   ∂(r×f)/∂x = −c (r × N) gᵀ       ∂(r×f)/∂ω = c (r × N)(g × r)ᵀ + (r × f)~
/// (eq. 4.5–4.9, with ã b̃ = b aᵀ − (a·b) I folding −f̃ r̃ + c d r̃ Ñ into (r × f)~), so four
/// outer products per point and the cross matrices of the totals once. When the grasp point
/// moves with the field object, every lever shortens by Δx and ∂T/∂x gains F̃. The
/// finite-difference tests in test_contact_query check each term.
///
/// The outer products are summed a chunk of points at a time, into accumulators the loop keeps
/// in registers: added one by one into memory they took a quarter of a query with thousands of
/// points in contact (scene A of bench_contact_query). Each entry is still the sum over the
/// points in order, so the result is the same.
struct ContactSums {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // Σ f
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // Σ r × f
  double weight = 0.0;                               // ℓ, weighted

  /// Inlined: called out of line, its loads of the vectors the caller has just stored element
  /// by element stalled on store forwarding (a third of its time).
  [[gnu::always_inline]] void add(const Eigen::Vector3d& r, double d, const Eigen::Vector3d& normal,
                                  const Eigen::Vector3d& gradient, double c) noexcept {
    const auto slot = static_cast<std::size_t>(m_pending);
    Eigen::Matrix<double, padded_rows, 1>& left = m_left[slot];
    left.head<3>() = c * normal;
    left.segment<3>(3) = c * r.cross(normal);
    left.tail<2>().setZero();
    m_right[slot].head<3>() = gradient;
    m_right[slot].tail<3>() = gradient.cross(r);
    force += d * left.head<3>();
    torque += d * left.segment<3>(3);
    if (++m_pending == chunk) flush();
  }

  /// The four outer-product sums as one 6×6 matrix:
  /// Σ c [N; r × N] [g; g × r]ᵀ = [Σ c N gᵀ, Σ c N (g × r)ᵀ; Σ c (r × N) gᵀ, Σ c (r × N)(g × r)ᵀ].
  Eigen::Matrix<double, 6, 6> moments() noexcept {
    flush();
    return m_moments.topRows<6>();
  }

 private:
  /// Points per chunk, and the rows of a padded column (one 8-double vector register, or two
  /// or four on narrower SIMD).
  static constexpr int chunk = 32;
  static constexpr int padded_rows = 8;

  [[gnu::noinline]] void flush() noexcept {
    Eigen::Matrix<double, padded_rows, 6> sum = m_moments;
    for (int k = 0; k < m_pending; ++k) {
      const auto u = static_cast<std::size_t>(k);
      sum.noalias() += m_left[u] * m_right[u].transpose();
    }
    m_moments = sum;
    m_pending = 0;
  }

  Eigen::Matrix<double, padded_rows, 6> m_moments = Eigen::Matrix<double, padded_rows, 6>::Zero();
  std::array<Eigen::Matrix<double, padded_rows, 1>, chunk> m_left;  // c [N; r × N; 0; 0]
  std::array<Eigen::Matrix<double, 6, 1>, chunk> m_right;           // [g; g × r]
  int m_pending = 0;
};

/// The traversal; a friend of ContactWorkspace.
struct TraversalAccess {
  /// Nodes whose points are moved into the field's frame, and whose field memory is requested,
  /// before the first of them is looked up.
  static constexpr Eigen::Index batch = 16;
  /// A level the time budget may cut reads the clock before every this many batches.
  static constexpr Eigen::Index batches_per_clock_reading = 2;
  using Clock = std::chrono::steady_clock;

  static void fail(ContactWorkspace& ws) noexcept {
    ContactResult& result = ws.m_result;
    result.force.setZero();
    result.torque.setZero();
    result.force_by_translation.setZero();
    result.force_by_rotation.setZero();
    result.torque_by_translation.setZero();
    result.torque_by_rotation.setZero();
    result.pointshell_reduced_force.setZero();
    result.field_reduced_force.setZero();
    result.statistics = ContactStatistics{};
  }

  /// |q| into the workspace, for DeformablePoints.
  /// nullptr if q does not fit the workspace or is not finite.
  static const double* absolute_q(ContactWorkspace& ws,
                                  const Eigen::Ref<const Eigen::VectorXd>& q) noexcept {
    if (ws.m_pointshell_dimension == 0 || q.size() != ws.m_pointshell_dimension || !q.allFinite()) {
      return nullptr;
    }
    ws.m_abs_q = q.cwiseAbs();
    return ws.m_abs_q.data();
  }

  template <typename Points, DistanceField Field>
  static bool run(const Points& points, const Field& field, const ContactFrames& frames,
                  ContactWorkspace& ws) noexcept;
};

template <typename Points, DistanceField Field>
bool TraversalAccess::run(const Points& points, const Field& field, const ContactFrames& frames,
                          ContactWorkspace& ws) noexcept {
  const ContactOptions& options = ws.m_options;
  const auto now = [clock = options.degradation.clock]() noexcept {
    return clock != nullptr
               ? clock()
               : std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  };
  const double start = now();
  const PointTree& tree = points.tree();
  constexpr bool deformable_field = DeformableDistanceField<Field>;
  constexpr bool gradient_with_value = !deformable_field;
  bool fits = ws.m_tree_identity == &tree && ws.m_nodes == tree.num_nodes() &&
              frames.pointshell.matrix().allFinite() && frames.field.matrix().allFinite() &&
              frames.grasp_point.allFinite();
  if constexpr (deformable_field) fits = fits && field.dimension() == ws.m_field_dimension;
  // Friction's default stick distance, μ_s h, and the contact onset's default depth need the
  // field's voxel h.
  double cell_size = 0.0;
  if constexpr (CellSizedDistanceField<Field>) cell_size = field.cell_size();
  const double onset = options.onset_depth_for(cell_size);
  FrictionOptions friction = options.friction;
  const bool with_friction = friction.enabled();
  if (with_friction) {
    friction.stick_distance = friction.stick_distance_for(cell_size);
    fits = fits && friction.stick_distance > 0.0;
  }
  if (!fits) {
    fail(ws);
    return false;
  }

  // Pointshell body → world (x = R_P p + t_P) and → field body (X = R p + t).
  const Eigen::Matrix3d rotation_p = frames.pointshell.linear();
  const Eigen::Vector3d translation_p = frames.pointshell.translation();
  const Eigen::Matrix3d rotation_f = frames.field.linear();
  const Eigen::Matrix3d rotation = rotation_f.transpose() * rotation_p;
  const Eigen::Vector3d translation =
      rotation_f.transpose() * (translation_p - frames.field.translation());

  ContactResult& result = ws.m_result;
  ContactStatistics& stats = result.statistics;
  stats = ContactStatistics{};
  // Against a deformable field only when it bounds its own motion.
  const bool coherent =
      options.coherence.enabled && (!deformable_field || BoundedDeformableDistanceField<Field>);
  if (coherent) {
    const double* q = nullptr;
    if constexpr (Points::deformable) q = points.q_data();
    const double* field_q = nullptr;
    double field_bound = 0.0;
    if constexpr (BoundedDeformableDistanceField<Field>) {
      field_q = field.coordinates().data();
      field_bound = field.displacement_bound();
    }
    stats.coherence_reset = ws.begin_coherence(rotation, translation, q, field_q, field_bound);
  }
  ContactSums sums;
  FrictionSums friction_sums;
  if (with_friction) ws.begin_friction();
  ws.m_contact_reduced_force.setZero();
  result.field_reduced_force.setZero();
  const double stiffness = options.stiffness;
  const bool weighted = !ws.m_area_weights.empty();
  const bool exact_gradient = options.gradient == ContactGradient::field_gradient;
  const DegradationOptions& degradation = options.degradation;
  const Pointshell& shell = tree.pointshell();
  double* point_distance = ws.m_point_distance.data();

  const auto cost_units = [&](double traversed, double contacts, double queued) noexcept {
    const double contact_share = traversed > 0.0 ? contacts / traversed : 0.0;
    return traversed + queued + degradation.contact_weight * (contacts + contact_share * queued);
  };

  // time_budget: a level the budget may cut is abandoned as soon as the clock passes its limit
  // (the budget, or cold_fraction of it for a level the previous query did not render), and the
  // query returns what the levels before it found, exactly as if it had stopped there: so it
  // never cuts a query that fits at its level of detail, and overruns by at most one clock
  // interval.
  const double budget_seconds = degradation.budget_microseconds * 1e-6;
  double abandon_after = budget_seconds;
  bool abandonable = false;
  ContactSums kept_sums;
  FrictionSums kept_friction_sums;
  std::int64_t kept_points_in_contact = 0;
  double kept_deepest_penetration = 0.0;

  // Level 0 is always rendered: all its nodes.
  std::int32_t* current = ws.m_current.data();
  std::int32_t* next = ws.m_next.data();
  Eigen::Index current_count = tree.level_end(0);
  for (Eigen::Index n = 0; n < current_count; ++n) current[n] = static_cast<std::int32_t>(n);

  Eigen::Vector3d batch_points[batch];        // pointshell body frame
  Eigen::Vector3d batch_field_points[batch];  // field body frame
  // Fields that cull many points faster than one at a time get the batch's new points at once
  // (only where no gradient comes with the value: a deformed field's costs as much again).
  constexpr bool batch_culling = BatchCullingDistanceField<Field> && !gradient_with_value;
  Eigen::Vector3d batch_lookup_points[batch];
  double batch_radii[batch], batch_distances[batch];
  // A deformed field's culling also finds the proxy a point in contact takes its reaction at
  // (it searched the neighbours for the value): no second search per point in contact.
  constexpr bool proxy_reaction = batch_culling && ProxyReactionDistanceField<Field>;
  [[maybe_unused]] Eigen::Index batch_proxies[batch];
  int batch_slot[batch];
  for (int level = 0;; ++level) {
    const Eigen::Index first_new_point = shell.level_begin(level);
    Eigen::Index next_count = 0;
    bool abandoned = false;
    for (Eigen::Index begin = 0; begin < current_count; begin += batch) {
      if (abandonable && (begin / batch) % batches_per_clock_reading == 1 &&
          now() - start > abandon_after) {
        abandoned = true;
        break;
      }
      const Eigen::Index end = std::min(begin + batch, current_count);
      [[maybe_unused]] int batch_count = 0;
      // Phase 1: the batch's new points in the field's frame, and the field memory their
      // lookups will read requested at once, so that the cache misses overlap rather than
      // follow one another; the next batch's modes too.
      for (Eigen::Index k = begin; k < end; ++k) {
        const std::int32_t n = current[k];
        if (k + batch < current_count) points.prefetch(current[k + batch]);
        const Eigen::Index s = tree.node(n).point;
        if (s < first_new_point) continue;
        if (coherent && ws.m_skip_until[static_cast<std::size_t>(n)] > ws.m_cycle) continue;
        batch_points[k - begin] = points.position(s);
        batch_field_points[k - begin] = rotation * batch_points[k - begin] + translation;
        if constexpr (requires { field.prefetch(batch_field_points[0]); }) {
          field.prefetch(batch_field_points[k - begin]);
        }
        if constexpr (batch_culling) {
          batch_slot[k - begin] = batch_count;
          batch_lookup_points[batch_count] = batch_field_points[k - begin];
          batch_radii[batch_count++] = points.radius(n);
        }
      }
      if constexpr (proxy_reaction) {
        field.culling_distances(std::span(batch_lookup_points, batch_count),
                                std::span<const double>(batch_radii, batch_count),
                                std::span(batch_distances, batch_count),
                                std::span(batch_proxies, batch_count));
      } else if constexpr (batch_culling) {
        field.culling_distances(std::span(batch_lookup_points, batch_count),
                                std::span<const double>(batch_radii, batch_count),
                                std::span(batch_distances, batch_count));
      }
      // Phase 2: look up, cull, queue, and render contacts.
      for (Eigen::Index k = begin; k < end; ++k) {
        const std::int32_t n = current[k];
        if (coherent && ws.m_skip_until[static_cast<std::size_t>(n)] > ws.m_cycle) {
          ++stats.nodes_skipped;
          continue;
        }
        ++stats.nodes_traversed;
        const PointTreeNode& node = tree.node(n);
        const Eigen::Index s = node.point;
        const bool first_instance = s >= first_new_point;
        const Eigen::Vector3d& p = batch_points[k - begin];
        const Eigen::Vector3d& field_point = batch_field_points[k - begin];
        const double radius = points.radius(n);
        double d;
        // Set with d when the exact gradient is wanted; zeroed so that no build can read it unset.
        Eigen::Vector3d field_gradient = Eigen::Vector3d::Zero();
        if (first_instance) {
          // A grid's gradient with every value costs less than a second lookup for the points
          // in contact once more than a few percent of them are; a deformed field's gradient
          // costs as much as its value (bench_contact_query). A culled node's value may be a
          // bound: the copies of its point are in its subtree, never read.
          if (exact_gradient && gradient_with_value) {
            d = field.distance_and_gradient(field_point, field_gradient);
          } else if constexpr (batch_culling) {
            d = batch_distances[batch_slot[k - begin]];
          } else if constexpr (CullingDistanceField<Field>) {
            d = field.culling_distance(field_point, radius);
          } else {
            d = field.distance(field_point);
          }
          point_distance[s] = d;
        } else {
          d = point_distance[s];
        }
        if (d > radius) {
          if (coherent)
            ws.m_skip_until[static_cast<std::size_t>(n)] = ws.coherent_skip_until(d - radius);
          continue;
        }
        for (std::int32_t c = 0; c < node.child_count; ++c)
          next[next_count++] = node.first_child + c;
        if (!first_instance || !(d < 0.0)) continue;

        // A point in contact (eq. 3.1, §4.1–§4.2), through the onset.
        const ContactOnset onset_point(d, onset);
        const double weight = weighted ? ws.m_area_weights[static_cast<std::size_t>(s)] : 1.0;
        const double coefficient = weight * stiffness * onset_point.slope;
        const Eigen::Vector3d normal_body = points.normal(s);
        const Eigen::Vector3d normal = rotation_p * normal_body;
        const Eigen::Vector3d x = rotation_p * p + translation_p;
        if (exact_gradient && !gradient_with_value) {
          field.distance_and_gradient(field_point, field_gradient);
        }
        const Eigen::Vector3d gradient =
            exact_gradient ? Eigen::Vector3d(rotation_f * field_gradient) : normal;
        const Eigen::Vector3d lever = x - frames.grasp_point;
        sums.add(lever, onset_point.depth, normal, gradient, coefficient);
        sums.weight += weight * onset_point.slope;
        ++stats.points_in_contact;
        stats.deepest_penetration = std::max(stats.deepest_penetration, -d);
        Eigen::Vector3d f = coefficient * onset_point.depth * normal;  // on the field object
        if (with_friction) {
          f += add_point_friction(
              {x, lever, normal, gradient, field_point, onset_point.depth, coefficient}, friction,
              ws.anchor_holds(s, level), ws.m_friction_query, ws.m_last_normal_load, rotation_f,
              frames.field.translation(), ws.m_anchors[static_cast<std::size_t>(s)], friction_sums);
        }
        if constexpr (Points::deformable) {
          points.add_reduced_force(s, rotation_p.transpose() * -f, ws.m_contact_reduced_force);
        }
        if constexpr (proxy_reaction) {
          field.add_proxy_reduced_force(batch_proxies[batch_slot[k - begin]],
                                        rotation_f.transpose() * f, result.field_reduced_force);
        } else if constexpr (deformable_field) {
          field.add_reduced_force(field_point, rotation_f.transpose() * f,
                                  result.field_reduced_force);
        }
      }
    }
    if (abandoned) {
      sums = kept_sums;
      friction_sums = kept_friction_sums;
      stats.points_in_contact = kept_points_in_contact;
      stats.deepest_penetration = kept_deepest_penetration;
      ws.m_contact_reduced_force = ws.m_kept_contact_reduced_force;
      result.field_reduced_force = ws.m_kept_field_reduced_force;
      stats.complete = false;
      break;
    }
    stats.deepest_level = level;
    if (next_count == 0 || level + 1 == tree.num_levels()) {
      // Nothing queued: every deeper point was culled, so those levels count as rendered (out of
      // contact) for friction's anchors too.
      if (with_friction) ws.mark_rendered(level, tree.num_levels());
      break;
    }
    if (with_friction) ws.mark_rendered(level, level + 1);
    if (level == options.max_level) {
      stats.complete = false;
      break;
    }

    // Graceful degradation (§3.10.3). The contact floor comes first: when the previous query had
    // points in contact, a level more than one above its deepest is always rendered, and its
    // deepest level too while the contact's cost at the machine's typical speed fits. So a spike
    // in the measured cost (a preempted thread) drops no level, and a contact whose cost has
    // really grown is handed to a coarser level one level per query, never at once to a coarse
    // level whose few points could let the object sink through.
    if (degradation.mode != DegradationOptions::Mode::none) {
      const bool floor_level = level + 1 == ws.m_contact_floor;
      // Eq. 3.13's prediction, for node_count and the floor's level only.
      const auto predicted_units = [&]() noexcept {
        // Queued nodes temporal coherence will skip cost next to nothing: only the others count
        // (one read each, against a lookup each for the nodes it would otherwise predict).
        Eigen::Index skipped_next = 0;
        if (coherent) {
          for (Eigen::Index k = 0; k < next_count; ++k) {
            skipped_next += ws.m_skip_until[static_cast<std::size_t>(next[k])] > ws.m_cycle ? 1 : 0;
          }
        }
        return cost_units(static_cast<double>(stats.nodes_traversed),
                          static_cast<double>(stats.points_in_contact),
                          static_cast<double>(next_count - skipped_next));
      };
      bool render = level + 1 < ws.m_contact_floor;
      abandonable = false;
      // A level deeper than the previous query's gets the cold threshold: the level of detail
      // goes finer only with room to spare, so it does not flicker.
      const double limit_fraction = level + 1 <= ws.m_warm_level ? 1.0 : degradation.cold_fraction;
      if (!render && degradation.mode == DegradationOptions::Mode::node_count) {
        render = predicted_units() <= limit_fraction * degradation.warm_threshold;
      } else if (!render) {
        render = floor_level && ws.fits_at_typical_speed(predicted_units(), budget_seconds);
        abandon_after = limit_fraction * budget_seconds;
        if (!render && now() - start < abandon_after) render = abandonable = true;
      }
      if (!render) {
        stats.complete = false;
        break;
      }
      if (abandonable) {
        kept_sums = sums;
        kept_friction_sums = friction_sums;
        kept_points_in_contact = stats.points_in_contact;
        kept_deepest_penetration = stats.deepest_penetration;
        ws.m_kept_contact_reduced_force = ws.m_contact_reduced_force;
        ws.m_kept_field_reduced_force = result.field_reduced_force;
      }
    }
    std::swap(current, next);
    current_count = next_count;
  }

  // L/ℓ scaling (§3.5) and the haptic object's side.
  const double scale = options.scaling_count / std::max(options.scaling_count, sums.weight);
  const Eigen::Matrix<double, 6, 6> moments = sums.moments();
  const double sign = options.haptic_object == HapticObject::distance_field ? 1.0 : -1.0;
  // Friction's sums carry their own derivatives (FrictionSums), and are zero without it.
  const Eigen::Matrix<double, 6, 6> tangential =
      with_friction ? friction_sums.jacobian() : Eigen::Matrix<double, 6, 6>::Zero();
  result.force = sign * scale * (sums.force + friction_sums.force);
  result.torque = sign * scale * (sums.torque + friction_sums.torque);
  result.force_by_translation =
      scale * (tangential.topLeftCorner<3, 3>() - moments.topLeftCorner<3, 3>());
  result.force_by_rotation = scale * (tangential.topRightCorner<3, 3>() +
                                      moments.topRightCorner<3, 3>() + cross_matrix(sums.force));
  // The field object's grasp point moves with it, shortening every lever by Δx (§4.2); a
  // pointshell's moves with the points.
  result.torque_by_translation =
      scale * (tangential.bottomLeftCorner<3, 3>() - moments.bottomLeftCorner<3, 3>());
  if (options.haptic_object == HapticObject::distance_field) {
    result.torque_by_translation += scale * cross_matrix(sums.force + friction_sums.force);
  }
  result.torque_by_rotation =
      scale * (tangential.bottomRightCorner<3, 3>() + moments.bottomRightCorner<3, 3>() +
               cross_matrix(sums.torque));
  stats.points_sliding = friction_sums.sliding;
  if (with_friction) ws.m_last_normal_load = friction_sums.normal_load;
  if constexpr (Points::deformable) {
    result.pointshell_reduced_force = scale * ws.m_contact_reduced_force;
  } else {
    // A deformable pair's workspace queried with its tree as rigid: no reduced force, not the
    // previous query's.
    result.pointshell_reduced_force.setZero();
  }
  if constexpr (deformable_field) result.field_reduced_force *= scale;

  const double seconds = now() - start;
  stats.microseconds = seconds * 1e6;
  ws.end_degradation(stats.deepest_level, stats.points_in_contact > 0, seconds,
                     cost_units(static_cast<double>(stats.nodes_traversed),
                                static_cast<double>(stats.points_in_contact), 0.0));
  return true;
}

}  // namespace khz::contact::detail
