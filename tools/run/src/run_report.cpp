#include <khz/plot/line_plot.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/run/run_report.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>

namespace khz::run {
namespace {

constexpr render::Color blue{31, 119, 180}, orange{255, 127, 14}, green{44, 160, 44};

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

plot::Series over_time(const std::vector<scene::CycleRow>& rows, std::string label,
                       render::Color color, double (*value)(const scene::CycleRow&)) {
  plot::Series series{std::move(label), {}, {}, color, false};
  for (const scene::CycleRow& row : rows) {
    series.x.push_back(row.time);
    series.y.push_back(value(row));
  }
  return series;
}

/// |value(row k) − value(row k−1)| over time, from the second row.
plot::Series jumps_over_time(const std::vector<scene::CycleRow>& rows, std::string label,
                             render::Color color,
                             Eigen::Vector3d (*value)(const scene::CycleRow&)) {
  plot::Series series{std::move(label), {}, {}, color, false};
  for (std::size_t k = 1; k < rows.size(); ++k) {
    series.x.push_back(rows[k].time);
    series.y.push_back((value(rows[k]) - value(rows[k - 1])).norm());
  }
  return series;
}

/// The metrics section: a table of the jumps, the still hand's jitter and the residual, then
/// penetration and the passivity observer.
void write_metrics(std::ostream& out, const haptic::CycleMetricsSummary& m,
                   const ReportFiles& files) {
  const auto row = [&](const char* name, const haptic::Quantiles& q, double scale, const char* unit,
                       double peak) {
    out << "| " << name << " | " << format("%.3g", scale * q.p50) << " | "
        << format("%.3g", scale * q.p99) << " | " << format("%.3g", scale * q.max) << " " << unit
        << " | " << (peak > 0.0 ? format("%.1f %%", scene::percent_of(q.p99, peak)) : "–") << " | "
        << q.count << " |\n";
  };
  out << "## Smoothness, steadiness and passivity\n\n"
      << "Computed by the runtime every cycle (haptic::CycleMetrics). Jumps are between "
         "consecutive cycles; the still hand's figures count the cycles after the manipulandum "
         "had been still for "
      << format("%.2g", haptic::CycleMetricsOptions{}.settle_time)
      << " s; the residual |F_contact + F_VC| counts cycles in contact with the coupling "
         "unsaturated.\n\n"
      << "| figure | p50 | p99 | max | p99 / peak | cycles |\n|---|---|---|---|---|---|\n";
  row("contact force jump", m.contact_force_jump, 1.0, "N", m.peak_contact_force);
  row("rendered force jump", m.rendered_force_jump, 1.0, "N", m.peak_rendered_force);
  row("contact torque jump", m.contact_torque_jump, 1.0, "N m", m.peak_contact_torque);
  row("rendered torque jump", m.rendered_torque_jump, 1.0, "N m", m.peak_rendered_torque);
  row("still hand: simulation step", m.still_translation, 1e6, "µm", 0.0);
  row("still hand: simulation turn", m.still_rotation, 1.0, "rad", 0.0);
  row("equilibrium residual", m.residual_force, 1.0, "N", m.peak_contact_force);
  out << "\nDeepest penetration: " << format("%.3g", 1e3 * m.deepest_penetration) << " mm ("
      << format("%.2f", m.deepest_penetration_voxels) << " voxels). Passivity observer "
      << "(Hannaford & Ryu): " << format("%.4g", m.energy) << " J at the end, lowest "
      << format("%.4g", m.lowest_energy) << " J"
      << (m.lowest_energy < 0.0 ? " — **the simulation gave energy to the hand**" : "") << ".\n\n"
      << "![force jumps](" << files.jump_plot.filename().string() << ")\n\n"
      << "![passivity observer](" << files.energy_plot.filename().string() << ")\n\n";
}

/// The stability map's section: one row a setting, then the plot.
void write_stability(std::ostream& out, const std::vector<scene::StabilityPoint>& points,
                     const ReportFiles& files) {
  out << "## Stability map\n\n"
      << "The scene run again with one parameter changed at a time. Stable: every value finite "
         "and the passivity observer never below "
      << format("%.3g", -scene::passive_tolerance)
      << " J. Smooth: stable, with contact- and rendered-force jump p99 at most "
      << format("%.0f", scene::smooth_jump_percent) << " % of their peaks.\n\n"
      << "| setting | stable | smooth | contact jump p99 | rendered jump p99 | peak contact | "
         "deepest | observer lowest | still step p99 |\n"
         "|---|---|---|---|---|---|---|---|---|\n";
  for (const scene::StabilityPoint& p : points) {
    out << "| " << p.setting.name() << " | ";
    if (!p.refused.empty()) {
      out << "refused: " << p.refused << " | | | | | | | |\n";
      continue;
    }
    out << (p.stable() ? "yes" : "**no**") << " | " << (p.smooth() ? "yes" : "no") << " | "
        << format("%.1f %%", p.contact_jump_p99) << " | " << format("%.1f %%", p.rendered_jump_p99)
        << " | " << format("%.3g N", p.peak_contact_force) << " | "
        << format("%.2f voxels", p.deepest_voxels) << " | " << format("%.3g J", p.lowest_energy)
        << " | " << (p.still_cycles > 0 ? format("%.3g µm", 1e6 * p.still_step_p99) : "–")
        << " |\n";
  }
  out << "\n![stability map](" << files.stability_plot.filename().string() << ")\n\n";
}

/// Contact-force jump p99 against value ÷ the scene's value, one series a parameter, the
/// unstable points marked apart, and the 5 % target.
void plot_stability(const std::filesystem::path& file,
                    const std::vector<scene::StabilityPoint>& points) {
  constexpr render::Color purple{148, 103, 189}, red{214, 39, 40}, grey{127, 127, 127};
  std::vector<plot::Series> series;
  const std::pair<scene::StabilityParameter, render::Color> parameters[] = {
      {scene::StabilityParameter::contact_stiffness, blue},
      {scene::StabilityParameter::coupling_stiffness, orange},
      {scene::StabilityParameter::saturation_force, green},
      {scene::StabilityParameter::static_damping, purple},
      {scene::StabilityParameter::rate, grey}};
  double as_given = 0.0;
  for (const scene::StabilityPoint& p : points) {
    if (p.setting.as_given) as_given = p.contact_jump_p99;
  }
  for (const auto& [parameter, color] : parameters) {
    std::vector<std::pair<double, double>> line{{1.0, as_given}};
    for (const scene::StabilityPoint& p : points) {
      if (p.setting.as_given || p.setting.parameter != parameter || !p.refused.empty()) continue;
      line.emplace_back(p.factor, p.contact_jump_p99);
    }
    if (line.size() < 2) continue;
    std::sort(line.begin(), line.end());
    plot::Series curve{std::string(scene::parameter_key(parameter)), {}, {}, color, true};
    for (const auto& [x, y] : line) {
      curve.x.push_back(x);
      curve.y.push_back(y);
    }
    series.push_back(std::move(curve));
  }
  plot::Series unstable{"unstable", {}, {}, red, true};
  for (const scene::StabilityPoint& p : points) {
    if (!p.refused.empty() || p.stable()) continue;
    unstable.x.push_back(p.factor);
    unstable.y.push_back(p.contact_jump_p99);
  }
  if (!unstable.x.empty()) series.push_back(std::move(unstable));
  series.push_back({"target",
                    {0.25, 4.0},
                    {scene::smooth_jump_percent, scene::smooth_jump_percent},
                    red,
                    false});
  plot::write_line_plot(
      file,
      {"Stability map: one parameter changed at a time", "value / the scene's value",
       "contact force jump p99 (% of peak)", 1000, 600, true, false},
      series);
}

void write_markdown(const std::filesystem::path& file, const ReportInput& input,
                    const scene::RunSummary& s, const ReportFiles& files) {
  std::ofstream out(file);
  if (!out) throw reduced::IoError("cannot write " + file.string());
  out << "# Run report: " << input.scene << "\n\n";
  if (!input.description.empty()) out << input.description << "\n\n";
  out << "## The run\n\n"
      << "| figure | value |\n|---|---|\n"
      << "| cycles | " << s.cycles << " at " << input.rate_hz << " Hz ("
      << format("%.3f", s.duration) << " s simulated) |\n"
      << "| cycles in contact | " << s.cycles_in_contact << " |\n"
      << "| µs per cycle, mean / p99 / max | " << format("%.1f", s.cycle_us.mean) << " / "
      << format("%.1f", s.cycle_us.p99) << " / " << format("%.1f", s.cycle_us.max) << " |\n"
      << "| µs per query in contact, mean / p99 | " << format("%.1f", s.query_us_in_contact.mean)
      << " / " << format("%.1f", s.query_us_in_contact.p99) << " |\n"
      << "| most points in contact | " << s.max_contacts << " |\n"
      << "| most nodes traversed | " << s.max_nodes << " |\n"
      << "| deepest level | " << s.deepest_level << " |\n"
      << "| cycles cut by degradation | " << s.incomplete_cycles << " |\n"
      << "| largest contact force | " << format("%.3f", s.max_force) << " N |\n"
      << "| largest rendered force | " << format("%.3f", s.max_rendered_force) << " N |\n"
      << "| failed cycles | " << s.failed_cycles << " |\n"
      << "| all values finite | " << (s.finite ? "yes" : "**no**") << " |\n\n"
      << "Times are wall-clock on this machine, measured in a simulated-time run (the machine "
         "was not reserved); benchmarks/ has the controlled figures.\n\n"
      << "![force](" << files.force_plot.filename().string() << ")\n\n"
      << "![torque](" << files.torque_plot.filename().string() << ")\n\n"
      << "![cost per cycle](" << files.cost_plot.filename().string() << ")\n\n";
  write_metrics(out, input.metrics, files);
  if (!input.free_bodies.empty()) {
    out << "## Free objects\n\nWhere the run left the objects that move freely (scene "
           "\"dynamics\"), their centre of mass against where it started.\n\n"
           "| object | moved | centre at the end (m) | at the end |\n|---|---|---|---|\n";
    for (const FreeBodyState& body : input.free_bodies) {
      out << "| " << body.name << " | " << format("%.4f m", (body.centre - body.start).norm())
          << " | " << format("[%.4f, ", body.centre.x()) << format("%.4f, ", body.centre.y())
          << format("%.4f]", body.centre.z()) << " | "
          << (body.hand >= 0 ? "grasped by hand " + std::to_string(body.hand)
              : body.asleep  ? std::string("at rest")
                             : format("moving at %.3g m/s", body.speed))
          << " |\n";
    }
    out << "\nThe speed-against-error replay below places the held and the free objects as "
           "recorded, with every grasp let go (a carried object is replayed as touched by what "
           "carried it), and its errors cover the free objects' contacts too.\n\n";
  }
  if (!input.sweep.empty()) {
    out << "## Speed against error of the contact query\n\n"
        << "The recorded states in contact (" << input.sweep.front().states
        << ", evenly spaced when there were more than " << scene::default_sweep_states
        << "), queried again under each setting "
           "(temporal coherence off) and compared with the full traversal.\n\n"
        << "| setting | µs mean | µs p99 | nodes | force error (RMS) | force error (max) | "
           "torque error (RMS) |\n|---|---|---|---|---|---|---|\n";
    for (const scene::SweepResult& r : input.sweep) {
      out << "| " << r.name << " | " << format("%.1f", r.query_us.mean) << " | "
          << format("%.1f", r.query_us.p99) << " | " << format("%.0f", r.mean_nodes) << " | "
          << format("%.2f %%", 100.0 * r.force_error) << " | "
          << format("%.2f %%", 100.0 * r.max_force_error) << " | "
          << format("%.2f %%", 100.0 * r.torque_error) << " |\n";
    }
    out << "\n![speed against error](" << files.speed_plot.filename().string() << ")\n\n";
  }
  if (!input.stability.empty()) write_stability(out, input.stability, files);
  if (!input.frames.empty()) {
    out << "## Frames\n\nYellow: pointshell points the query looked at; red: points in contact "
           "(drawn through the other object), blue where their friction slid; green: the contact "
           "force on the held object. Held objects are blue, free ones pale green.\n\n";
    for (const std::filesystem::path& frame : input.frames) {
      out << "![" << frame.stem().string() << "](" << frame.string() << ")\n";
    }
  }
  if (!out.flush()) throw reduced::IoError("cannot write " + file.string());
}

}  // namespace

ReportFiles write_report(const std::filesystem::path& directory, const ReportInput& input) {
  std::filesystem::create_directories(directory);
  ReportFiles files{directory / "report.md",
                    directory / "force.png",
                    directory / "torque.png",
                    directory / "cost.png",
                    directory / "jumps.png",
                    directory / "energy.png",
                    {},
                    {}};
  const std::vector<scene::CycleRow>& rows = input.rows;
  plot::write_line_plot(files.force_plot, {"Force on the held object", "time (s)", "force (N)"},
                        {over_time(rows, "contact |F|", blue,
                                   [](const scene::CycleRow& r) { return r.force.norm(); }),
                         over_time(rows, "rendered |F|", orange, [](const scene::CycleRow& r) {
                           return r.rendered_force.norm();
                         })});
  plot::write_line_plot(
      files.torque_plot, {"Torque on the held object", "time (s)", "torque (N m)"},
      {over_time(rows, "contact |T|", blue,
                 [](const scene::CycleRow& r) { return r.torque.norm(); }),
       over_time(rows, "rendered |T|", orange,
                 [](const scene::CycleRow& r) { return r.rendered_torque.norm(); })});
  plot::write_line_plot(
      files.cost_plot, {"Cost per cycle", "time (s)", "microseconds"},
      {over_time(rows, "whole cycle", blue, [](const scene::CycleRow& r) { return r.cycle_us; }),
       over_time(rows, "contact query", orange,
                 [](const scene::CycleRow& r) { return r.query_us; })});
  plot::write_line_plot(
      files.jump_plot, {"Force jumps between cycles", "time (s)", "|F(k) - F(k-1)| (N)"},
      {jumps_over_time(rows, "contact", blue, [](const scene::CycleRow& r) { return r.force; }),
       jumps_over_time(rows, "rendered", orange,
                       [](const scene::CycleRow& r) { return r.rendered_force; })});
  plot::write_line_plot(files.energy_plot,
                        {"Passivity observer: energy the hand put in", "time (s)", "energy (J)"},
                        {over_time(rows, "observed energy", blue,
                                   [](const scene::CycleRow& r) { return r.energy; })});
  if (!input.sweep.empty()) {
    files.speed_plot = directory / "speed_vs_error.png";
    plot::Series levels{"fixed levels", {}, {}, blue, true};
    plot::Series budgets{"time budgets", {}, {}, orange, true};
    for (std::size_t i = 1; i < input.sweep.size(); ++i) {
      const scene::SweepResult& r = input.sweep[i];
      plot::Series& series = r.name.rfind("level", 0) == 0 ? levels : budgets;
      series.x.push_back(r.query_us.mean);
      series.y.push_back(100.0 * r.force_error);
    }
    plot::Series reference{
        "reference (0 %)", {input.sweep.front().query_us.mean}, {0.0}, green, true};
    plot::write_line_plot(files.speed_plot,
                          {"Contact query: speed against force error", "microseconds per query",
                           "force error RMS (%)"},
                          {levels, budgets, reference});
  }
  if (!input.stability.empty()) {
    files.stability_plot = directory / "stability.png";
    plot_stability(files.stability_plot, input.stability);
  }
  write_markdown(files.markdown, input, scene::summarize(rows, 1.0 / input.rate_hz), files);
  return files;
}

}  // namespace khz::run
