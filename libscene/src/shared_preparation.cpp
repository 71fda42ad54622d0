#include "shared_preparation.hpp"

#include "object_preparer.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/scene/prepare_error.hpp>

#include <algorithm>
#include <exception>
#include <set>
#include <string>

namespace khz::scene::detail {
namespace {

/// One missing cached product and the round it is computed in: 0 for what is made from the
/// mesh alone, 1 for pointshells (a repulsion pointshell samples the field).
struct Task {
  std::size_t object = 0;
  Product product = Product::distance_field;
  int round = 0;
  std::vector<ObjectPreparer::CacheFile> files;
};
constexpr int rounds = 2;

/// The products missing from the cache, as prepare_scene() would compute them, each once.
std::vector<Task> missing_products(const SceneDescription& scene, ProductCache& cache,
                                   const PrepareOptions& options) {
  std::vector<Task> tasks;
  std::set<std::filesystem::path> listed;  // objects with equal inputs share one file
  std::vector<PrepareRecord> unused_records;
  std::vector<PrepareWarning> unused_warnings;
  for (std::size_t index = 0; index < scene.objects.size(); ++index) {
    const ObjectDescription& object = scene.objects[index];
    ObjectPreparer preparer(object, cache, options, unused_records, unused_warnings);
    const auto add = [&](bool missing, Product product, int round) {
      if (!missing) return;
      std::vector<ObjectPreparer::CacheFile> files = preparer.files(product);
      if (listed.insert(files.back().path).second) tasks.push_back({index, product, round, files});
    };
    const bool reduced = object.is_reduced();
    const bool shell = object.roles.pointshell && !preparer.in_cache(Product::pointshell);
    const bool repulsion = object.pointshell.method == PointshellMethod::repulsion;
    add(reduced && !preparer.in_cache(Product::reduced_model), Product::reduced_model, 0);
    add((object.roles.distance_field || (shell && repulsion)) &&
            !preparer.in_cache(Product::distance_field),
        Product::distance_field, 0);
    add(shell, Product::pointshell, 1);
  }
  return tasks;
}

/// Collective: whether every process lists the same products (their count and a hash of their
/// file names), so that all deal them out alike.
bool same_list_everywhere(reduced::WorkGroup& group, const std::vector<Task>& tasks) {
  std::string names;
  for (const Task& task : tasks)
    names += task.files.back().path.filename().string() + '\n';  // not where it is mounted
  // 40 bits of the hash: exact in a double, as the sum below needs.
  const double mine[2] = {
      static_cast<double>(tasks.size()),
      static_cast<double>(std::stoull(hash_hex(names).substr(0, 10), nullptr, 16))};
  std::vector<double> all(2 * static_cast<std::size_t>(group.size()), 0.0);
  std::copy(mine, mine + 2, all.begin() + 2 * group.rank());
  group.sum(all);
  for (std::size_t at = 0; at < all.size(); at += 2) {
    if (all[at] != mine[0] || all[at + 1] != mine[1]) return false;
  }
  return true;
}

std::string group_text(const reduced::WorkGroup& group) {
  return std::to_string(group.size()) + " processes";
}

}  // namespace

std::vector<SharedFile> compute_shared_products(const SceneDescription& scene, ProductCache& cache,
                                                const PrepareOptions& options,
                                                reduced::WorkGroup& group,
                                                std::vector<PrepareWarning>& warnings) {
  // Listing reads every mesh (content keys): a mesh one process cannot read must stop all of
  // them here, before the collectives below.
  std::vector<Task> tasks;
  reduced::GroupStatus listed;
  std::exception_ptr listing_failure;
  try {
    tasks = missing_products(scene, cache, options);
  } catch (const std::exception& error) {
    listed.state = reduced::GroupStatus::State::failed;
    listed.message = error.what();
    listing_failure = std::current_exception();
  }
  reduced::stop_unless_running(group.checkpoint(listed), group.rank(), group.size(),
                               "preparing the scene", listing_failure);
  if (!same_list_everywhere(group, tasks)) {
    throw reduced::Error(
        "preparing the scene over " + group_text(group) +
        ": the processes find different products missing from their caches; give every process "
        "the same scene and the same cache directory, on a file system they all see");
  }
  std::vector<SharedFile> written;
  std::vector<std::size_t> first_file;  // index into `written` of each task's first file
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    first_file.push_back(written.size());
    const int rank = static_cast<int>(t % static_cast<std::size_t>(group.size()));
    const std::string& object = scene.objects[tasks[t].object].name;
    for (const ObjectPreparer::CacheFile& file : tasks[t].files) {
      written.push_back({object, file.step, file.path, rank, 0.0, {}});
    }
  }
  for (int round = 0; round < rounds; ++round) {
    reduced::GroupStatus mine;
    std::exception_ptr own_failure;
    bool any = false;
    for (std::size_t t = 0; t < tasks.size(); ++t) {
      if (tasks[t].round != round) continue;
      any = true;
      if (written[first_file[t]].rank != group.rank()) continue;
      if (mine.state != reduced::GroupStatus::State::running) continue;
      const ObjectDescription& object = scene.objects[tasks[t].object];
      std::vector<PrepareRecord> records;
      ObjectPreparer preparer(object, cache, options, records, warnings);
      try {
        preparer.make(tasks[t].product);
      } catch (const reduced::Cancelled& cancel) {
        mine.state = reduced::GroupStatus::State::cancelled;
        mine.message = cancel.what();
      } catch (const std::exception& error) {
        try {
          std::throw_with_nested(PrepareError(object.name, preparer.step(), error.what()));
        } catch (const PrepareError& failure) {
          mine.state = reduced::GroupStatus::State::failed;
          mine.message = failure.what();
          own_failure = std::current_exception();
        }
      }
      for (const PrepareRecord& record : records) {
        const auto end =
            written.begin() + static_cast<std::ptrdiff_t>(first_file[t] + tasks[t].files.size());
        const auto file = std::find_if(written.begin() + first_file[t], end,
                                       [&](const SharedFile& f) { return f.file == record.file; });
        if (record.origin != PrepareRecord::Origin::computed || file == end) continue;
        file->seconds = record.seconds;
        file->note = record.note;
      }
    }
    if (!any) continue;
    reduced::stop_unless_running(group.checkpoint(mine), group.rank(), group.size(),
                                 "preparing the scene", own_failure);
  }
  std::vector<double> shared(written.size() + 1, 0.0);  // seconds, then files not seen
  for (std::size_t f = 0; f < written.size(); ++f) {
    if (written[f].rank == group.rank()) shared[f] = written[f].seconds;
    if (!std::filesystem::exists(written[f].file)) shared.back() += 1.0;
  }
  group.sum(shared);
  if (shared.back() > 0.0) {
    throw reduced::Error("preparing the scene over " + group_text(group) +
                         ": some processes do not see the products the others wrote; give every "
                         "process the same cache directory, on a file system they all see");
  }
  for (std::size_t f = 0; f < written.size(); ++f) written[f].seconds = shared[f];
  return written;
}

}  // namespace khz::scene::detail
