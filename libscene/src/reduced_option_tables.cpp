// The option tables of libreduced's structs, and of the scene's own structs that map onto
// libreduced: an object's model.
#include "names.hpp"
#include "option_tables.hpp"

#include <utility>
#include <vector>

namespace khz::scene::detail {

template <>
const OptionTable<reduced::VoxelizeOptions>& option_table() {
  using O = reduced::VoxelizeOptions;
  static const OptionTable<O> table{
      integer("resolution", &O::resolution, closed(1, 1024)),
      number("enlargement", &O::enlargement, at_least(1.0)),
      flag("fill_interior", &O::fill_interior),
  };
  return table;
}

template <>
const OptionTable<reduced::TetrahedralizeOptions>& option_table() {
  using O = reduced::TetrahedralizeOptions;
  static const OptionTable<O> table{
      number("facet_size", &O::facet_size, at_least(0.0)),
      number("facet_distance", &O::facet_distance, at_least(0.0)),
      number("facet_angle", &O::facet_angle, closed(0.0, 30.0)),
      number("cell_size", &O::cell_size, at_least(0.0)),
      number("cell_radius_edge_ratio", &O::cell_radius_edge_ratio, at_least(2.0)),
      integer("seed", &O::seed, at_least(0.0)),
      number("sliver_bound", &O::sliver_bound, at_least(0.0)),
      flag("perturb", &O::perturb),
      flag("exude", &O::exude),
  };
  return table;
}

template <>
const OptionTable<reduced::ReducedNewmarkOptions>& option_table() {
  using O = reduced::ReducedNewmarkOptions;
  using Newmark = reduced::NewmarkParameters;
  // The file writes the NewmarkParameters flat, beside the integrator's own settings.
  static const OptionTable<O> table{
      within(&O::newmark, number("time_step", &Newmark::time_step, above(0.0))),
      within(&O::newmark, number("beta", &Newmark::beta, open_closed(0.0, 0.5))),
      within(&O::newmark, number("gamma", &Newmark::gamma, closed(0.0, 1.0))),
      within(&O::newmark, number("mass_damping", &Newmark::mass_damping, at_least(0.0))),
      within(&O::newmark, number("stiffness_damping", &Newmark::stiffness_damping, at_least(0.0))),
      integer("max_newton_iterations", &O::max_newton_iterations, at_least(1)),
      number("tolerance", &O::tolerance, above(0.0)),
      number("acceleration_limit", &O::acceleration_limit, above(0.0)),
  };
  return table;
}

template <>
const OptionTable<reduced::StaticSolveOptions>& option_table() {
  using O = reduced::StaticSolveOptions;
  static const OptionTable<O> table{
      integer("load_steps", &O::load_steps, at_least(1)),
      integer("max_iterations", &O::max_iterations, at_least(1)),
      number("tolerance", &O::tolerance, above(0.0)),
      flag("line_search", &O::line_search),
  };
  return table;
}

template <>
const OptionTable<reduced::LinearModesOptions>& option_table() {
  using O = reduced::LinearModesOptions;
  static const OptionTable<O> table{
      integer("k", &O::num_modes, at_least(1)),
      choice("mass", &O::mass, mass_lumpings),
      number("tolerance", &O::tolerance, at_least(0.0)),
      integer("max_restarts", &O::max_restarts, at_least(1)),
  };
  return table;
}

template <>
const OptionTable<reduced::ModalDerivativeBasisOptions>& option_table() {
  using O = reduced::ModalDerivativeBasisOptions;
  // r (basis_size) is read by the reader: its bound depends on k and on the anchors.
  static const OptionTable<O> table = [] {
    std::vector<OptionEntry<O>> entries =
        within(&O::modes, option_table<reduced::LinearModesOptions>());
    entries.push_back(choice("metric", &O::metric, pca_metrics));
    return OptionTable<O>(std::move(entries));
  }();
  return table;
}

template <>
const OptionTable<reduced::SketchBasisOptions>& option_table() {
  using O = reduced::SketchBasisOptions;
  // r (basis_size) is read by the reader, before the load file, as for simulation_data.
  static const OptionTable<O> table{
      choice("metric", &O::metric, pca_metrics),
      number("rank_tolerance", &O::rank_tolerance, half_open(0.0, 1.0)),
      number("force_separation", &O::force_separation, at_least(0.0)),
      number("force_kernel_width", &O::force_kernel_width, at_least(0.0)),
      number("deformation_separation", &O::deformation_separation, at_least(0.0)),
      number("deformation_kernel_width", &O::deformation_kernel_width, at_least(0.0)),
      block("static_solve", &O::static_solve, option_table<reduced::StaticSolveOptions>()),
      flag("skip_failed_solves", &O::skip_failed_solves),
  };
  return table;
}

template <>
const OptionTable<reduced::SimulationDataBasisOptions>& option_table() {
  using O = reduced::SimulationDataBasisOptions;
  static const OptionTable<O> table{
      choice("metric", &O::metric, pca_metrics),
      number("rank_tolerance", &O::rank_tolerance, half_open(0.0, 1.0)),
      number("fixed_tolerance", &O::fixed_tolerance, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<MaterialDescription>& option_table() {
  using O = MaterialDescription;
  // The library has no default material: every key is required.
  static const OptionTable<O> table{
      required_number("young_modulus", &O::young_modulus, above(0.0), "E in Pa"),
      required_number("poisson_ratio", &O::poisson_ratio, open_interval(-1.0, 0.5), "ν in (−1, ½)"),
      required_number("density", &O::density, above(0.0), "ρ in kg/m³"),
  };
  return table;
}

template <>
const OptionTable<SimulationRunDescription>& option_table() {
  using O = SimulationRunDescription;
  using Full = reduced::FullNewmarkOptions;
  using Newmark = reduced::NewmarkParameters;
  const auto newmark = [](OptionEntry<Newmark> entry) {
    return within(&O::integrator, within(&Full::newmark, std::move(entry)));
  };
  static const OptionTable<O> table{
      required_integer("hold_steps", &O::hold_steps, at_least(1), "steps each load is applied"),
      integer("release_steps", &O::release_steps, at_least(0)),
      integer("snapshot_every", &O::snapshot_every, at_least(1)),
      newmark(number("time_step", &Newmark::time_step, above(0.0))),
      within(&O::integrator,
             integer("max_newton_iterations", &Full::max_newton_iterations, at_least(1))),
      newmark(number("mass_damping", &Newmark::mass_damping, at_least(0.0))),
      newmark(number("stiffness_damping", &Newmark::stiffness_damping, at_least(0.0))),
  };
  return table;
}

}  // namespace khz::scene::detail
