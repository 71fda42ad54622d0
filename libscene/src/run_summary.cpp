#include <khz/scene/run_summary.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <ostream>

namespace khz::scene {

Spread spread(std::vector<double> values) {
  Spread s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const auto rank = [&](double fraction) {
    const auto k =
        static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(values.size())));
    return values[std::clamp<std::size_t>(k, 1, values.size()) - 1];
  };
  s.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  s.p50 = rank(0.5);
  s.p99 = rank(0.99);
  s.max = values.back();
  s.count = static_cast<std::int64_t>(values.size());
  return s;
}

RunSummary summarize(const std::vector<CycleRow>& rows, double period) {
  RunSummary s;
  s.cycles = static_cast<std::int64_t>(rows.size());
  if (rows.empty()) return s;
  s.duration = rows.back().time + period;
  std::vector<double> cycle, query, query_in_contact;
  for (const CycleRow& row : rows) {
    cycle.push_back(row.cycle_us);
    query.push_back(row.query_us);
    if (row.contacts > 0) {
      ++s.cycles_in_contact;
      query_in_contact.push_back(row.query_us);
    }
    s.failed_cycles += row.ok ? 0 : 1;
    s.incomplete_cycles += row.complete ? 0 : 1;
    s.max_contacts = std::max(s.max_contacts, row.contacts);
    s.contact_points += row.contacts;
    s.sliding_points += row.sliding;
    s.max_nodes = std::max(s.max_nodes, row.nodes);
    s.deepest_level = std::max(s.deepest_level, row.level);
    s.max_force = std::max(s.max_force, row.force.norm());
    s.max_torque = std::max(s.max_torque, row.torque.norm());
    s.max_rendered_force = std::max(s.max_rendered_force, row.rendered_force.norm());
    s.finite = s.finite && row.force.allFinite() && row.torque.allFinite() &&
               row.rendered_force.allFinite() && row.simulation.allFinite() &&
               row.orientation.coeffs().allFinite();
  }
  s.cycle_us = spread(std::move(cycle));
  s.query_us = spread(std::move(query));
  s.query_us_in_contact = spread(std::move(query_in_contact));
  return s;
}

void print_summary(std::ostream& out, const RunSummary& s) {
  char line[256];
  const auto spread_line = [&](const char* name, const Spread& v) {
    std::snprintf(line, sizeof line, "  %-22s mean %8.1f  p50 %8.1f  p99 %8.1f  max %8.1f\n", name,
                  v.mean, v.p50, v.p99, v.max);
    out << line;
  };
  std::snprintf(line, sizeof line, "cycles: %lld over %.3f s, %lld in contact\n",
                static_cast<long long>(s.cycles), s.duration,
                static_cast<long long>(s.cycles_in_contact));
  out << line;
  out << "cost (us):\n";
  spread_line("cycle", s.cycle_us);
  spread_line("query", s.query_us);
  spread_line("query, in contact", s.query_us_in_contact);
  std::snprintf(line, sizeof line,
                "contact: max %lld points, max %lld nodes, deepest level %d, %lld cycles cut by "
                "degradation\n",
                static_cast<long long>(s.max_contacts), static_cast<long long>(s.max_nodes),
                s.deepest_level, static_cast<long long>(s.incomplete_cycles));
  out << line;
  if (s.sliding_points > 0) {
    std::snprintf(
        line, sizeof line, "friction: %.1f %% of the points in contact slid\n",
        percent_of(static_cast<double>(s.sliding_points), static_cast<double>(s.contact_points)));
    out << line;
  }
  std::snprintf(line, sizeof line,
                "force: max %.3f N contact, %.3f N rendered; max torque %.4f N m\n", s.max_force,
                s.max_rendered_force, s.max_torque);
  out << line;
  out << "failed cycles: " << s.failed_cycles << (s.finite ? "" : "; NON-FINITE VALUES") << "\n";
  print_metrics(out, s.metrics);
}

double percent_of(double value, double peak) { return peak > 0.0 ? 100.0 * value / peak : 0.0; }

void print_metrics(std::ostream& out, const haptic::CycleMetricsSummary& m) {
  char line[320];
  const auto jump_line = [&](const char* name, const haptic::Quantiles& jump, double peak,
                             const char* unit) {
    std::snprintf(line, sizeof line,
                  "  %-16s p50 %9.3g  p99 %9.3g  max %9.3g %-4s (p99 %5.1f %% of the %.3g peak)\n",
                  name, jump.p50, jump.p99, jump.max, unit, percent_of(jump.p99, peak), peak);
    out << line;
  };
  out << "jumps between cycles:\n";
  jump_line("contact force", m.contact_force_jump, m.peak_contact_force, "N");
  jump_line("rendered force", m.rendered_force_jump, m.peak_rendered_force, "N");
  jump_line("contact torque", m.contact_torque_jump, m.peak_contact_torque, "N m");
  jump_line("rendered torque", m.rendered_torque_jump, m.peak_rendered_torque, "N m");
  if (m.still_translation.count > 0) {
    std::snprintf(line, sizeof line,
                  "still hand (%lld cycles): simulation moves p99 %.3g um, max %.3g um; turns "
                  "p99 %.3g rad, max %.3g rad per cycle\n",
                  static_cast<long long>(m.still_translation.count), 1e6 * m.still_translation.p99,
                  1e6 * m.still_translation.max, m.still_rotation.p99, m.still_rotation.max);
  } else {
    std::snprintf(line, sizeof line, "still hand: never held still long enough to tell\n");
  }
  out << line;
  std::snprintf(line, sizeof line,
                "equilibrium residual (%lld unsaturated cycles in contact): p50 %.3g  p99 %.3g  "
                "max %.3g N\n",
                static_cast<long long>(m.residual_force.count), m.residual_force.p50,
                m.residual_force.p99, m.residual_force.max);
  out << line;
  std::snprintf(line, sizeof line, "penetration: deepest %.3g mm, %.2f voxels\n",
                1e3 * m.deepest_penetration, m.deepest_penetration_voxels);
  out << line;
  std::snprintf(line, sizeof line, "passivity observer: %.4g J at the end, lowest %.4g J%s\n",
                m.energy, m.lowest_energy,
                m.lowest_energy < 0.0 ? " (the simulation gave energy to the hand)" : "");
  out << line;
}

}  // namespace khz::scene
