#pragma once
// Scene preparation (issue 9): for every object, exactly the products its roles and model need,
// each read from the product cache when its content key is there and computed (and stored)
// otherwise. See docs/SCENES.md, "Preparing a scene".

#include <khz/reduced/progress.hpp>
#include <khz/reduced/work_group.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/prepare_error.hpp>
#include <khz/scene/prepared_scene.hpp>
#include <khz/scene/product_cache.hpp>
#include <khz/scene/scene_description.hpp>

#include <functional>
#include <string>

namespace khz::scene {

/// Receives the progress of every stage prepare_scene() runs: the object's name, the step, and
/// the library's report (reduced::Progress: stage name, done, total). Steps the libraries do not
/// report on (reading a product, meshing, the FEM set-up) report one stage of one unit. Called
/// from the preparing thread; return false to cancel (prepare_scene() then throws
/// reduced::Cancelled within one unit of work, and the cache keeps no partial file).
using PrepareProgress = std::function<bool(const std::string& object, PrepareStep step,
                                           const reduced::Progress& progress)>;

/// Options of prepare_scene().
struct PrepareOptions {
  PrepareProgress progress;  ///< Empty: no reports, never cancelled.
  /// The processes that share the preparation (e.g. the ranks of an MPI job through
  /// khz::mpi::MpiWorkGroup), each calling prepare_scene() with the same scene and the same
  /// cache directory on a file system they all see. Null (or a group of one): this process
  /// alone. See prepare_scene(), "Shared preparation".
  reduced::WorkGroup* group = nullptr;
};

/// Prepares every object of `scene` (a description from read_scene()) in order. Everything is
/// made from the object's surface mesh in its body frame (read_body_mesh(); read only when some
/// product must be computed) and is in that frame (m). Per object, as needs_product() decides:
/// - reduced model: the volume mesh (voxelize or tetrahedralize with model.meshing) → FemModel
///   with the StVK material → the anchored vertices (every volume-mesh vertex inside an anchor
///   region) → the basis (linear modes, with modal derivatives and mass-PCA; a sketch basis
///   from the load file; or the mass-PCA of a FullNewmark run) → ReducedModel::precompute().
///   The volume mesh is cached as a second file under the reduced model's key. The integrator
///   defaults are then set from model.integrator (they enter no key);
/// - distance field: signed_distance_field(), or polygon_soup_field() for soups, with the
///   field settings;
/// - pointshell: repulsion on the field's zero level set (normals from the surface mesh, or
///   from the field's zero isosurface for soups), or vertex / random / voxel samples nested by
///   farthest-point order;
/// - point tree: built from the pointshell every time, never stored: a rigid pointshell's
///   PointTree (the pointshell in another order, 0.09 s for 256k points), a reduced one's
///   DeformablePointTree with modes sampled from the embedding and the basis (0.3 s for the
///   demo's 262k-point dragon at r = 15, where reading a file of its modes took 0.42 s);
/// - deformed field (reduced objects with the distance_field role): DeformedDistanceField from
///   the rest field, the embedding and the basis with the field's proxies, neighbours and seed;
///   built every time (no file format; 0.2 s for a 40-proxy dino at r = 15).
/// Every cached product is fetched with ProductCache::fetch() under the file name
/// `<step name>-<hash_hex(content_key(object, product))>.<extension>`: the object's name is
/// not part of it, so objects (and scenes) with equal inputs share one file. A product is only
/// fetched when this preparation needs it: a repulsion pointshell's field is not read when the
/// pointshell is cached and the object has no distance_field role, nor a reduced pointshell's
/// pointshell when its tree is cached.
///
/// Objects with the same inputs in the same scene: the second reads what the first computed.
///
/// Shared preparation (options.group of more than one process): first the cached products
/// missing from the cache are computed, each by one process, in two rounds (reduced models
/// and distance fields; then pointshells, which sample the fields), the products of a round
/// dealt to the processes in turn, with a checkpoint of the group after each round; then every
/// process prepares the scene as above, reading them all. The files are the ones one process would
/// write, under the same names; a later preparation by one process computes nothing. The records of
/// products computed in the first part say which process computed them (PrepareRecord::rank) and
/// how long it took; a computed product's note is kept only by the process that computed it. A
/// failure or a cancel on any process ends the call on every process at the next checkpoint: the
/// failing process throws its own PrepareError, the others a reduced::Error that names it; a cancel
/// gives Cancelled everywhere. A process that dies (killed, out of memory) ends the job through the
/// launcher (mpiexec), as for any MPI program; the temporary file it was writing is removed by the
/// next preparation with this cache on the same host (ProductCache).
///
/// Then PreparedScene::warnings gets one entry per object whose size (the longest side of its
/// pointshell's or field's body-frame box) is below 1 mm, above 10 m, or at least 100 times the
/// smallest object's: most likely a mesh in millimetres (or other units) read as metres; and one
/// per hand whose device (not a hardware one: its first reading, through the hand's mapping)
/// starts turned more than 10° from the object it holds, which the coupling would turn into line
/// at the start.
/// @throws PrepareError naming the object and step, with the original exception nested
///         (std::throw_with_nested), for any failure: a mesh or load file that cannot be read,
///         a product file that is corrupt or belongs to another mesh, an invalid mesh, an
///         anchor set that selects no vertex, a solver failure; reduced::Cancelled, unchanged,
///         if options.progress cancels; reduced::Error, in a shared preparation, when another
///         process failed, or when the processes do not see the same cache directory.
KHZ_SCENE_API PreparedScene prepare_scene(const SceneDescription& scene, ProductCache& cache,
                                          const PrepareOptions& options = {});

}  // namespace khz::scene
