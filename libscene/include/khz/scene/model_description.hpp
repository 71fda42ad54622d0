#pragma once
// What an object is made of as a simulated body: rigid, or a reduced deformable model with its
// volume mesh, material, anchors, basis and integrator settings.

#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/scene/anchor_region.hpp>
#include <khz/scene/basis_description.hpp>

#include <vector>

namespace khz::scene {

/// JSON model.type.
enum class ModelType {
  rigid,    ///< "rigid": the object never deforms (the default).
  reduced,  ///< "reduced": a reduced nonlinear FEM model (ReducedModel), u = U q.
};

/// JSON model.meshing.method: how the simulation's volume mesh is made from the surface.
enum class MeshingMethod {
  voxels,      ///< "voxels": reduced::voxelize(), for any surface, soups included (the default).
  tetrahedra,  ///< "tetrahedra": reduced::tetrahedralize(), closed manifold surfaces only.
};

/// JSON model.meshing. The options of the chosen method; the JSON keys are their field names
/// (voxels: resolution, enlargement, fill_interior; tetrahedra: facet_size, facet_distance,
/// facet_angle, cell_size, cell_radius_edge_ratio, seed, sliver_bound, perturb, exude), with the
/// library's defaults. Lengths are metres, measured on the scaled surface.
struct MeshingDescription {
  MeshingMethod method = MeshingMethod::voxels;  ///< "method".
  reduced::VoxelizeOptions voxels;               ///< Used when method is voxels.
  reduced::TetrahedralizeOptions tetrahedra;     ///< Used when method is tetrahedra.
};

/// JSON model.material: one isotropic StVK material for the whole object
/// (reduced::Material::stvk). All three keys are required for a reduced model: the library has
/// no default material.
struct MaterialDescription {
  double young_modulus = 0.0;  ///< "young_modulus": E (Pa), > 0.
  double poisson_ratio = 0.0;  ///< "poisson_ratio": ν, in (−1, ½).
  double density = 0.0;        ///< "density": ρ (kg/m³), > 0.
};

/// JSON model. Everything but `type` applies to reduced models only; the reader refuses those
/// keys on a rigid object.
struct ModelDescription {
  ModelType type = ModelType::rigid;  ///< "type": "rigid" | "reduced".
  MeshingDescription meshing;         ///< "meshing".
  MaterialDescription material;       ///< "material" (required for reduced models).
  /// "anchors": regions whose volume-mesh vertices are held fixed (their union); empty for an
  /// unconstrained (free-floating, §2.8.7) object, the default.
  std::vector<AnchorRegion> anchors;
  BasisDescription basis;  ///< "basis".
  /// "integrator": the reduced Newmark settings the object runs with (ReducedNewmarkOptions;
  /// JSON keys time_step, beta, gamma, mass_damping, stiffness_damping — the NewmarkParameters
  /// — and max_newton_iterations, tolerance, acceleration_limit). time_step defaults to the
  /// loop's period 1 / loop.rate_hz, acceleration_limit to none (+∞); the rest are the
  /// library's defaults (Rayleigh damping α = β = 0: undamped).
  reduced::ReducedNewmarkOptions integrator;
};

}  // namespace khz::scene
