#include <khz/run/run_summary.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <ostream>

namespace khz::run {

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
  std::snprintf(line, sizeof line,
                "force: max %.3f N contact, %.3f N rendered; max torque %.4f N m\n", s.max_force,
                s.max_rendered_force, s.max_torque);
  out << line;
  out << "failed cycles: " << s.failed_cycles << (s.finite ? "" : "; NON-FINITE VALUES") << "\n";
}

}  // namespace khz::run
