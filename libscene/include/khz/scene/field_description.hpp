#pragma once
// How an object's signed distance field is computed (and, for a reduced object, deformed).

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>

namespace khz::scene {

/// JSON object.field: the distance field of an object with the distance_field role, and the
/// level-set field a repulsion pointshell is fitted on (thesis §3.8.1, §3.11, §3.12). The
/// settings of the library's structs keep the library's defaults and names.
struct FieldDescription {
  /// "cells" (in [1, 32768]; the grid's memory budget, 1 GiB by default, is checked when the
  /// field is computed), "box_expansion" (≥ 1), "exact_band" (≥ √3): the grid of
  /// signed_distance_field(), and of polygon_soup_field() for soups. geometry,
  /// memory_budget_bytes and progress are not keys.
  contact::DistanceFieldOptions distance;
  /// "soup": the mesh is a polygon soup (open, non-manifold, self-intersecting): the field is
  /// signed by an offset surface (contact::polygon_soup_field) instead of the mesh itself
  /// (signed_distance_field).
  bool soup = false;
  /// "offset" (soups only): σ (m) of the soup's offset surface, ≥ 0, 0 for 1.4 grid spacings;
  /// PolygonSoupFieldOptions::offset, whose default it takes.
  double offset = contact::PolygonSoupFieldOptions{}.offset;
  /// A reduced object's deformed field (reduced objects with the distance_field role only):
  /// "proxies" (≥ neighbours), "neighbours" (k, in [2, 16]) and "seed". progress is not a key.
  contact::DeformedFieldOptions deformed;
};

}  // namespace khz::scene
