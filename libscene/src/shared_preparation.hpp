#pragma once
// The first part of a shared preparation (PrepareOptions::group): the cached products missing
// from the cache, each computed by one process of the group (issue 24, item 4).

#include <khz/reduced/work_group.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/product_cache.hpp>
#include <khz/scene/scene_description.hpp>

#include <filesystem>
#include <vector>

namespace khz::scene::detail {

/// A cache file written by one process of a shared preparation.
struct SharedFile {
  std::string object;  ///< The first object that needs it.
  PrepareStep step = PrepareStep::distance_field;
  std::filesystem::path file;
  int rank = 0;          ///< The process that computed it.
  double seconds = 0.0;  ///< Its computation and write, on that process.
  std::string note;      ///< The computation's note; kept by the computing process only.
};

/// Computes every cached product of `scene` that is missing from `cache`, each on one process of
/// `group`, in rounds that respect what products are computed from (models and distance fields,
/// then pointshells, then deformable point trees); every process calls it alike. Returns the
/// files written, with their process and time, the same list on every process. Warnings of the
/// cache (a damaged file computed again) go to `warnings` on the process that saw them.
/// @throws as prepare_scene() does for a failure or cancel on any process, on every process;
///         reduced::Error on every process if they do not list the same missing products or do
///         not all see the written files afterwards (caches that are not one shared directory).
std::vector<SharedFile> compute_shared_products(const SceneDescription& scene, ProductCache& cache,
                                                const PrepareOptions& options,
                                                reduced::WorkGroup& group,
                                                std::vector<PrepareWarning>& warnings);

}  // namespace khz::scene::detail
