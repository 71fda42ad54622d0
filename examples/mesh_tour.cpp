// mesh_tour: load a surface mesh, check it, repair it and save it for ParaView.
//
//   mesh_tour [MESH] [OUTPUT.vtu]
//
// Defaults to CGAL's dino.off. Shows the mesh I/O and diagnosis API of libreduced.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  namespace kr = khz::reduced;
  const std::filesystem::path input =
      argc > 1 ? argv[1] : std::filesystem::path(KHZ_CGAL_MESH_DIR) / "dino.off";
  const std::filesystem::path output = argc > 2 ? argv[2] : "mesh_tour.vtu";
  try {
    kr::TriangleMesh mesh = kr::read_triangle_mesh(input);  // format from the extension
    std::cout << "read " << input << "\n" << kr::analyze_mesh(mesh);

    // Weld exact duplicates, drop degenerate triangles, make orientation consistent.
    const kr::RepairSummary summary = kr::repair_mesh(mesh);
    std::cout << "\nrepair: welded " << summary.vertices_welded << " vertices, removed "
              << summary.triangles_removed
              << " triangles, consistently oriented: " << (summary.oriented ? "yes" : "no") << "\n";

    kr::write_triangle_mesh(output, mesh);
    std::cout << "wrote " << output << " (open it in ParaView)\n";
  } catch (const kr::Error& error) {
    std::cerr << "mesh_tour: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
