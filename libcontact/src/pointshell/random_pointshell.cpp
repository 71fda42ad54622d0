#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/mesh/surface_area.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "pointshell/split_mix.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace khz::contact {

using detail::split_mix;
using detail::unit_interval;

Pointshell random_pointshell(const TriangleMesh& mesh, Eigen::Index count, std::uint64_t seed) {
  validate(mesh);
  if (count < 1) throw Error("random_pointshell: count " + std::to_string(count) + " is below 1");
  const Eigen::Index triangles = mesh.num_triangles();
  // Running sums of the areas (serial: the same bits on every run).
  std::vector<double> cumulative(static_cast<std::size_t>(triangles));
  double total = 0.0;
  for (Eigen::Index t = 0; t < triangles; ++t) {
    total += reduced::triangle_area(mesh, t);
    cumulative[static_cast<std::size_t>(t)] = total;
  }
  if (!(total > 0.0)) throw Error("random_pointshell: the mesh has zero area");
  // Where a target rounds up to `total`: the last triangle with an area.
  Eigen::Index last = triangles - 1;
  while (last > 0 && cumulative[static_cast<std::size_t>(last)] ==
                         cumulative[static_cast<std::size_t>(last - 1)]) {
    --last;
  }

  Pointshell pointshell;
  pointshell.points.resize(count, 3);
  pointshell.normals.resize(count, 3);
  const std::uint64_t key = split_mix(seed);
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(static)
  for (Eigen::Index k = 0; k < count; ++k) {
    const std::uint64_t counter = key + 3 * static_cast<std::uint64_t>(k);
    // The first triangle whose running sum exceeds the target: zero-area triangles are never
    // chosen (their sum equals their predecessor's).
    const double target = unit_interval(split_mix(counter)) * total;
    const auto found = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const Eigen::Index t = found == cumulative.end() ? last : found - cumulative.begin();
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
    // Uniform on the triangle: √u₁ picks the distance from a, u₂ the position across
    // [Osada et al. 2002, "Shape distributions", eq. 1].
    const double root = std::sqrt(unit_interval(split_mix(counter + 1)));
    const double across = unit_interval(split_mix(counter + 2));
    pointshell.points.row(k) =
        ((1.0 - root) * a + root * (1.0 - across) * b + root * across * c).transpose();
    pointshell.normals.row(k) = -(b - a).cross(c - a).normalized().transpose();  // inward (§3.5)
  }
  pointshell.level_ends = {count};
  return pointshell;
}

}  // namespace khz::contact
