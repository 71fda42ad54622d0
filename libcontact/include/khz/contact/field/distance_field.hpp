#pragma once
// What every distance-field object offers the contact query: sampled grids, analytic shapes and
// (later) deformed fields all answer the same two questions, so the query is written once as a
// template over this concept, with no virtual call per point (thesis §3.5, §3.11, §3.11.1).

#include <Eigen/Core>

#include <concepts>
#include <span>

namespace khz::contact {

/// A signed distance d(p) to an object, in its own frame: negative inside, metres.
/// - distance(p): d(p), or where d is not known exactly (e.g. outside a grid's box) a lower
///   bound, so that culling by it never misses a contact.
/// - distance_and_gradient(p, g): the same value, and in g the gradient of the function whose
///   value is returned (not normalized).
/// Both are noexcept, allocate nothing, are thread-safe (const) and are finite for finite p.
template <typename Field>
concept DistanceField = requires(const Field& field, const Eigen::Vector3d& p, Eigen::Vector3d& g) {
  { field.distance(p) }
  noexcept->std::same_as<double>;
  { field.distance_and_gradient(p, g) }
  noexcept->std::same_as<double>;
};

/// A DistanceField with a cheaper answer to the contact query's culling question "is d(p) above
/// t?": culling_distance(p, t) is distance(p), bit for bit, when that is at most t, and otherwise
/// any lower bound of distance(p) above t. noexcept, allocation-free, thread-safe.
template <typename Field>
concept CullingDistanceField = DistanceField<Field> &&
    requires(const Field& field, const Eigen::Vector3d& p, double t) {
  { field.culling_distance(p, t) }
  noexcept->std::same_as<double>;
};

/// A CullingDistanceField that answers many culling questions at once, faster per point:
/// culling_distances(x, t, out) sets out[i] = culling_distance(x[i], t[i]) for spans of equal
/// size. noexcept, allocation-free, thread-safe.
template <typename Field>
concept BatchCullingDistanceField = CullingDistanceField<Field> &&
    requires(const Field& field, std::span<const Eigen::Vector3d> x, std::span<const double> t,
             std::span<double> out) {
  { field.culling_distances(x, t, out) }
  noexcept;
};

/// A DistanceField sampled on cells: cell_size() is h (m, > 0), the length below which it
/// resolves no detail (a grid's spacing). The contact query chooses friction's default stick
/// distance from it (FrictionOptions::stick_distance); analytic shapes have none.
template <typename Field>
concept CellSizedDistanceField = DistanceField<Field> && requires(const Field& field) {
  { field.cell_size() }
  noexcept->std::convertible_to<double>;
};

/// A distance field of a reduced deformable object (thesis §3.12), in its current deformation:
/// besides the distances it takes the reaction of a contact, so the contact query can apply it to
/// the object's integrator.
/// - dimension(): r, the object's number of reduced coordinates.
/// - add_reduced_force(X, f, reduced): adds to `reduced` (r entries, an Eigen::VectorXd) the
///   reduced force of force f (N, body frame) applied at X (m, body frame). It must not throw or
///   allocate (the concept cannot check it: binding an Eigen::Ref is not noexcept).
template <typename Field>
concept DeformableDistanceField = DistanceField<Field> &&
    requires(const Field& field, const Eigen::Vector3d& x, Eigen::VectorXd& reduced) {
  { field.dimension() }
  noexcept->std::convertible_to<Eigen::Index>;
  field.add_reduced_force(x, x, reduced);
};

/// A DeformableDistanceField and BatchCullingDistanceField whose batch culling also names the
/// proxy each point's reaction applies at, so the contact query does not search for it again:
/// - culling_distances(x, t, out, proxies): as culling_distances(x, t, out), and proxies[i] (an
///   Eigen::Index) the one add_reduced_force(x[i], …) would use, wherever out[i] ≤ t[i];
/// - add_proxy_reduced_force(proxy, f, reduced): add_reduced_force(x, f, reduced) for an x whose
///   proxy that is. Neither may throw or allocate.
template <typename Field>
concept ProxyReactionDistanceField = DeformableDistanceField<Field> &&
    BatchCullingDistanceField<Field> &&
    requires(const Field& field, std::span<const Eigen::Vector3d> x, std::span<const double> t,
             std::span<double> out, std::span<Eigen::Index> proxies, Eigen::Index proxy,
             const Eigen::Vector3d& f, Eigen::VectorXd& reduced) {
  { field.culling_distances(x, t, out, proxies) }
  noexcept;
  field.add_proxy_reduced_force(proxy, f, reduced);
};

/// A DeformableDistanceField that also tells how far its surface can have moved, so temporal
/// coherence can cover it (§3.10.2):
/// - coordinates(): its current reduced coordinates q (r entries);
/// - displacement_bound(): m per unit q, no surface point moves more than this times ‖Δq‖.
template <typename Field>
concept BoundedDeformableDistanceField = DeformableDistanceField<Field> &&
    requires(const Field& field) {
  { field.coordinates() }
  noexcept->std::convertible_to<const Eigen::VectorXd&>;
  { field.displacement_bound() }
  noexcept->std::convertible_to<double>;
};

}  // namespace khz::contact
