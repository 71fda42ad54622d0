#include <khz/viewer/preparation_messages.hpp>

#include <cstdio>

namespace khz::viewer {

std::string PreparationMessages::line(const std::string& object, scene::PrepareStep step,
                                      const reduced::Progress& progress) {
  const int step_index = static_cast<int>(step);
  if (object == m_object && step_index == m_step) return {};
  m_object = object;
  m_step = step_index;
  const std::string product = object + " " + std::string(scene::step_name(step));
  return progress.stage == cache_read_stage ? product + ": cached"
                                            : "preparing " + product + " ...";
}

std::string preparation_summary(const scene::PreparedScene& prepared) {
  using Origin = scene::PrepareRecord::Origin;
  char text[160];
  std::snprintf(text, sizeof text, "prepared in %.2f s: %d cached, %d computed, %d built",
                prepared.total_seconds(), prepared.count(Origin::read),
                prepared.count(Origin::computed), prepared.count(Origin::built));
  return text;
}

}  // namespace khz::viewer
