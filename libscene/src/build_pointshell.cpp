#include "product_builders.hpp"

#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>

#include <string>

namespace khz::scene::detail {
namespace {

/// What a repulsion run left undone, for the preparation summary; empty if nothing.
std::string repulsion_note(const contact::RepulsionReport& report) {
  std::string levels;
  for (std::size_t i = 0; i < report.levels.size(); ++i) {
    if (report.levels[i].converged) continue;
    levels += (levels.empty() ? "" : ", ") + std::to_string(i);
  }
  std::string note;
  if (!levels.empty()) note = "repulsion level(s) " + levels + " did not converge";
  if (!report.off_level_set.empty()) {
    note += (note.empty() ? "" : "; ") + std::to_string(report.off_level_set.size()) +
            " point(s) off the level set";
  }
  return note;
}

contact::Pointshell repulsion(const reduced::TriangleMesh& surface, const ObjectDescription& object,
                              const contact::DistanceGrid& field,
                              const reduced::ProgressCallback& progress, std::string& note) {
  contact::RepulsionOptions options = object.pointshell.repulsion;
  options.progress = progress;
  contact::RepulsionReport report;
  // A soup's points lie on its offset surface, whose pseudonormals the soup itself lacks.
  contact::Pointshell result =
      object.field.soup ? contact::repulsion_pointshell(field, 0.0, contact::isosurface(field, 0.0),
                                                        options, &report)
                        : contact::repulsion_pointshell(field, 0.0, surface, options, &report);
  note = repulsion_note(report);
  return result;
}

}  // namespace

contact::Pointshell compute_pointshell(const reduced::TriangleMesh& surface,
                                       const ObjectDescription& object,
                                       const contact::DistanceGrid* field,
                                       const reduced::ProgressCallback& progress,
                                       std::string& note) {
  const PointshellDescription& shell = object.pointshell;
  contact::Pointshell samples;
  switch (shell.method) {
    case PointshellMethod::repulsion:
      return repulsion(surface, object, *field, progress, note);
    case PointshellMethod::vertices:
      samples = contact::vertex_pointshell(surface);
      break;
    case PointshellMethod::random:
      samples = contact::random_pointshell(surface, shell.count, shell.nested.seed);
      break;
    case PointshellMethod::voxels:
      samples = contact::voxel_pointshell(surface, shell.cell_size, progress);
      break;
  }
  contact::NestedLevelOptions nested = shell.nested;
  nested.progress = progress;
  return contact::nested_pointshell(samples, nested);
}

}  // namespace khz::scene::detail
