#pragma once
// What `khz prep`, `khz run` and `khz report` share: where the product cache is, Ctrl-C as a
// request to stop, and preparing a scene with progress bars and a summary table.

#include <khz/reduced/work_group.hpp>
#include <khz/scene/prepared_scene.hpp>
#include <khz/scene/scene_description.hpp>

#include <filesystem>
#include <iosfwd>
#include <string>

namespace khz::tool {

/// While alive, Ctrl-C asks the running computation to stop (it polls requested()) instead of
/// killing the process, so the product cache is left without temporary files and a run's
/// outputs are written; a second Ctrl-C ends the process at once.
class InterruptRequest {
 public:
  InterruptRequest();
  ~InterruptRequest();
  InterruptRequest(const InterruptRequest&) = delete;
  InterruptRequest& operator=(const InterruptRequest&) = delete;

  bool requested() const noexcept;

 private:
  void (*m_previous)(int);
};

/// --cache, or scene::default_cache_directory(), or `.khz-cache` beside the scene file.
std::filesystem::path cache_directory(const std::string& option, const std::string& scene_file);

/// Prepares `description` through the cache in `cache` (scene::prepare_scene()) with progress
/// bars on stderr; Ctrl-C cancels (reduced::Cancelled). Prints the summary table
/// (print_prepare_summary()) to `summary`. With a `group` of several processes they share the
/// preparation; only its first process (rank 0) shows progress and the summary.
/// @throws what scene::prepare_scene() throws.
scene::PreparedScene prepare_with_progress(const scene::SceneDescription& description,
                                           const std::filesystem::path& cache,
                                           std::ostream& summary,
                                           reduced::WorkGroup* group = nullptr);

/// One row per product: object, product, how it was obtained (with the rank that computed it in
/// a shared preparation), seconds, cache file; then the
/// total, and the notes of products that need a look.
void print_prepare_summary(std::ostream& out, const scene::PreparedScene& prepared,
                           const std::filesystem::path& cache);

}  // namespace khz::tool
