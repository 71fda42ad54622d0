#include <khz/reduced/errors.hpp>
#include <khz/run/point_states.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

namespace khz::run {
namespace {

/// The tree of `body`'s pointshell, rigid or deformable (null if it has none).
const contact::PointTree* point_tree(const haptic::Body& body) noexcept {
  if (const auto* deformable = std::get_if<const contact::DeformablePointTree*>(&body.pointshell)) {
    return &(*deformable)->tree();
  }
  const auto* rigid = std::get_if<const contact::PointTree*>(&body.pointshell);
  return rigid != nullptr ? *rigid : nullptr;
}

}  // namespace

std::int64_t PointPicture::count(PointState state) const noexcept {
  return std::count(states.begin(), states.end(), state);
}

PointPicture classify_points(const haptic::Body& pointshell, const haptic::Body& field,
                             int deepest_level) {
  if (pointshell.integrator == nullptr) {
    return classify_points(pointshell, Eigen::VectorXd(), field, deepest_level);
  }
  return classify_points(pointshell, pointshell.integrator->coordinates(), field, deepest_level);
}

PointPicture classify_points(const haptic::Body& pointshell,
                             const Eigen::Ref<const Eigen::VectorXd>& coordinates,
                             const haptic::Body& field, int deepest_level) {
  const auto* deformable = std::get_if<const contact::DeformablePointTree*>(&pointshell.pointshell);
  const contact::PointTree* const found = point_tree(pointshell);
  if (found == nullptr) {
    throw reduced::Error("classify_points: body '" + pointshell.name + "' has no pointshell");
  }
  const contact::PointTree& tree = *found;
  PointPicture picture;
  if (deepest_level < 0) return picture;
  const int last = std::min(deepest_level, tree.num_levels() - 1);
  const Eigen::Index points = tree.pointshell().level_end(last);

  Eigen::VectorXd q, abs_q;
  if (deformable != nullptr) {
    if (coordinates.size() != (*deformable)->dimension()) {
      throw reduced::Error("classify_points: the deformable pointshell has r = " +
                           std::to_string((*deformable)->dimension()) + " but q has " +
                           std::to_string(coordinates.size()) + " entries");
    }
    q = coordinates;
    abs_q = q.cwiseAbs();
  }
  picture.positions.resize(points, 3);
  for (Eigen::Index s = 0; s < points; ++s) {
    const Eigen::Vector3d body = deformable != nullptr
                                     ? (*deformable)->position(s, q)
                                     : Eigen::Vector3d(tree.pointshell().points.row(s));
    picture.positions.row(s) = (pointshell.pose * body).transpose();
  }
  const Eigen::Isometry3d to_field = field.pose.inverse();
  const auto distance = [&](Eigen::Index s) {
    const Eigen::Vector3d x = to_field * Eigen::Vector3d(picture.positions.row(s));
    return std::visit(
        [&](const auto& f) {
          if constexpr (std::is_same_v<std::decay_t<decltype(f)>, std::monostate>) {
            return std::numeric_limits<double>::infinity();
          } else {
            return f->distance(x);
          }
        },
        field.field);
  };

  picture.states.assign(static_cast<std::size_t>(points), PointState::untouched);
  std::vector<char> visit(static_cast<std::size_t>(tree.num_nodes()), 0);
  std::fill(visit.begin(), visit.begin() + tree.level_end(0), 1);
  for (int level = 0; level <= last; ++level) {
    for (Eigen::Index n = tree.level_begin(level); n < tree.level_end(level); ++n) {
      if (visit[static_cast<std::size_t>(n)] == 0) continue;
      const contact::PointTreeNode& node = tree.node(n);
      const double d = distance(node.point);
      PointState& state = picture.states[static_cast<std::size_t>(node.point)];
      if (level == last) {
        if (d < 0.0) state = PointState::in_contact;
      }
      state = std::max(state, PointState::traversed);
      const double radius =
          deformable != nullptr ? (*deformable)->bounding_radius(n, abs_q) : node.rest_radius;
      if (level < last && !(d > radius)) {
        std::fill_n(visit.begin() + node.first_child, node.child_count, 1);
      }
    }
  }
  return picture;
}

std::size_t sliding_points(const haptic::World& world, int pair,
                           std::span<std::int32_t> out) noexcept {
  const contact::ContactResult& result = world.pair_result(pair);
  const std::int64_t sliding = result.statistics.points_sliding;
  if (sliding <= 0 || result.statistics.deepest_level < 0) return 0;
  const contact::PointTree* tree = point_tree(world.bodies()[static_cast<std::size_t>(
      world.pairs()[static_cast<std::size_t>(pair)].pointshell)]);
  if (tree == nullptr) return 0;
  const Eigen::Index points = tree->pointshell().level_end(
      std::min(result.statistics.deepest_level, tree->num_levels() - 1));
  std::size_t found = 0;
  for (Eigen::Index s = 0;
       s < points && found < out.size() && static_cast<std::int64_t>(found) < sliding; ++s) {
    if (world.friction_state(pair, s) == contact::FrictionState::sliding) {
      out[found++] = static_cast<std::int32_t>(s);
    }
  }
  return found;
}

void mark_sliding(PointPicture& picture, std::span<const std::int32_t> sliding) noexcept {
  for (const std::int32_t s : sliding) {
    if (s < 0 || static_cast<std::size_t>(s) >= picture.states.size()) continue;
    PointState& state = picture.states[static_cast<std::size_t>(s)];
    if (state == PointState::in_contact) state = PointState::sliding;
  }
}

}  // namespace khz::run
