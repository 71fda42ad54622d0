#include <khz/scene/anchor_region.hpp>

namespace khz::scene {

bool AnchorRegion::contains(const Eigen::Vector3d& p) const noexcept {
  if (kind == Kind::box) {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  return (p - point).dot(normal) >= 0.0;
}

}  // namespace khz::scene
