#include <khz/scene/content_key.hpp>

#include "names.hpp"
#include "option_tables.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/scene/procedural_shape.hpp>

#include <xxhash.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>

namespace khz::scene {
namespace {

using detail::canonical_options;
using detail::Json;

/// Bumped whenever a key's content or spelling changes, so old cache entries stop matching.
constexpr int key_version = 1;

Json vector_json(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

/// The mesh by content and format, never by path; a procedural shape by its canonical spec and
/// the generators' version.
Json mesh_json(const ObjectDescription& object) {
  if (!object.shape.empty()) {
    return {{"shape", object.shape}, {"generator_version", procedural_shape_version}};
  }
  std::string extension = object.mesh_path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  return {{"xxh3", file_hash_hex(object.mesh_path)}, {"extension", extension}};
}

/// How the body frame is made from the file's coordinates.
Json geometry_json(const ObjectDescription& object) {
  Json geometry = {{"centre", object.centre}};
  if (object.size) {
    geometry["size"] = *object.size;
  } else {
    geometry["scale"] = object.scale;
  }
  // Only when set, so that the keys of scenes written before the option are unchanged.
  if (object.fill_holes) geometry["fill_holes"] = true;
  return geometry;
}

Json field_json(const FieldDescription& field) {
  Json result = canonical_options(field.distance);
  result["soup"] = field.soup;
  if (field.soup) result["offset"] = field.offset;
  return result;
}

Json pointshell_json(const ObjectDescription& object) {
  const PointshellDescription& shell = object.pointshell;
  Json result = {{"method", detail::name_of(shell.method, detail::pointshell_methods)}};
  if (shell.method == PointshellMethod::repulsion) {
    result.update(canonical_options(shell.repulsion));
    result["field"] = field_json(object.field);  // the level set the points lie on
    return result;
  }
  // Key format 1 nests the schedule, beside the seed.
  result["seed"] = shell.nested.seed;
  result["schedule"] = canonical_options(shell.nested.schedule);
  if (shell.method == PointshellMethod::random) result["points"] = shell.count;
  if (shell.method == PointshellMethod::voxels) result["cell_size"] = shell.cell_size;
  return result;
}

Json meshing_json(const MeshingDescription& meshing) {
  Json result = meshing.method == MeshingMethod::voxels ? canonical_options(meshing.voxels)
                                                        : canonical_options(meshing.tetrahedra);
  result["method"] = detail::name_of(meshing.method, detail::meshing_methods);
  return result;
}

Json anchors_json(const std::vector<AnchorRegion>& anchors) {
  Json result = Json::array();
  for (const AnchorRegion& anchor : anchors) {
    if (anchor.kind == AnchorRegion::Kind::box) {
      result.push_back(
          {{"type", "box"}, {"min", vector_json(anchor.min)}, {"max", vector_json(anchor.max)}});
    } else {
      result.push_back({{"type", "half_space"},
                        {"point", vector_json(anchor.point)},
                        {"normal", vector_json(anchor.normal)}});
    }
  }
  return result;
}

Json basis_json(const BasisDescription& basis) {
  Json result;
  switch (basis.method) {
    case BasisMethod::modes:
      result = canonical_options(basis.modal);
      result["modal_derivatives"] = basis.modal_derivatives;
      if (!basis.modal_derivatives) result.erase("metric");  // the first r modes: no PCA
      break;
    case BasisMethod::sketch:
      result = canonical_options(basis.sketch);
      result["loads"] = file_hash_hex(basis.loads_path);
      break;
    case BasisMethod::simulation_data:
      result = canonical_options(basis.simulation_data);
      result["loads"] = file_hash_hex(basis.loads_path);
      result["simulation"] = canonical_options(basis.simulation);
      break;
  }
  result["method"] = detail::name_of(basis.method, detail::basis_methods);
  result["r"] = basis.basis_size();
  return result;
}

Json model_json(const ModelDescription& model) {
  return {{"meshing", meshing_json(model.meshing)},
          {"material", canonical_options(model.material)},
          {"anchors", anchors_json(model.anchors)},
          {"basis", basis_json(model.basis)}};
}

/// The key of one product as JSON (point trees nest the keys of their two inputs).
Json key_json(const ObjectDescription& object, Product product) {
  if (!needs_product(object, product)) {
    throw reduced::Error("content_key: object \"" + object.name + "\" has no " +
                         std::string(product_name(product)));
  }
  Json key = {{"key_version", key_version}, {"product", product_name(product)}};
  switch (product) {
    case Product::distance_field:
      key["mesh"] = mesh_json(object);
      key["geometry"] = geometry_json(object);
      key["field"] = field_json(object.field);
      break;
    case Product::pointshell:
      key["mesh"] = mesh_json(object);
      key["geometry"] = geometry_json(object);
      key["pointshell"] = pointshell_json(object);
      break;
    case Product::reduced_model:
      key["mesh"] = mesh_json(object);
      key["geometry"] = geometry_json(object);
      key["model"] = model_json(object.model);
      break;
  }
  return key;
}

std::string hex(XXH64_hash_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

std::string_view product_name(Product product) noexcept {
  switch (product) {
    case Product::distance_field:
      return "distance_field";
    case Product::pointshell:
      return "pointshell";
    case Product::reduced_model:
      return "reduced_model";
  }
  return "?";
}

bool needs_product(const ObjectDescription& object, Product product) noexcept {
  switch (product) {
    case Product::distance_field:
      return object.uses_field();
    case Product::pointshell:
      return object.roles.pointshell;
    case Product::reduced_model:
      return object.is_reduced();
  }
  return false;
}

std::string content_key(const ObjectDescription& object, Product product) {
  return key_json(object, product).dump();
}

std::string hash_hex(std::string_view text) { return hex(XXH3_64bits(text.data(), text.size())); }

std::string file_hash_hex(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw reduced::IoError("cannot read " + file.string() + " to hash it");
  const std::string bytes((std::istreambuf_iterator<char>(stream)),
                          std::istreambuf_iterator<char>());
  if (stream.bad()) throw reduced::IoError("cannot read " + file.string() + " to hash it");
  return hash_hex(bytes);
}

}  // namespace khz::scene
