#include <khz/contact/pointshell/pointshell.hpp>

#include <cmath>
#include <string>

namespace khz::contact {

void validate(const Pointshell& pointshell) {
  const Eigen::Index n = pointshell.size();
  if (pointshell.normals.rows() != n) {
    throw Error("Pointshell: " + std::to_string(n) + " points but " +
                std::to_string(pointshell.normals.rows()) + " normals");
  }
  if (pointshell.level_ends.empty()) throw Error("Pointshell: no levels");
  Eigen::Index begin = 0;
  for (int level = 0; level < pointshell.num_levels(); ++level) {
    const Eigen::Index end = pointshell.level_ends[static_cast<std::size_t>(level)];
    if (end <= begin) {
      throw Error("Pointshell: level " + std::to_string(level) + " is empty or out of order");
    }
    begin = end;
  }
  if (begin != n) {
    throw Error("Pointshell: the levels end at point " + std::to_string(begin) + ", not at " +
                std::to_string(n));
  }
  for (Eigen::Index s = 0; s < n; ++s) {
    if (!pointshell.points.row(s).allFinite() || !pointshell.normals.row(s).allFinite()) {
      throw Error("Pointshell: point " + std::to_string(s) + " is not finite");
    }
    if (std::abs(pointshell.normals.row(s).norm() - 1.0) > 1e-6) {
      throw Error("Pointshell: the normal of point " + std::to_string(s) + " is not a unit vector");
    }
  }
}

}  // namespace khz::contact
