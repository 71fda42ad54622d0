#pragma once
// Signed distance fields of polygon soups through an offset surface (thesis §3.11, §3.8.1).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>

namespace khz::contact {

/// Options of polygon_soup_field().
struct PolygonSoupFieldOptions {
  /// Grid, band, budget and progress of both fields the pipeline computes.
  DistanceFieldOptions field;
  /// σ (m): the offset surface is {unsigned distance = σ}. 0 picks 1.4 grid spacings, the
  /// thesis's value for thin structures (Fig. 3.15); it must exceed the spacing to stay smooth.
  double offset = 0.0;
};

/// What polygon_soup_field() made.
struct PolygonSoupField {
  /// Signed distance to `offset_surface` on the grid of the unsigned field: negative within σ
  /// of the soup (and in closed cavities the soup encloses), positive outside.
  DistanceGrid field;
  /// The closed offset surface the field is signed by: the outer components of the level set
  /// σ, oriented outward.
  TriangleMesh offset_surface;
  int components_removed = 0;  ///< Level-set components that lay inside others (inner walls).
  double offset = 0.0;         ///< σ used (m).
};

/// Signed field of a triangle soup: unsigned field → level set at σ (isosurface()) → removal of
/// every connected component lying inside another one (the inner side of the offset shell
/// around a closed or nearly closed soup) → signed_distance_field() of what remains.
///
/// Inside-ness is decided on the grid, not by geometric ray or winding tests: a component is
/// kept exactly when its larger-value side is the free region {U > σ} connected to the box's
/// boundary (a flood fill over the nodes, along the isosurface's tetrahedron edges). Those are
/// the components inside no other, and the kept ones face that region, so they are outward.
/// Holes in the soup narrower than about 2σ close; wider ones join the inner and outer walls
/// into one surface, which is kept (the field is then not "solid" there).
///
/// Both fields use one grid: `options.field.geometry`, or the cube around all of the soup's
/// vertices that unsigned_distance_field() would choose. Costs: the two fields dominate; the
/// level set and the flood fill take a fraction of a second at 256³.
/// @throws MeshError, Error, Cancelled as signed_distance_field(); Error if σ ≤ spacing, if the
///         σ-surface reaches the grid's boundary (some boundary node within σ of the soup:
///         raise box_expansion), or no level-set component remains.
KHZ_CONTACT_API PolygonSoupField polygon_soup_field(const TriangleMesh& soup,
                                                    const PolygonSoupFieldOptions& options = {});

}  // namespace khz::contact
