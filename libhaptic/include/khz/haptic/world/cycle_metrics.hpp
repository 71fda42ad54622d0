#pragma once
// How smooth, steady and passive a hand's contact is, cycle after cycle: the figures that tell
// chatter, jitter, sinking and energy gain apart (docs/HAPTICS.md, "Smoothness metrics").

#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/export.hpp>
#include <khz/haptic/world/cycle_record.hpp>

#include <cstdint>
#include <memory>

namespace khz::haptic {

/// The mean, median, 99th percentile (nearest rank) and maximum of a per-cycle quantity, and
/// the number of values they were taken over; all zero when count is 0. CycleMetrics' are of
/// nonnegative values, with the percentiles known to 2 % (logarithmic bins) and the mean and
/// maximum exactly.
struct Quantiles {
  double mean = 0.0;
  double p50 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
  std::int64_t count = 0;
};

/// When the manipulandum counts as still, for the simulation pose's jitter.
struct KHZ_HAPTIC_API CycleMetricsOptions {
  /// The manipulandum is still in a cycle where it moved slower than this since the last one
  /// (m/s, ≥ 0)…
  double still_speed = 1e-3;
  /// …and turned slower than this (rad/s, ≥ 0).
  double still_angular_speed = 1e-2;
  /// The simulation pose's steps are counted once the manipulandum has been still this long (s,
  /// ≥ 0): what is left then is jitter, not the pose settling after the hand stopped.
  double settle_time = 0.1;

  /// @throws Error naming a negative or non-finite setting.
  void validate() const;
};

/// A hand's cycles in figures (CycleMetrics::summary()).
struct CycleMetricsSummary {
  std::int64_t cycles = 0;  ///< Cycles recorded.
  /// |F_k − F_{k−1}| of the contact force between consecutive cycles (N): chatter.
  Quantiles contact_force_jump;
  Quantiles contact_torque_jump;      ///< The same for the contact torque (N·m).
  Quantiles rendered_force_jump;      ///< The same for the force sent to the device (device N).
  Quantiles rendered_torque_jump;     ///< The same for the torque sent (device N·m).
  double peak_contact_force = 0.0;    ///< Largest |contact force| (N).
  double peak_contact_torque = 0.0;   ///< Largest |contact torque| (N·m).
  double peak_rendered_force = 0.0;   ///< Largest |force sent| (device N).
  double peak_rendered_torque = 0.0;  ///< Largest |torque sent| (device N·m).
  /// How far the simulation pose moved per cycle (m) while the manipulandum had been still for
  /// CycleMetricsOptions::settle_time: jitter of a held press.
  Quantiles still_translation;
  Quantiles still_rotation;  ///< The same for its rotation (rad).
  /// |F_contact + F_VC| at the queried pose (N; CycleRecord::residual) in cycles with points in
  /// contact and an unsaturated coupling: how far each step left the simulation object from the
  /// equilibrium it solves for (thesis eq. 4.1).
  Quantiles residual_force;
  Quantiles residual_torque;         ///< The same for the torque (N·m).
  double deepest_penetration = 0.0;  ///< Deepest point in contact in any cycle (m).
  /// The same in voxels of the field it was in (CycleRecord::penetration_voxels); 0 when only
  /// analytic fields were touched.
  double deepest_penetration_voxels = 0.0;
  /// The passivity observer at the end (CycleRecord::observed_energy, J at the device).
  double energy = 0.0;
  /// Its lowest value: below zero, the simulation gave the hand that much energy more than it
  /// took at some point, which a passive object never does (Hannaford & Ryu 2002).
  double lowest_energy = 0.0;
};

/// Accumulates one hand's CycleRecords into a CycleMetricsSummary, and keeps the passivity
/// observer (Hannaford & Ryu, "Time-domain passivity control of haptic interfaces", 2002): the
/// work the hand has done on the device since the first cycle,
///
///     E_k = − Σ_{j<k} (F_j · Δx_j + T_j · Δθ_j),
///
/// F_j, T_j the wrench sent in cycle j (held until the next write) and Δx_j, Δθ_j the device's
/// motion until cycle j + 1, both in device axes and units (the manipulandum's motion mapped back
/// through the SafeDevice's WorkspaceMapping). A passive simulation keeps E_k ≥ 0.
///
/// World keeps one per hand (World::metrics()); a program running its own loop may feed its own.
/// record() allocates nothing, takes no lock and throws nothing; the constructor allocates the
/// histograms (~100 KB).
class KHZ_HAPTIC_API CycleMetrics {
 public:
  /// @throws Error if the options are invalid.
  explicit CycleMetrics(const CycleMetricsOptions& options = {});
  ~CycleMetrics();
  CycleMetrics(CycleMetrics&&) noexcept;
  CycleMetrics& operator=(CycleMetrics&&) noexcept;

  /// Records one cycle and returns the passivity observer after it (J; what it writes into
  /// record.observed_energy when the caller keeps it). `mapping` is the hand's device mapping
  /// (SafeDevice::mapping()), for the energy in device units. Cycles are expected in time
  /// order; a record without a valid device read adds no motion.
  double record(const CycleRecord& record, const WorkspaceMapping& mapping) noexcept;
  /// The figures so far (one pass over each histogram).
  CycleMetricsSummary summary() const noexcept;
  /// Forgets every cycle (the observer restarts at 0).
  void clear() noexcept;
  const CycleMetricsOptions& options() const noexcept;

 private:
  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::haptic
