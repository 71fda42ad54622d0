#include <khz/reduced/errors.hpp>
#include <khz/run/point_states.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

namespace khz::run {

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
  const contact::PointTree& tree =
      deformable != nullptr ? (*deformable)->tree()
                            : *std::get<const contact::PointTree*>(pointshell.pointshell);
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

}  // namespace khz::run
