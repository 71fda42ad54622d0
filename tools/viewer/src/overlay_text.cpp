#include <khz/viewer/overlay_text.hpp>

#include <cstdarg>
#include <cstdio>

namespace khz::viewer {
namespace {

/// printf into a string; the attribute lets the compiler check the arguments against `format`.
[[gnu::format(printf, 1, 2)]] std::string formatted(const char* format, ...) {
  char text[200];
  std::va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(text, sizeof text, format, arguments);
  va_end(arguments);
  return text;
}

}  // namespace

std::vector<std::string> overlay_status(const OverlayRates& rates,
                                        std::span<const haptic::CycleRecord> records,
                                        std::span<const std::string> hand_names) {
  std::vector<std::string> lines;
  lines.push_back(formatted("haptic loop: %.0f cycles/s, %.1f us of work per cycle",
                            rates.cycles_per_second, rates.microseconds_per_cycle));
  lines.push_back(formatted("drawing: %.0f frames/s", rates.frames_per_second));
  for (std::size_t h = 0; h < records.size(); ++h) {
    const haptic::CycleRecord& record = records[h];
    const std::string name = h < hand_names.size() ? " (" + hand_names[h] + ")" : std::string();
    lines.push_back(formatted("hand %zu%s: force %.3g N, torque %.3g N m", h, name.c_str(),
                              record.contact.force.norm(), record.contact.torque.norm()));
    const contact::ContactStatistics& statistics = record.contact.statistics;
    if (!record.contact_valid) {
      lines.emplace_back("  no contact query this cycle (none yet, or it refused its input)");
    } else {
      const std::string sliding =
          statistics.points_sliding > 0
              ? formatted(" (%lld sliding)", static_cast<long long>(statistics.points_sliding))
              : std::string();
      lines.push_back(formatted("  %lld points in contact%s, deepest level %d%s",
                                static_cast<long long>(statistics.points_in_contact),
                                sliding.c_str(), statistics.deepest_level,
                                statistics.complete ? "" : ", cut short by degradation"));
    }
  }
  return lines;
}

std::vector<std::string> overlay_help() {
  return {"left drag: move hand 0 across the view    wheel: move it nearer / farther",
          "right drag: orbit    shift+wheel, +/-: zoom    R: reset view    Esc: quit"};
}

}  // namespace khz::viewer
