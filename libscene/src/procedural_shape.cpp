#include <khz/scene/procedural_shape.hpp>

#include "procedural_shapes.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <array>
#include <optional>

namespace khz::scene {
namespace {

/// A shape's name and its reader.
struct ShapeKind {
  std::string_view name;
  detail::ShapeGenerator (*read)(detail::ShapeArguments&);
};

/// Sorted by name.
constexpr std::array<ShapeKind, 3> shape_kinds{{
    {"alpha_tube", detail::read_alpha_tube},
    {"peg", detail::read_peg},
    {"plate_with_hole", detail::read_plate_with_hole},
}};

constexpr std::array<std::string_view, shape_kinds.size()> shape_names = [] {
  std::array<std::string_view, shape_kinds.size()> names;
  for (std::size_t i = 0; i < names.size(); ++i) names[i] = shape_kinds[i].name;
  return names;
}();

/// A spec read: its canonical text and its mesh's generator.
struct ReadSpec {
  std::string canonical;
  detail::ShapeGenerator generate;
};

ReadSpec read_spec(std::string_view spec) {
  const std::size_t colon = spec.find(':');
  const std::string_view name = spec.substr(0, colon);
  const auto kind = std::find_if(shape_kinds.begin(), shape_kinds.end(),
                                 [name](const ShapeKind& entry) { return entry.name == name; });
  if (kind == shape_kinds.end()) {
    throw reduced::Error(detail::unknown_name_message("shape", name, shape_names));
  }
  detail::ShapeArguments arguments(
      name, colon == std::string_view::npos ? std::nullopt : std::optional(spec.substr(colon + 1)));
  ReadSpec result;
  result.generate = kind->read(arguments);
  arguments.refuse_unknown();
  result.canonical = arguments.canonical();
  return result;
}

}  // namespace

std::span<const std::string_view> procedural_shape_names() noexcept { return shape_names; }

std::string canonical_shape_spec(std::string_view spec) { return read_spec(spec).canonical; }

reduced::TriangleMesh procedural_shape(std::string_view spec) { return read_spec(spec).generate(); }

}  // namespace khz::scene
