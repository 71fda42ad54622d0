#include "product_builders.hpp"

#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/stage_progress.hpp>

#include <utility>

namespace khz::scene::detail {

reduced::ReducedModel compute_reduced_model(const reduced::VolumeMesh& volume,
                                            const ModelDescription& model,
                                            const reduced::ProgressCallback& progress,
                                            std::string& note) {
  reduced::StageProgress stage(progress, "FEM model", 1);
  const MaterialDescription& material = model.material;
  const reduced::FemModel fem(
      volume,
      {reduced::Material::stvk(material.young_modulus, material.poisson_ratio, material.density)});
  const std::vector<int> fixed_vertices = anchored_vertices(volume, model.anchors);
  stage.finish();
  reduced::Basis basis = compute_basis(fem, fixed_vertices, model.basis, progress, note);
  reduced::ReducedModelOptions options;
  options.progress = progress;
  return reduced::ReducedModel::precompute(fem, std::move(basis), options);
}

reduced::ReducedIntegratorDefaults integrator_defaults(
    const reduced::ReducedNewmarkOptions& integrator) {
  reduced::ReducedIntegratorDefaults defaults;
  defaults.newmark = integrator.newmark;
  defaults.max_newton_iterations = integrator.max_newton_iterations;
  defaults.newton_tolerance = integrator.tolerance;
  return defaults;
}

}  // namespace khz::scene::detail
