#include <khz/contact/query/contact_options.hpp>

#include <cmath>
#include <string>

namespace khz::contact {
namespace {

void require(bool valid, const std::string& name, double value, const std::string& expected) {
  if (!valid) {
    throw Error("ContactOptions: " + name + " must be " + expected + ", got " +
                std::to_string(value));
  }
}

bool finite_positive(double value) { return std::isfinite(value) && value > 0.0; }
bool finite_non_negative(double value) { return std::isfinite(value) && value >= 0.0; }

}  // namespace

void ContactOptions::validate() const {
  require(finite_positive(stiffness), "stiffness", stiffness, "finite and > 0 (N/m)");
  require(finite_positive(scaling_count), "scaling_count", scaling_count, "finite and > 0");
  require(max_level >= -1, "max_level", max_level, "≥ −1");
  require(finite_non_negative(onset_depth), "onset_depth", onset_depth,
          "finite and ≥ 0 (m; 0: onset_voxels times the field's voxel)");
  require(finite_non_negative(onset_voxels), "onset_voxels", onset_voxels, "finite and ≥ 0");
  const DegradationOptions& d = degradation;
  require(finite_positive(d.warm_threshold), "degradation.warm_threshold", d.warm_threshold,
          "finite and > 0");
  require(finite_positive(d.budget_microseconds), "degradation.budget_microseconds",
          d.budget_microseconds, "finite and > 0");
  require(d.cold_fraction > 0.0 && d.cold_fraction <= 1.0, "degradation.cold_fraction",
          d.cold_fraction, "in (0, 1]");
  require(finite_non_negative(d.contact_weight), "degradation.contact_weight", d.contact_weight,
          "finite and ≥ 0");
  const CoherenceOptions& c = coherence;
  require(finite_non_negative(c.max_translation), "coherence.max_translation", c.max_translation,
          "finite and ≥ 0 (m)");
  require(finite_non_negative(c.max_rotation), "coherence.max_rotation", c.max_rotation,
          "finite and ≥ 0 (rad)");
  require(finite_non_negative(c.max_deformation), "coherence.max_deformation", c.max_deformation,
          "finite and ≥ 0 (m)");
  require(finite_non_negative(c.max_field_deformation), "coherence.max_field_deformation",
          c.max_field_deformation, "finite and ≥ 0 (m)");
  require(c.max_skip >= 1 && c.max_skip <= (1 << 20), "coherence.max_skip", c.max_skip,
          "in [1, 2^20]");
  const FrictionOptions& f = friction;
  require(finite_non_negative(f.static_coefficient), "friction.static_coefficient",
          f.static_coefficient, "finite and ≥ 0");
  require(
      finite_non_negative(f.kinetic_coefficient) && f.kinetic_coefficient <= f.static_coefficient,
      "friction.kinetic_coefficient", f.kinetic_coefficient,
      ("finite, ≥ 0 and at most friction.static_coefficient (" +
       std::to_string(f.static_coefficient) + ")"));
  require(finite_non_negative(f.stick_distance), "friction.stick_distance", f.stick_distance,
          "finite and ≥ 0 (m; 0: μ_s times the field's voxel)");
}

}  // namespace khz::contact
