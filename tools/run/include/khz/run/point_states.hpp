#pragma once
// Which pointshell points a contact query looks at and which touch (thesis Figure 3.1), for
// pictures and ParaView files of a run.

#include <khz/haptic/world/body.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace khz::run {

/// What the traversal did with a point.
enum class PointState : std::uint8_t {
  untouched = 0,   ///< In a culled subtree: never looked at.
  traversed = 1,   ///< Its distance was looked up; not in contact.
  in_contact = 2,  ///< On the deepest level rendered, inside the field (d < 0), not sliding.
  /// In contact, and its friction slid in the pair's last query (contact::FrictionState); set by
  /// capture_frame(), not by classify_points().
  sliding = 3,
};

/// A pointshell's points down to some level, placed in the world and classified.
struct PointPicture {
  reduced::VertexMatrix positions;  ///< World positions (m) of the tree's points on levels ≤ L.
  std::vector<PointState> states;   ///< One per row of `positions`.
  /// How many are in each state, indexed by PointState.
  std::int64_t count(PointState state) const noexcept;
};

/// Replays the culling of a contact query (§3.10.1) for one pair as the objects are now: level 0
/// is looked at whole; a node's children are looked at when its point's distance d does not
/// exceed its bounding radius (rest radius, or eq. 3.12's R_i(q) for a deformable pointshell);
/// on `deepest_level` (the query's ContactStatistics::deepest_level, clamped to the tree) a point
/// with d < 0 is in contact. This is what a query without temporal coherence visits; one with
/// coherence skips some of these nodes but finds the same contacts. Not for the haptic thread
/// (allocates; one distance lookup per node, as the query).
/// @param pointshell a body with a pointshell (haptic::Body::pointshell), at its pose and q.
/// @param field a body with a distance field (haptic::Body::field), at its pose.
/// @param deepest_level < 0 gives an empty picture.
PointPicture classify_points(const haptic::Body& pointshell, const haptic::Body& field,
                             int deepest_level);

/// classify_points() with the pointshell's reduced coordinates given instead of read from
/// `pointshell.integrator`, which may then be null: for a caller that keeps its own copy of q,
/// such as the interactive viewer's drawing thread, whose bodies' integrators the haptic thread
/// is stepping meanwhile.
/// @param q a deformable pointshell's q (its tree's r entries); ignored for a rigid one.
/// @throws reduced::Error if `pointshell` has no pointshell, or a deformable pointshell's q
///         does not have r entries.
PointPicture classify_points(const haptic::Body& pointshell,
                             const Eigen::Ref<const Eigen::VectorXd>& q, const haptic::Body& field,
                             int deepest_level);

/// The points of World pair `pair` whose friction slid in its last query
/// (contact::FrictionState::sliding; ContactStatistics::points_sliding counts them): their
/// pointshell indices, ascending, written to `out`, at most out.size() of them.
/// noexcept and allocation-free: for the haptic thread (it reads the pair's workspace, so call it
/// between cycles). Looks at the points of the pair's deepest level rendered and stops when it
/// has found them all.
/// @returns how many it wrote.
std::size_t sliding_points(const haptic::World& world, int pair,
                           std::span<std::int32_t> out) noexcept;

/// Marks the points of `picture` in contact (PointState::in_contact) that `sliding` lists
/// (pointshell indices, as sliding_points() gives them) as PointState::sliding; an index past
/// the picture or of a point not in contact there is passed over.
void mark_sliding(PointPicture& picture, std::span<const std::int32_t> sliding) noexcept;

}  // namespace khz::run
