#pragma once
// Content keys: the canonical text of exactly the inputs that determine one precomputed product
// of an object, so a cache can hash it and reuse the product across scenes that differ only in
// something else (names, poses, contact, coupling, device, loop, integrator settings).

#include <khz/scene/export.hpp>
#include <khz/scene/object_description.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::scene {

/// The precomputed products of an object.
enum class Product {
  /// The signed distance field (.khzsdf), or a soup's PolygonSoupField. Inputs: the mesh
  /// file's bytes and extension (a procedural shape's canonical spec and
  /// procedural_shape_version instead), scale or size, centre, and field.cells, box_expansion,
  /// exact_band, soup (and offset for soups).
  distance_field,
  /// The pointshell (.khzshell). Inputs: the mesh, scale or size, centre and the pointshell
  /// settings of its method (repulsion: first_level_points, levels, seed, max_iterations,
  /// tolerance, radius_factor, plus the distance_field inputs, whose zero level set it samples;
  /// vertices: the level schedule and seed; random: points, the schedule and seed; voxels:
  /// cell_size, the schedule and seed).
  pointshell,
  /// The reduced model (.khzmodel): the mesh, scale or size, centre, model.meshing (method and
  /// its options), model.material, model.anchors (in order) and model.basis (method, r and the
  /// method's settings, with the load file's bytes for sketch and simulation_data). Not the
  /// integrator settings: they can be set on a loaded model (ReducedModel::set_defaults()).
  reduced_model,
};

/// "distance_field", "pointshell" or "reduced_model".
KHZ_SCENE_API std::string_view product_name(Product product) noexcept;

/// Whether the object needs `product`: distance_field when uses_field(), pointshell for the
/// pointshell role, reduced_model for a reduced model.
KHZ_SCENE_API bool needs_product(const ObjectDescription& object, Product product) noexcept;

/// The canonical JSON text of the inputs of `product` (see Product): sorted keys, no spaces,
/// numbers as the shortest text that reads back to the same double, every default written out,
/// and a key format version; files enter as the XXH3-64 of their bytes, never by path, so
/// moving or renaming a file keeps the key, and a procedural mesh ("shape:SPEC") enters as its
/// canonical spec (ObjectDescription::shape) with procedural_shape_version. Equal texts ⇔ equal
/// inputs.
/// @throws reduced::Error if the object does not need the product (needs_product());
///         reduced::IoError if the mesh or load file cannot be read.
KHZ_SCENE_API std::string content_key(const ObjectDescription& object, Product product);

/// XXH3-64 of `text` as 16 lowercase hexadecimal digits: a cache file name for a content key.
KHZ_SCENE_API std::string hash_hex(std::string_view text);

/// XXH3-64 of a file's bytes as 16 lowercase hexadecimal digits.
/// @throws reduced::IoError if the file cannot be read.
KHZ_SCENE_API std::string file_hash_hex(const std::filesystem::path& file);

}  // namespace khz::scene
