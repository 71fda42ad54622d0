// The option tables of libcontact's structs: the scene's contact query.
#include "names.hpp"
#include "option_tables.hpp"

namespace khz::scene::detail {

template <>
const OptionTable<contact::ContactOptions>& option_table() {
  using O = contact::ContactOptions;
  // haptic_object is not a key: it is the held object's role. The reader reads the degradation
  // and coherence blocks itself: which of their keys apply depends on their mode.
  static const OptionTable<O> table{
      number("stiffness", &O::stiffness, above(0.0)),
      number("scaling_count", &O::scaling_count, above(0.0)),
      integer("max_level", &O::max_level, at_least(-1)),
      choice("gradient", &O::gradient, contact_gradients),
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
