// meshing_tour: turn a surface into simulation meshes, both ways libreduced offers.
//
//   meshing_tour [MESH] [RESOLUTION]
//
// Defaults to CGAL's dino.off at resolution 32. Voxelizes the surface into hexahedra
// (works for any polygon soup) and, if the surface is closed and manifold, tetrahedralizes it
// with CGAL Mesh_3; prints each mesh's element quality and writes meshing_tour_hex.vtu and
// meshing_tour_tet.vtu with the per-element quality as a cell array for ParaView.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include <filesystem>
#include <iostream>
#include <string>

namespace {

namespace kr = khz::reduced;

void report_and_write(const kr::VolumeMesh& mesh, const std::filesystem::path& output) {
  const kr::QualityReport quality = kr::analyze_elements(mesh);
  std::cout << mesh.num_vertices() << " vertices\n" << quality;
  kr::VtkFields fields;
  fields.cell_data.push_back(
      {"quality", Eigen::Map<const Eigen::VectorXd>(quality.quality.data(),
                                                    Eigen::Index(quality.quality.size()))});
  kr::write_volume_mesh(output, mesh, fields);
  std::cout << "wrote " << output << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path input =
      argc > 1 ? argv[1] : std::filesystem::path(KHZ_CGAL_MESH_DIR) / "dino.off";
  try {
    const kr::TriangleMesh surface = kr::read_triangle_mesh(input);
    const kr::MeshReport report = kr::analyze_mesh(surface);
    std::cout << "read " << input << ": " << report.num_triangles << " triangles, "
              << (report.closed ? "closed" : "not closed") << "\n";

    // Thesis §2.5.2: a cube grid around the model, the voxels touching it, here filled.
    kr::VoxelizeOptions voxel_options;
    voxel_options.resolution = argc > 2 ? std::stoi(argv[2]) : 32;
    voxel_options.fill_interior = true;
    std::cout << "\nvoxelize at resolution " << voxel_options.resolution << ":\n";
    report_and_write(kr::voxelize(surface, voxel_options), "meshing_tour_hex.vtu");

    std::cout << "\ntetrahedralize with the default criteria:\n";
    try {
      report_and_write(kr::tetrahedralize(surface), "meshing_tour_tet.vtu");
    } catch (const kr::MeshError& error) {
      std::cout << "skipped: " << error.what() << "\n";  // an open or non-manifold surface
    }
  } catch (const kr::Error& error) {
    std::cerr << "meshing_tour: " << error.what() << "\n";
    return 1;
  } catch (const std::logic_error& error) {  // std::stoi on a bad RESOLUTION
    std::cerr << "meshing_tour: bad resolution: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
