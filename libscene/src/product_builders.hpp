#pragma once
// How each product of scene preparation is computed from an object's description: the calls into
// libreduced and libcontact with the scene's settings mapped onto their options. Private to
// prepare_scene(), which decides what to compute and caches the results.

#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/pointshell/pointshell.hpp>
#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/scene/object_description.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::scene::detail {

/// Objects' sizes, the longest side of the body-frame bounding box their products give, outside
/// [min_plausible_extent, max_plausible_extent] metres or at least max_plausible_ratio times the
/// smallest object's: the signs of a mesh in other units than metres.
inline constexpr double min_plausible_extent = 1e-3, max_plausible_extent = 10.0;
inline constexpr double max_plausible_ratio = 100.0;

/// One warning per object whose size is implausible (see max_plausible_ratio), naming the
/// "scale" and "size" keys.
std::vector<PrepareWarning> scale_warnings(const PreparedScene& prepared);

/// A hand's device (not a hardware one) whose first reading, through the hand's mapping, is
/// turned more than this from the held object's orientation: the coupling would turn the object
/// into line with the hand at the start.
inline constexpr double max_start_turn_degrees = 10.0;

/// One warning per such hand, naming the held object and the "mapping" key.
std::vector<PrepareWarning> start_warnings(const SceneDescription& scene);

/// Nothing if `surface` bounds a volume (closed, edge-manifold, consistently oriented).
/// @throws reduced::MeshError "the mesh <problem>, so its inside is undefined and <needed_by>;
///         <remedy>", naming the first problem and pointing to khz info and khz repair.
void require_closed_surface(const reduced::TriangleMesh& surface, std::string_view needed_by,
                            std::string_view remedy);

/// The object's distance field from its body-frame surface: signed_distance_field(), or
/// polygon_soup_field()'s field for soups, with the field settings.
/// @throws reduced::MeshError, in the scene's terms, for a signed field of an open or
///         non-manifold surface (before computing it) or a field with "inside" nodes on its
///         box's faces (after).
contact::DistanceGrid compute_distance_field(const reduced::TriangleMesh& surface,
                                             const FieldDescription& field,
                                             const reduced::ProgressCallback& progress);

/// The object's pointshell by its method. Repulsion runs on the zero level set of `field` (not
/// null for repulsion; unused otherwise), with normals from `surface`, or for soups from the
/// field's zero isosurface (the offset surface). Non-convergence is not an error: `note` then
/// says which levels did not converge.
contact::Pointshell compute_pointshell(const reduced::TriangleMesh& surface,
                                       const ObjectDescription& object,
                                       const contact::DistanceGrid* field,
                                       const reduced::ProgressCallback& progress,
                                       std::string& note);

/// The volume mesh of model.meshing (voxelize() or tetrahedralize()) of the body-frame surface.
/// @throws reduced::MeshError, in the scene's terms, before tetrahedralizing a surface that does
///         not bound a volume.
reduced::VolumeMesh compute_volume_mesh(const reduced::TriangleMesh& surface,
                                        const MeshingDescription& meshing,
                                        const reduced::ProgressCallback& progress);

/// Writes `mesh` as Gmsh 2.2 text to `file`, whatever its extension (the product cache writes
/// to a temporary name), exactly: read back, its mesh_fingerprint() is the same.
/// @throws reduced::IoError naming the file if it cannot be written.
void write_volume_mesh_file(const reduced::VolumeMesh& mesh, const std::filesystem::path& file);

/// Reads a volume mesh write_volume_mesh_file() wrote. Its text has no checksum, so when
/// `model_file`, the reduced model computed on it, exists and is intact, the mesh must have the
/// fingerprint the model stores: a changed digit reads as another mesh.
/// @throws reduced::ParseError if the text is malformed or the fingerprints differ (damaged);
///         reduced::IoError if it cannot be read.
reduced::VolumeMesh read_volume_mesh_file(const std::filesystem::path& file,
                                          const std::filesystem::path& model_file);

/// The vertices of `mesh` inside any of the regions (sorted): the fixed vertices. Empty for no
/// regions. @throws reduced::Error if regions are given but select no vertex.
std::vector<int> anchored_vertices(const reduced::VolumeMesh& mesh,
                                   const std::vector<AnchorRegion>& regions);

/// The basis of the recipe: linear modes (the first r, or with modal derivatives and mass-PCA),
/// a sketch basis, or the mass-PCA of a FullNewmark run driven by the load file. `note` tells of
/// skipped static solves or unconverged simulation steps.
reduced::Basis compute_basis(const reduced::FemModel& fem, std::span<const int> fixed_vertices,
                             const BasisDescription& basis,
                             const reduced::ProgressCallback& progress, std::string& note);

/// The reduced model of `volume` as `model` describes it: FemModel with the StVK material, the
/// anchored vertices, compute_basis() and ReducedModel::precompute(). Integrator defaults are
/// the library's (they are set on the loaded model, and enter no key).
reduced::ReducedModel compute_reduced_model(const reduced::VolumeMesh& volume,
                                            const ModelDescription& model,
                                            const reduced::ProgressCallback& progress,
                                            std::string& note);

/// model.integrator as the defaults a ReducedModel carries (all but the acceleration limit).
reduced::ReducedIntegratorDefaults integrator_defaults(
    const reduced::ReducedNewmarkOptions& integrator);

}  // namespace khz::scene::detail
