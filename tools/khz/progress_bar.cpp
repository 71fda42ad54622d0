#include "progress_bar.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <string>
#include <utility>

namespace khz::tool {
namespace {

/// Columns of the terminal on stderr; 100 when it cannot be asked.
int terminal_columns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 100;
}

/// Redraws at most this often, so reporting costs nothing next to the work.
constexpr std::chrono::milliseconds redraw_interval{100};

/// `seconds` as "m:ss", or "h:mm:ss" from an hour up.
std::string clock_text(double seconds) {
  const auto total = static_cast<long long>(std::llround(std::max(seconds, 0.0)));
  char text[32];
  if (total >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, total / 60 % 60,
                  total % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", total / 60, total % 60);
  }
  return text;
}

}  // namespace

ProgressBar::ProgressBar(std::ostream& out, bool interactive)
    : m_out(out), m_interactive(interactive) {}

void ProgressBar::update(std::string_view label, const reduced::Progress& progress) {
  const Clock::time_point now = Clock::now();
  std::string stage(label);
  stage += "  ";
  stage += progress.stage;
  if (progress.done == 0 || stage != m_stage) {
    m_stage = std::move(stage);
    m_start = now;
    m_finish_shown = false;
  } else if (m_interactive && progress.done < progress.total && now - m_drawn < redraw_interval) {
    return;
  }
  draw(label, progress, now);
}

void ProgressBar::draw(std::string_view label, const reduced::Progress& progress,
                       Clock::time_point now) {
  m_drawn = now;
  const double elapsed = std::chrono::duration<double>(now - m_start).count();
  const bool finished = progress.done >= progress.total;
  if (!m_interactive) {
    // A stage whose total was estimated low can report done = total more than once.
    if (finished && !m_finish_shown) {
      m_finish_shown = true;
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%.2f s", elapsed);
      m_out << label << ": " << progress.stage << ": " << seconds << "\n" << std::flush;
    }
    return;
  }
  constexpr int bar_width = 24;
  const double fraction = std::clamp(progress.fraction(), 0.0, 1.0);
  const auto filled = static_cast<int>(std::lround(fraction * bar_width));
  char tail[96];
  if (finished) {
    std::snprintf(tail, sizeof tail, "] 100%%  %.1f s", elapsed);
  } else if (progress.done > 0 && elapsed >= 1.0) {
    const double left = elapsed * static_cast<double>(progress.total - progress.done) /
                        static_cast<double>(progress.done);
    std::snprintf(tail, sizeof tail, "] %3d%%  ETA %s", static_cast<int>(fraction * 100.0),
                  clock_text(left).c_str());
  } else {
    std::snprintf(tail, sizeof tail, "] %3d%%", static_cast<int>(fraction * 100.0));
  }
  std::string text = m_stage;  // the label and the stage
  // The bar and its tail always show; a long label and stage give way.
  const std::size_t room = static_cast<std::size_t>(
      std::max(10, terminal_columns() - 1 - bar_width - 3 - static_cast<int>(std::strlen(tail))));
  if (text.size() > room) text = text.substr(0, room - 1) + "~";
  text += " [" + std::string(static_cast<std::size_t>(filled), '#') +
          std::string(static_cast<std::size_t>(bar_width - filled), '.') + tail;
  m_out << '\r' << text << "\x1b[K" << std::flush;
  m_line_open = true;
}

void ProgressBar::clear() {
  if (!m_line_open) return;
  m_out << "\r\x1b[K" << std::flush;
  m_line_open = false;
}

}  // namespace khz::tool
