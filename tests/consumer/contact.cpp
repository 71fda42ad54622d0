// Links only Kilohertz::contact from an install prefix (libkhz_contact.so finds libkhz_reduced.so
// by its own run path): four points of a pointshell pressed into a floor.
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/version.hpp>

#include <cstring>
#include <iostream>

int main() {
  if (std::strcmp(khz::contact::library_version(), KHZ_CONTACT_VERSION_STRING) != 0) {
    std::cerr << "libkhz_contact " << khz::contact::library_version()
              << " differs from its headers' " << KHZ_CONTACT_VERSION_STRING << "\n";
    return 1;
  }
  // The header-only contact query, compiled here against installed headers: four points pressed
  // 1 cm into a floor push it down.
  khz::contact::Pointshell shell;
  shell.points.resize(4, 3);
  shell.normals.resize(4, 3);
  shell.points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  shell.normals.rowwise() = Eigen::RowVector3d(0, 0, 1);
  shell.level_ends = {1, 4};
  const khz::contact::PointTree tree(shell);
  const khz::contact::ImplicitShape floor = khz::contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  khz::contact::ContactWorkspace workspace(tree, khz::contact::ContactOptions{});
  khz::contact::ContactFrames frames;
  frames.pointshell.translation() = Eigen::Vector3d(0, 0, -0.01);
  if (!khz::contact::query_contact(tree, floor, frames, workspace) ||
      workspace.result().statistics.points_in_contact != 4 ||
      !(workspace.result().force.z() < 0.0)) {
    std::cerr << "installed libcontact's query did not find the four points in the floor\n";
    return 1;
  }
  std::cout << "Kilohertz::contact " << khz::contact::library_version() << ": contact force "
            << workspace.result().force.z() << " N\n";
  return 0;
}
