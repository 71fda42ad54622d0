// The option tables of libcontact's structs: an object's field and pointshell, and the scene's
// contact query.
#include "names.hpp"
#include "option_tables.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace khz::scene::detail {

template <>
const OptionTable<contact::DistanceFieldOptions>& option_table() {
  using O = contact::DistanceFieldOptions;
  // Not keys: geometry (the cube around the mesh is the scene's grid), memory_budget_bytes (the
  // library's budget is checked when the field is computed) and progress.
  static const OptionTable<O> table{
      integer("cells", &O::cells, closed(1, 32768)),
      number("box_expansion", &O::box_expansion, at_least(1.0)),
      number("exact_band", &O::exact_band,
             with_text(at_least(std::sqrt(3.0)), "a number ≥ √3 ≈ 1.732 (cell spacings)")),
  };
  return table;
}

template <>
const OptionTable<contact::DeformedFieldOptions>& option_table() {
  using O = contact::DeformedFieldOptions;
  // neighbours first: the proxies' lower bound is the neighbours read.
  static const OptionTable<O> table{
      integer("neighbours", &O::neighbours, closed(2, O::max_neighbours)),
      integer("proxies", &O::proxies,
              [](const O& options) {
                return with_text(
                    at_least(static_cast<double>(options.neighbours)),
                    "an integer ≥ neighbours (" + std::to_string(options.neighbours) + ")");
              }),
      seed("seed", &O::seed),
  };
  return table;
}

template <>
const OptionTable<contact::RepulsionOptions>& option_table() {
  using O = contact::RepulsionOptions;
  // Not keys: projection_tolerance (its automatic value suits any grid) and progress. The
  // reader also accepts "points", the total over all levels, instead of first_level_points.
  static const OptionTable<O> table{
      seed("seed", &O::seed),
      integer("levels", &O::levels, at_least(1)),
      integer("first_level_points", &O::first_level_points, at_least(1)),
      integer("max_iterations", &O::max_iterations, at_least(1)),
      number("tolerance", &O::tolerance, open_interval(0.0, 1.0)),
      number("radius_factor", &O::radius_factor, closed(1.0, 4.0)),
  };
  return table;
}

template <>
const OptionTable<contact::LevelSchedule>& option_table() {
  using O = contact::LevelSchedule;
  // The file names them as repulsion's settings; content keys kept the library's names.
  static const OptionTable<O> table{
      integer("first_level_points", &O::first_level_size, at_least(1))
          .named_in_keys("first_level_size"),
      integer("growth", &O::growth, at_least(2)),
      integer("levels", &O::max_levels, at_least(0)).named_in_keys("max_levels"),
  };
  return table;
}

template <>
const OptionTable<contact::NestedLevelOptions>& option_table() {
  using O = contact::NestedLevelOptions;
  static const OptionTable<O> table = [] {
    std::vector<OptionEntry<O>> entries{seed("seed", &O::seed)};
    for (OptionEntry<O>& entry : within(&O::schedule, option_table<contact::LevelSchedule>())) {
      entries.push_back(std::move(entry));
    }
    return OptionTable<O>(std::move(entries));
  }();
  return table;
}

template <>
const OptionTable<contact::ContactOptions>& option_table() {
  using O = contact::ContactOptions;
  // haptic_object is not a key: it is the held object's role. The reader reads the degradation,
  // coherence and friction blocks itself: which of their keys apply depends on their mode, and
  // friction is also read per pair.
  static const OptionTable<O> table{
      number("stiffness", &O::stiffness, above(0.0)),
      number("scaling_count", &O::scaling_count, above(0.0)),
      integer("max_level", &O::max_level, at_least(-1)),
      choice("gradient", &O::gradient, contact_gradients),
      number("onset_depth", &O::onset_depth, at_least(0.0)),
      number("onset_voxels", &O::onset_voxels, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<contact::DegradationOptions>& option_table() {
  using O = contact::DegradationOptions;
  static const OptionTable<O> table{
      choice("mode", &O::mode, degradation_modes),
      number("warm_threshold", &O::warm_threshold, above(0.0)),
      number("budget_microseconds", &O::budget_microseconds, above(0.0)),
      number("cold_fraction", &O::cold_fraction, open_closed(0.0, 1.0)),
      number("contact_weight", &O::contact_weight, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<contact::FrictionOptions>& option_table() {
  using O = contact::FrictionOptions;
  static const OptionTable<O> table{
      number("static", &O::static_coefficient, at_least(0.0)),
      number("kinetic", &O::kinetic_coefficient, at_least(0.0)),
      number("stick_distance", &O::stick_distance, above(0.0)),
  };
  return table;
}

template <>
const OptionTable<contact::CoherenceOptions>& option_table() {
  using O = contact::CoherenceOptions;
  static const OptionTable<O> table{
      flag("enabled", &O::enabled),
      number("max_translation", &O::max_translation, at_least(0.0)),
      number("max_rotation", &O::max_rotation, at_least(0.0)),
      number("max_deformation", &O::max_deformation, at_least(0.0)),
      number("max_field_deformation", &O::max_field_deformation, at_least(0.0)),
      integer("max_skip", &O::max_skip, closed(1, 1 << 20)),
  };
  return table;
}

}  // namespace khz::scene::detail
