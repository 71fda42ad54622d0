#include "product_builders.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>
#include <khz/reduced/stage_progress.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace khz::scene::detail {

reduced::VolumeMesh compute_volume_mesh(const reduced::TriangleMesh& surface,
                                        const MeshingDescription& meshing,
                                        const reduced::ProgressCallback& progress) {
  // Neither mesher reports progress; one stage of one unit says which one runs.
  if (meshing.method == MeshingMethod::voxels) {
    reduced::StageProgress stage(progress, "voxelization", 1);
    reduced::VolumeMesh mesh = reduced::voxelize(surface, meshing.voxels);
    stage.finish();
    return mesh;
  }
  require_closed_surface(surface, "it cannot be tetrahedralized",
                         "set \"fill_holes\": true on the object to close small holes, or "
                         "mesh it with \"meshing\": {\"method\": \"voxels\"}, which takes any "
                         "surface");
  reduced::StageProgress stage(progress, "tetrahedralization", 1);
  reduced::VolumeMesh mesh = reduced::tetrahedralize(surface, meshing.tetrahedra);
  stage.finish();
  return mesh;
}

void write_volume_mesh_file(const reduced::VolumeMesh& mesh, const std::filesystem::path& file) {
  // format_gmsh() writes coordinates as the shortest text that reads back exactly, so the model
  // file's mesh fingerprint still matches after a read.
  const std::string text = reduced::format_gmsh(mesh);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw reduced::IoError("cannot write the volume mesh " + file.string());
}

reduced::VolumeMesh read_volume_mesh_file(const std::filesystem::path& file,
                                          const std::filesystem::path& model_file) {
  reduced::VolumeMesh mesh = reduced::read_volume_mesh(file);
  std::error_code error;
  if (!std::filesystem::exists(model_file, error)) return mesh;
  std::uint64_t stored = 0;
  try {
    stored = reduced::read_reduced_model_info(model_file).basis.fingerprint;
  } catch (const reduced::ParseError&) {
    return mesh;  // a damaged model file is the model's read to report
  }
  if (const std::uint64_t read = reduced::mesh_fingerprint(mesh); read != stored) {
    throw reduced::ParseError::at_byte(
        file.string(), 0,
        "not the mesh the reduced model " + model_file.filename().string() +
            " was computed on (fingerprint " + std::to_string(read) + ", the model's " +
            std::to_string(stored) + "): the file is damaged");
  }
  return mesh;
}

std::vector<int> anchored_vertices(const reduced::VolumeMesh& mesh,
                                   const std::vector<AnchorRegion>& regions) {
  std::vector<int> fixed;
  if (regions.empty()) return fixed;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    if (std::any_of(regions.begin(), regions.end(),
                    [&](const AnchorRegion& region) { return region.contains(p); })) {
      fixed.push_back(static_cast<int>(v));
    }
  }
  if (fixed.empty()) {
    // An anchored object that silently came out free-floating would surprise: say where the
    // vertices are, so the regions can be moved onto them.
    std::ostringstream message;
    message << "the anchors select none of the volume mesh's " << mesh.num_vertices()
            << " vertices, which span [" << mesh.vertices.colwise().minCoeff() << "] to ["
            << mesh.vertices.colwise().maxCoeff() << "] (body frame, m)";
    throw reduced::Error(message.str());
  }
  if (static_cast<Eigen::Index>(fixed.size()) == mesh.num_vertices()) {
    throw reduced::Error("the anchors select all " + std::to_string(mesh.num_vertices()) +
                         " of the volume mesh's vertices: nothing is left to deform (make the "
                         "\"anchors\" regions cover only the part held fixed)");
  }
  return fixed;
}

}  // namespace khz::scene::detail
