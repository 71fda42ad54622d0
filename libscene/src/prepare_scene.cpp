#include <khz/scene/prepare_scene.hpp>

#include "object_preparer.hpp"
#include "shared_preparation.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <algorithm>
#include <exception>
#include <optional>
#include <vector>

namespace khz::scene {

PreparedScene prepare_scene(const SceneDescription& scene, ProductCache& cache,
                            const PrepareOptions& options) {
  std::optional<reduced::ScopedWorkerThreads> threads;
  if (scene.threads > 0) threads.emplace(scene.threads);
  PreparedScene prepared;
  prepared.description = scene;
  prepared.objects.reserve(scene.objects.size());
  std::vector<detail::SharedFile> shared;
  if (options.group && options.group->size() > 1) {
    shared =
        detail::compute_shared_products(scene, cache, options, *options.group, prepared.warnings);
  }
  for (const ObjectDescription& object : scene.objects) {
    detail::ObjectPreparer preparer(object, cache, options, prepared.records, prepared.warnings);
    try {
      prepared.objects.push_back(preparer.prepare());
    } catch (const reduced::Cancelled&) {
      throw;
    } catch (const std::exception& error) {
      std::throw_with_nested(PrepareError(object.name, preparer.step(), error.what()));
    }
  }
  for (const detail::SharedFile& product : shared) {
    // Read by the preparation above, or only computed from (a field a cached pointshell was
    // sampled from): recorded once either way.
    auto record = std::find_if(prepared.records.begin(), prepared.records.end(),
                               [&](const PrepareRecord& r) { return r.file == product.file; });
    if (record == prepared.records.end()) {
      record = prepared.records.insert(prepared.records.end(), PrepareRecord{});
    }
    *record = {product.object,  product.step, PrepareRecord::Origin::computed,
               product.seconds, product.file, product.note,
               product.rank};
  }
  // After the cache's warnings, which the objects' preparation left.
  const auto append = [&](std::vector<PrepareWarning> more) {
    for (PrepareWarning& warning : more) prepared.warnings.push_back(std::move(warning));
  };
  append(detail::scale_warnings(prepared));
  append(detail::start_warnings(scene));
  return prepared;
}

}  // namespace khz::scene
