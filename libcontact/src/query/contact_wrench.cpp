#include <khz/contact/query/contact_wrench.hpp>

#include <algorithm>

namespace khz::contact {

void ContactStatistics::accumulate(const ContactStatistics& other) noexcept {
  nodes_traversed += other.nodes_traversed;
  nodes_skipped += other.nodes_skipped;
  coherence_reset = coherence_reset || other.coherence_reset;
  points_in_contact += other.points_in_contact;
  points_sliding += other.points_sliding;
  deepest_level = std::max(deepest_level, other.deepest_level);
  deepest_penetration = std::max(deepest_penetration, other.deepest_penetration);
  complete = complete && other.complete;
  microseconds += other.microseconds;
}

void ContactWrench::accumulate(const ContactWrench& other) noexcept {
  force += other.force;
  torque += other.torque;
  force_by_translation += other.force_by_translation;
  force_by_rotation += other.force_by_rotation;
  torque_by_translation += other.torque_by_translation;
  torque_by_rotation += other.torque_by_rotation;
  statistics.accumulate(other.statistics);
}

}  // namespace khz::contact
