#pragma once
// Preparing one object of a scene: each product it needs fetched through the product cache, in
// the order of PrepareStep. prepare_scene() runs one per object; a shared preparation
// (shared_preparation.hpp) runs one per product it computes.

#include "product_builders.hpp"

#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/stage_progress.hpp>
#include <khz/scene/body_mesh.hpp>
#include <khz/scene/content_key.hpp>
#include <khz/scene/prepare_scene.hpp>

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace khz::scene::detail {

/// A file extension without its leading dot, as ProductCache takes it.
inline std::string bare(std::string_view extension) { return std::string(extension.substr(1)); }

/// The volume mesh is stored as Gmsh text beside its reduced model, under the model's key.
inline constexpr std::string_view volume_mesh_extension = ".msh";

/// Prepares one object. Intermediate products (the surface mesh, the rest field, the
/// pointshell) are obtained on first use and kept for the later steps, so each is read or
/// computed at most once, and only if some step needs it.
class ObjectPreparer {
 public:
  ObjectPreparer(const ObjectDescription& object, ProductCache& cache,
                 const PrepareOptions& options, std::vector<PrepareRecord>& records,
                 std::vector<PrepareWarning>& warnings)
      : m_object(object),
        m_cache(cache),
        m_options(options),
        m_records(records),
        m_warnings(warnings) {}

  PreparedObject prepare() {
    PreparedObject prepared;
    if (m_object.is_reduced()) prepare_model(prepared);
    // Fetched before the pointshell, so that the records follow PrepareStep's order.
    if (m_object.roles.distance_field) field();
    if (m_object.roles.pointshell) prepare_tree(prepared);
    if (m_object.roles.distance_field) prepare_field(prepared);
    if (m_object.is_dynamic()) prepare_mass(prepared);
    return prepared;
  }

  /// The step last started: after a failure, the one that failed.
  PrepareStep step() const noexcept { return m_step; }

  /// A cache file of a product, and the step that fetches it.
  struct CacheFile {
    PrepareStep step;
    std::filesystem::path path;
  };

  /// The cache files of a cached product, in the order they are fetched: the volume mesh and
  /// the model for reduced_model, one file otherwise.
  std::vector<CacheFile> files(Product product) {
    if (product == Product::reduced_model) {
      return {
          {PrepareStep::volume_mesh, m_cache.file(std::string(step_name(PrepareStep::volume_mesh)),
                                                  key(product), bare(volume_mesh_extension))},
          {PrepareStep::reduced_model,
           m_cache.file(std::string(step_name(PrepareStep::reduced_model)), key(product),
                        bare(reduced::reduced_model_file_extension))}};
    }
    const auto [step, extension] = step_and_extension(product);
    return {{step, m_cache.file(std::string(step_name(step)), key(product), bare(extension))}};
  }

  /// Whether every file of `product` is in the cache.
  bool in_cache(Product product) {
    for (const CacheFile& file : files(product)) {
      if (!std::filesystem::exists(file.path)) return false;
    }
    return true;
  }

  /// Fetches one cached product (and what it is computed from) through the cache, computing
  /// and storing it when it is missing, as prepare() would. The object's other products are
  /// left alone.
  void make(Product product) {
    PreparedObject scratch;
    switch (product) {
      case Product::reduced_model:
        prepare_model(scratch);
        break;
      case Product::distance_field:
        field();
        break;
      case Product::pointshell:
        pointshell();
        break;
    }
  }

 private:
  using Clock = std::chrono::steady_clock;
  using Origin = PrepareRecord::Origin;

  static std::pair<PrepareStep, std::string_view> step_and_extension(Product product) {
    switch (product) {
      case Product::distance_field:
        return {PrepareStep::distance_field, contact::distance_field_file_extension};
      case Product::pointshell:
        return {PrepareStep::pointshell, contact::pointshell_file_extension};
      case Product::reduced_model:
        break;
    }
    return {PrepareStep::reduced_model, reduced::reduced_model_file_extension};
  }

  /// Forwards a library's reports to PrepareOptions::progress with the object and step.
  reduced::ProgressCallback progress(PrepareStep step) const {
    if (!m_options.progress) return {};
    return [this, step](const reduced::Progress& report) {
      return m_options.progress(m_object.name, step, report);
    };
  }

  const std::string& key(Product product) {
    auto found = m_keys.find(product);
    if (found == m_keys.end()) {
      found = m_keys.emplace(product, hash_hex(content_key(m_object, product))).first;
    }
    return found->second;
  }

  /// Whether the cache holds `product` (it will be read, not computed); makes its step the
  /// step under way.
  bool cached(Product product) {
    m_step = step_and_extension(product).first;
    return in_cache(product);
  }

  /// ProductCache::fetch() of the step's product under `product`'s key, recorded. `compute`
  /// may leave a note for the record.
  template <typename T>
  T fetch(PrepareStep step, Product product, std::string_view extension,
          const std::function<T(const std::filesystem::path&)>& read,
          const std::function<T(std::string&)>& compute,
          const std::function<void(const T&, const std::filesystem::path&)>& write) {
    m_step = step;
    const std::string& product_key = key(product);
    const reduced::ProgressCallback report = progress(step);
    std::string note;
    T result = m_cache.fetch<T>(
        std::string(step_name(step)), product_key, bare(extension),
        [&](const std::filesystem::path& file) {
          reduced::StageProgress stage(report, "reading", 1);
          T value = read(file);
          stage.finish();
          return value;
        },
        [&] { return compute(note); }, write);
    const ProductCache::Record& done = m_cache.records().back();
    if (!done.damaged.empty()) {
      m_warnings.push_back({m_object.name, "the cached " + std::string(step_name(step)) +
                                               " could not be used and was computed again (" +
                                               done.damaged + ")"});
    }
    m_records.push_back({m_object.name, step, done.computed ? Origin::computed : Origin::read,
                         done.seconds, done.file, done.computed ? note : std::string()});
    return result;
  }

  /// A product made anew every time (not cached), on the heap, recorded as built.
  template <typename T, typename Make>
  std::unique_ptr<T> build(PrepareStep step, const Make& make) {
    m_step = step;
    const Clock::time_point start = Clock::now();
    auto product = std::make_unique<T>(make());
    m_records.push_back({m_object.name,
                         step,
                         Origin::built,
                         std::chrono::duration<double>(Clock::now() - start).count(),
                         {},
                         {}});
    return product;
  }

  /// The body-frame surface mesh, read when a computation first needs it (its time counts to
  /// that computation).
  const reduced::TriangleMesh& surface() {
    if (!m_surface) {
      const reduced::ProgressCallback report = progress(m_step);
      reduced::StageProgress stage(report, "reading the surface mesh", 1);
      m_surface.emplace(read_body_mesh(m_object));
      stage.finish();
    }
    return *m_surface;
  }

  const contact::DistanceGrid& field() {
    if (!m_field) {
      m_field.emplace(fetch<contact::DistanceGrid>(
          PrepareStep::distance_field, Product::distance_field,
          contact::distance_field_file_extension,
          [](const std::filesystem::path& file) { return contact::read_distance_field(file); },
          [this](std::string&) {
            return detail::compute_distance_field(surface(), m_object.field,
                                                  progress(PrepareStep::distance_field));
          },
          [](const contact::DistanceGrid& grid, const std::filesystem::path& file) {
            contact::write_distance_field(file, grid);
          }));
    }
    return *m_field;
  }

  const contact::Pointshell& pointshell() {
    if (!m_pointshell) {
      const bool repulsion = m_object.pointshell.method == PointshellMethod::repulsion;
      // The field first when the pointshell will be computed from it, so that its time is not
      // counted as the pointshell's.
      if (repulsion && !cached(Product::pointshell)) {
        field();
      }
      m_pointshell.emplace(fetch<contact::Pointshell>(
          PrepareStep::pointshell, Product::pointshell, contact::pointshell_file_extension,
          [](const std::filesystem::path& file) { return contact::read_pointshell(file); },
          [this, repulsion](std::string& note) {
            return detail::compute_pointshell(surface(), m_object, repulsion ? &field() : nullptr,
                                              progress(PrepareStep::pointshell), note);
          },
          [](const contact::Pointshell& shell, const std::filesystem::path& file) {
            contact::write_pointshell(file, shell);
          }));
    }
    return *m_pointshell;
  }

  void prepare_model(PreparedObject& prepared) {
    // The volume mesh is the model's other half (the model file keeps only its fingerprint):
    // stored under the model's key, since the same inputs determine it.
    const reduced::VolumeMesh volume = fetch<reduced::VolumeMesh>(
        PrepareStep::volume_mesh, Product::reduced_model, volume_mesh_extension,
        [this](const std::filesystem::path& file) {
          return detail::read_volume_mesh_file(
              file, m_cache.file(std::string(step_name(PrepareStep::reduced_model)),
                                 key(Product::reduced_model),
                                 bare(reduced::reduced_model_file_extension)));
        },
        [this](std::string&) {
          return detail::compute_volume_mesh(surface(), m_object.model.meshing,
                                             progress(PrepareStep::volume_mesh));
        },
        detail::write_volume_mesh_file);
    reduced::ReducedModel model = fetch<reduced::ReducedModel>(
        PrepareStep::reduced_model, Product::reduced_model, reduced::reduced_model_file_extension,
        [&](const std::filesystem::path& file) {
          return reduced::read_reduced_model(file, volume);
        },
        [&](std::string& note) {
          return detail::compute_reduced_model(volume, m_object.model,
                                               progress(PrepareStep::reduced_model), note);
        },
        [&](const reduced::ReducedModel& computed, const std::filesystem::path& file) {
          reduced::write_reduced_model(file, computed, volume);
        });
    model.set_defaults(detail::integrator_defaults(m_object.model.integrator));
    prepared.embedding = std::make_unique<reduced::MeshEmbedding>(volume);
    prepared.model = std::make_unique<reduced::ReducedModel>(std::move(model));
  }

  // Neither tree is stored: a rigid one is its pointshell reordered (point_tree_file.hpp), and
  // a reduced one's modes are sampled from the model's basis faster than a file holding them
  // (48r bytes per point, 200 MB for the demo's dragon) is read: 0.3 s against 0.42 s.
  void prepare_tree(PreparedObject& prepared) {
    const contact::Pointshell& shell = pointshell();
    const reduced::ProgressCallback report = progress(PrepareStep::point_tree);
    if (!m_object.is_reduced()) {
      prepared.tree = build<contact::PointTree>(PrepareStep::point_tree,
                                                [&] { return contact::PointTree(shell, report); });
      return;
    }
    prepared.deformable_tree = build<contact::DeformablePointTree>(PrepareStep::point_tree, [&] {
      return contact::DeformablePointTree(contact::PointTree(shell, report), *prepared.embedding,
                                          prepared.model->basis().vectors, report);
    });
  }

  void prepare_field(PreparedObject& prepared) {
    // The last use of the rest field: it moves into the prepared object.
    contact::DistanceGrid rest = std::move(*m_field);
    m_field.reset();
    if (!m_object.is_reduced()) {
      prepared.field = std::make_unique<contact::DistanceGrid>(std::move(rest));
      return;
    }
    prepared.deformed_field =
        build<contact::DeformedDistanceField>(PrepareStep::deformed_field, [&] {
          contact::DeformedFieldOptions options = m_object.field.deformed;
          options.progress = progress(PrepareStep::deformed_field);
          std::vector<contact::DistanceGrid> fields;
          fields.push_back(std::move(rest));
          return contact::DeformedDistanceField(std::move(fields), *prepared.embedding,
                                                prepared.model->basis().vectors, options);
        });
  }

  void prepare_mass(PreparedObject& prepared) {
    prepared.mass_properties = build<reduced::MassProperties>(PrepareStep::mass_properties, [&] {
      const DynamicsDescription& dynamics = *m_object.dynamics;
      detail::require_closed_surface(surface(), "it has no mass or inertia as a free body",
                                     "give a closed mesh, or hold the object instead");
      const double density = dynamics.mass
                                 ? *dynamics.mass / reduced::mass_properties(surface(), 1.0).volume
                                 : dynamics.density;
      return reduced::mass_properties(surface(), density);
    });
  }

  const ObjectDescription& m_object;
  ProductCache& m_cache;
  const PrepareOptions& m_options;
  std::vector<PrepareRecord>& m_records;
  std::vector<PrepareWarning>& m_warnings;
  PrepareStep m_step = PrepareStep::volume_mesh;  // the step under way: a failure names it
  std::map<Product, std::string> m_keys;
  std::optional<reduced::TriangleMesh> m_surface;
  std::optional<contact::DistanceGrid> m_field;
  std::optional<contact::Pointshell> m_pointshell;
};

}  // namespace khz::scene::detail
