// Links only Kilohertz::reduced from an install prefix: the mesh layer judges a tetrahedron.
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/version.hpp>

#include <cstring>
#include <iostream>

int main() {
  if (std::strcmp(khz::reduced::library_version(), KHZ_REDUCED_VERSION_STRING) != 0) {
    std::cerr << "libkhz_reduced " << khz::reduced::library_version()
              << " differs from its headers' " << KHZ_REDUCED_VERSION_STRING << "\n";
    return 1;
  }
  const char* tetrahedron =
      "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const khz::reduced::MeshReport report =
      khz::reduced::analyze_mesh(khz::reduced::parse_off(tetrahedron, "tetrahedron.off"));
  if (!report.closed || !report.consistently_oriented) {
    std::cerr << "installed libreduced misjudged a tetrahedron:\n" << report;
    return 1;
  }
  std::cout << "Kilohertz::reduced " << khz::reduced::library_version()
            << ": tetrahedron closed and oriented, volume " << report.signed_volume << "\n";
  return 0;
}
