#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/world/cycle_metrics.hpp>

#include "magnitude_histogram.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace khz::haptic {

void CycleMetricsOptions::validate() const {
  const auto require = [](double value, const char* name) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw Error(std::string("CycleMetricsOptions: ") + name + " must be finite and >= 0, not " +
                  std::to_string(value));
    }
  };
  require(still_speed, "still_speed");
  require(still_angular_speed, "still_angular_speed");
  require(settle_time, "settle_time");
}

struct CycleMetrics::Data {
  CycleMetricsOptions options;
  detail::MagnitudeHistogram contact_force_jump, contact_torque_jump, rendered_force_jump,
      rendered_torque_jump, still_translation, still_rotation, residual_force, residual_torque;
  CycleMetricsSummary totals;  // counts, peaks, penetration and energy; quantiles filled later
  bool has_previous = false;
  CycleRecord previous;
  double still_since = 0.0;  // start of the current still stretch (s)
  bool still = false;
};

CycleMetrics::CycleMetrics(const CycleMetricsOptions& options) : m_data(std::make_unique<Data>()) {
  options.validate();
  m_data->options = options;
}

CycleMetrics::~CycleMetrics() = default;
CycleMetrics::CycleMetrics(CycleMetrics&&) noexcept = default;
CycleMetrics& CycleMetrics::operator=(CycleMetrics&&) noexcept = default;

const CycleMetricsOptions& CycleMetrics::options() const noexcept { return m_data->options; }

namespace {

/// The rotation from a to b (rad, world axes).
Eigen::Vector3d turn(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) noexcept {
  return rotation_vector(b * a.conjugate());
}

}  // namespace

double CycleMetrics::record(const CycleRecord& r, const WorkspaceMapping& mapping) noexcept {
  Data& d = *m_data;
  CycleMetricsSummary& t = d.totals;
  ++t.cycles;
  t.peak_contact_force = std::max(t.peak_contact_force, r.contact.force.norm());
  t.peak_contact_torque = std::max(t.peak_contact_torque, r.contact.torque.norm());
  t.peak_rendered_force = std::max(t.peak_rendered_force, r.rendered.force.norm());
  t.peak_rendered_torque = std::max(t.peak_rendered_torque, r.rendered.torque.norm());
  t.deepest_penetration = std::max(t.deepest_penetration, r.contact.statistics.deepest_penetration);
  t.deepest_penetration_voxels = std::max(t.deepest_penetration_voxels, r.penetration_voxels);
  if (r.coupling_valid && !r.coupling_saturated && r.contact.statistics.points_in_contact > 0) {
    d.residual_force.add(r.residual.force.norm());
    d.residual_torque.add(r.residual.torque.norm());
  }

  if (d.has_previous) {
    const CycleRecord& p = d.previous;
    d.contact_force_jump.add((r.contact.force - p.contact.force).norm());
    d.contact_torque_jump.add((r.contact.torque - p.contact.torque).norm());
    d.rendered_force_jump.add((r.rendered.force - p.rendered.force).norm());
    d.rendered_torque_jump.add((r.rendered.torque - p.rendered.torque).norm());

    // The passivity observer: the previous output, held while the device moved to this pose.
    const Eigen::Vector3d moved = r.manipulandum.position - p.manipulandum.position;
    const Eigen::Vector3d turned = turn(p.manipulandum.orientation, r.manipulandum.orientation);
    const Eigen::Matrix3d to_device = mapping.offset.orientation.conjugate().toRotationMatrix();
    const double work = p.rendered.force.dot(to_device * moved) / mapping.scale +
                        p.rendered.torque.dot(to_device * turned);
    if (std::isfinite(work)) t.energy -= work;
    t.lowest_energy = std::min(t.lowest_energy, t.energy);

    // Jitter: the simulation's steps once the manipulandum has been still for settle_time.
    const double dt = r.time - p.time;
    const bool still_now = dt > 0.0 && moved.norm() <= d.options.still_speed * dt &&
                           turned.norm() <= d.options.still_angular_speed * dt;
    if (still_now && !d.still) d.still_since = p.time;
    d.still = still_now;
    if (still_now && r.time - d.still_since >= d.options.settle_time) {
      d.still_translation.add((r.simulation.position - p.simulation.position).norm());
      d.still_rotation.add(turn(p.simulation.orientation, r.simulation.orientation).norm());
    }
  }
  d.previous = r;
  d.has_previous = true;
  return t.energy;
}

CycleMetricsSummary CycleMetrics::summary() const noexcept {
  const Data& d = *m_data;
  CycleMetricsSummary s = d.totals;
  s.contact_force_jump = d.contact_force_jump.quantiles();
  s.contact_torque_jump = d.contact_torque_jump.quantiles();
  s.rendered_force_jump = d.rendered_force_jump.quantiles();
  s.rendered_torque_jump = d.rendered_torque_jump.quantiles();
  s.still_translation = d.still_translation.quantiles();
  s.still_rotation = d.still_rotation.quantiles();
  s.residual_force = d.residual_force.quantiles();
  s.residual_torque = d.residual_torque.quantiles();
  return s;
}

void CycleMetrics::clear() noexcept {
  Data& d = *m_data;
  for (detail::MagnitudeHistogram* h :
       {&d.contact_force_jump, &d.contact_torque_jump, &d.rendered_force_jump,
        &d.rendered_torque_jump, &d.still_translation, &d.still_rotation, &d.residual_force,
        &d.residual_torque}) {
    h->clear();
  }
  d.totals = {};
  d.has_previous = false;
  d.still = false;
  d.still_since = 0.0;
}

}  // namespace khz::haptic
