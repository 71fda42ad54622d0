#include <khz/contact/field/mesh_distance.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>

#include <khz/reduced/stage_progress.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace khz::contact {

namespace {

// Points per progress report: each closest-point query takes microseconds, so a report every
// few milliseconds.
constexpr Eigen::Index chunk_size = 4096;

}  // namespace

PointMatrix inward_normals(const MeshDistance& surface, const Eigen::Ref<const PointMatrix>& points,
                           const ProgressCallback& progress) {
  const Eigen::Index count = points.rows();
  for (Eigen::Index s = 0; s < count; ++s) {
    if (!points.row(s).allFinite()) {
      throw Error("inward_normals: point " + std::to_string(s) + " is not finite");
    }
  }
  PointMatrix normals(count, 3);
  reduced::StageProgress stage(progress, "pointshell normals", count);
  // The first point whose closest feature has no pseudonormal (only a mesh of degenerate
  // triangles has none); reported after the parallel loop, which must not throw.
  Eigen::Index without_normal = std::numeric_limits<Eigen::Index>::max();
  for (Eigen::Index begin = 0; begin < count; begin += chunk_size) {
    const Eigen::Index end = std::min(count, begin + chunk_size);
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic, 64) \
    reduction(min                                                                     \
              : without_normal)
    for (Eigen::Index s = begin; s < end; ++s) {
      const Eigen::Vector3d pseudonormal = surface.closest(points.row(s).transpose()).pseudonormal;
      if (!(std::abs(pseudonormal.norm() - 1.0) < 1e-6))
        without_normal = std::min(without_normal, s);
      normals.row(s) = -pseudonormal.transpose();  // inward (§3.5)
    }
    stage.advance(end - begin);
  }
  if (without_normal < count) {
    throw Error("inward_normals: the mesh feature closest to point " +
                std::to_string(without_normal) + " has no normal");
  }
  stage.finish();
  return normals;
}

}  // namespace khz::contact
