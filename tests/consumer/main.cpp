// Links all three installed Kilohertz libraries through Kilohertz::haptic and exercises them.
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/version.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/version.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/version.hpp>

#include <cstring>
#include <iostream>

int main() {
  const char* versions[] = {khz::reduced::library_version(), khz::contact::library_version(),
                            khz::haptic::library_version()};
  for (const char* version : versions) {
    if (std::strcmp(version, KHZ_REDUCED_VERSION_STRING) != 0) {
      std::cerr << "library version " << version << " differs from the headers' "
                << KHZ_REDUCED_VERSION_STRING << "\n";
      return 1;
    }
  }
  const char* tetrahedron =
      "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const khz::reduced::MeshReport report =
      khz::reduced::analyze_mesh(khz::reduced::parse_off(tetrahedron, "tetrahedron.off"));
  if (!report.closed || !report.consistently_oriented) {
    std::cerr << "installed libreduced misjudged a tetrahedron:\n" << report;
    return 1;
  }
  // The header-only contact query and the coupling, compiled here against installed headers:
  // four points pressed 1 cm into a floor push it down and the coupling renders the reaction.
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
  khz::haptic::VirtualCoupling coupling(khz::haptic::CouplingOptions{});
  const khz::haptic::CouplingStep step = coupling.step({}, workspace.result());
  if (!step.valid) {
    std::cerr << "installed libhaptic's coupling refused a finite contact\n";
    return 1;
  }
  std::cout << "Kilohertz " << versions[0] << ": reduced, contact and haptic linked; "
            << "tetrahedron closed and oriented, volume " << report.signed_volume
            << "; contact force " << workspace.result().force.z() << " N\n";
  return 0;
}
