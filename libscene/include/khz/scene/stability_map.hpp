#pragma once
// Where a scene's runs stay stable and smooth: the scene run again with one parameter changed at
// a time — contact stiffness, coupling stiffness, saturation, static damping, loop rate — each
// run summarised by the runtime's metrics (haptic::CycleMetricsSummary), so a user can see which
// way to move a parameter (issue 19 item 8; docs/HAPTICS.md, "Stability map").

#include <khz/haptic/world/cycle_metrics.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <string>
#include <vector>

namespace khz::scene {

/// The parameters a stability map varies.
enum class StabilityParameter {
  contact_stiffness,   ///< contact.stiffness, k_C (N/m per point).
  coupling_stiffness,  ///< coupling.stiffness, k_VC (N/m).
  saturation_force,    ///< coupling.saturation_force, F_VC,max (N).
  static_damping,      ///< coupling.static_damping, α of §4.6 (in [0, 1)).
  /// loop.rate_hz (Hz), with the coupling's period and the devices' rate, and the contact's
  /// time budget (or node count) scaled with the period: the same share of each cycle.
  rate,
};

/// The scene key a parameter is set by, e.g. "coupling.stiffness".
KHZ_SCENE_API std::string_view parameter_key(StabilityParameter parameter) noexcept;

/// One run of the map: the scene with one parameter at `value` (the scene's own values when
/// `as_given`).
struct KHZ_SCENE_API StabilitySetting {
  bool as_given = false;
  StabilityParameter parameter = StabilityParameter::contact_stiffness;
  double value = 0.0;
  /// "as given", or "<key> = <value>" for tables and legends.
  std::string name() const;
};

/// What one run showed. Relative figures are of the run's own peaks.
struct KHZ_SCENE_API StabilityPoint {
  StabilitySetting setting;
  /// Non-empty when the libraries refused the setting (e.g. k_VC above the device's stiffness
  /// limit, a simulated operator that cannot run at that rate): their message; nothing ran.
  std::string refused;
  /// setting.value ÷ the scene's own value of the parameter (1 as given).
  double factor = 1.0;
  bool finite = true;               ///< Every cycle finite, none failed.
  std::size_t cycles = 0;           ///< Cycles run (every hand; the figures are hand 0's).
  double peak_contact_force = 0.0;  ///< N.
  double contact_jump_p99 = 0.0;    ///< p99 of the cycle-to-cycle contact-force jump, % of peak.
  double rendered_jump_p99 = 0.0;   ///< The same for the force sent to the device, % of peak.
  double still_step_p99 = 0.0;      ///< Simulation pose's step while the hand is still (m, p99).
  std::int64_t still_cycles = 0;    ///< Cycles that figure counts (0: never still long enough).
  double deepest_voxels = 0.0;      ///< Deepest penetration (voxels of the field it is in).
  double lowest_energy = 0.0;       ///< Passivity observer's lowest value (J; < 0: gave energy).

  /// Finite, and the observer never below −passive_tolerance: the simulation gave the hand no
  /// energy worth feeling.
  bool stable() const noexcept;
  /// Stable, and contact and rendered jump p99 both at most smooth_jump_percent of their peaks.
  bool smooth() const noexcept;
};

/// The observer's allowed dip (J): sampling a stiff contact and holding it makes the device
/// port slightly active even where the device's own damping keeps it stable (Colgate), 0.6 mJ
/// in test_haptic_passivity_controller's passive wall.
inline constexpr double passive_tolerance = 1e-3;
/// Issue 19's smoothness target: contact-force jump p99 ≤ 5 % of the peak.
inline constexpr double smooth_jump_percent = 5.0;

/// The settings `khz report` maps for `scene`: as given; contact and coupling stiffness and
/// saturation (when the scene sets one) × 1/4 and × 4; static damping 0.2 and 0.9; rates 500,
/// 1000, 2000 and 4000 Hz (each value the scene does not already have).
KHZ_SCENE_API std::vector<StabilitySetting> default_stability_settings(
    const SceneDescription& scene);

/// Runs `prepared` once per setting for `duration` simulated seconds (0: the scene's own, as
/// run_scene()), each time on a fresh SceneRuntime with the setting applied to
/// prepared.description, which is restored afterwards (also on throw). `devices`, one per hand,
/// replace the scene's (e.g. run::choose_devices()'s); empty keeps them. `progress` hears of one
/// stage a setting, named after it, in cycles.
/// @throws reduced::Error as run_scene() (no duration), or if `devices` is neither empty nor
///         one per hand; reduced::Cancelled if `progress` returns false.
KHZ_SCENE_API std::vector<StabilityPoint> stability_map(
    PreparedScene& prepared, const std::vector<StabilitySetting>& settings, double duration = 0.0,
    const std::vector<DeviceDescription>& devices = {},
    const reduced::ProgressCallback& progress = {});

}  // namespace khz::scene
