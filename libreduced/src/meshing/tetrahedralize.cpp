// The only translation unit that includes CGAL Mesh_3 (it is heavy to compile).
#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/make_mesh_3.h>

#include <cmath>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_3<SurfaceMesh, Kernel>;
// Sequential: the parallel mesher's result depends on thread scheduling.
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

void check_options(const TetrahedralizeOptions& options) {
  for (const auto& [name, value] : {std::pair{"facet_size", options.facet_size},
                                    {"facet_distance", options.facet_distance},
                                    {"cell_size", options.cell_size},
                                    {"sliver_bound", options.sliver_bound}}) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw Error(std::string("tetrahedralize: ") + name + " must be finite and >= 0, got " +
                  std::to_string(value));
    }
  }
  if (!(options.facet_angle >= 0.0 && options.facet_angle <= 30.0)) {
    throw Error("tetrahedralize: facet_angle must be in [0, 30] degrees, got " +
                std::to_string(options.facet_angle));
  }
  if (!(options.cell_radius_edge_ratio >= 2.0) || !std::isfinite(options.cell_radius_edge_ratio)) {
    throw Error("tetrahedralize: cell_radius_edge_ratio must be finite and >= 2, got " +
                std::to_string(options.cell_radius_edge_ratio));
  }
}

/// Mesh_3 decides inside/outside by ray parity and walks the surface's facets, so it needs a
/// watertight, manifold surface. Diagnosing with analyze_mesh() first gives a message that says
/// what to fix instead of a CGAL failure or a silently wrong volume.
MeshReport check_surface(const TriangleMesh& surface) {
  const MeshReport report = analyze_mesh(surface);
  std::vector<std::string> problems;
  if (report.num_triangles == 0) problems.push_back("it has no triangles");
  if (report.num_non_manifold_edges > 0) {
    problems.push_back(std::to_string(report.num_non_manifold_edges) + " non-manifold edges");
  }
  if (report.num_non_manifold_vertices > 0) {
    problems.push_back(std::to_string(report.num_non_manifold_vertices) + " non-manifold vertices");
  }
  if (report.num_boundary_edges > 0) {
    problems.push_back("it is not closed (" + std::to_string(report.num_boundary_edges) +
                       " boundary edges)");
  }
  if (report.edge_manifold && !report.consistently_oriented) {
    problems.push_back("it is not consistently oriented");
  }
  if (!report.degenerate_triangles.empty()) {
    problems.push_back(std::to_string(report.degenerate_triangles.size()) +
                       " degenerate triangles (first: " +
                       std::to_string(report.degenerate_triangles.front()) + ")");
  }
  if (problems.empty()) return report;
  std::ostringstream message;
  message << "tetrahedralize needs a closed, manifold, consistently oriented surface, but ";
  for (std::size_t i = 0; i < problems.size(); ++i) message << (i > 0 ? ", " : "") << problems[i];
  message << "; repair it with repair_mesh(), or voxelize() it if it is a polygon soup";
  throw MeshError(message.str());
}

SurfaceMesh to_surface_mesh(const TriangleMesh& surface) {
  SurfaceMesh mesh;
  mesh.reserve(SurfaceMesh::size_type(surface.num_vertices()), 0,
               SurfaceMesh::size_type(surface.num_triangles()));
  for (Eigen::Index v = 0; v < surface.num_vertices(); ++v) {
    mesh.add_vertex(Point(surface.vertices(v, 0), surface.vertices(v, 1), surface.vertices(v, 2)));
  }
  for (Eigen::Index t = 0; t < surface.num_triangles(); ++t) {
    mesh.add_face(SurfaceMesh::Vertex_index(surface.triangles(t, 0)),
                  SurfaceMesh::Vertex_index(surface.triangles(t, 1)),
                  SurfaceMesh::Vertex_index(surface.triangles(t, 2)));
  }
  return mesh;
}

/// The cells of the complex as a VolumeMesh. Vertices are numbered in order of first use by the
/// cells (deterministic, as the complex's iteration order is). CGAL stores cells positively
/// oriented in its sense, (p1−p0)·((p2−p0)×(p3−p0)) > 0, which is VolumeMesh's; the exact
/// orientation test makes that an enforced invariant rather than an assumption.
VolumeMesh to_volume_mesh(const Complex& complex) {
  std::unordered_map<Triangulation::Vertex_handle, int> index;
  std::vector<Point> points;
  VolumeMesh mesh;
  mesh.element_type = ElementType::tetrahedron;
  mesh.elements.resize(Eigen::Index(complex.number_of_cells_in_complex()), 4);
  Eigen::Index e = 0;
  for (auto cell = complex.cells_in_complex_begin(); cell != complex.cells_in_complex_end();
       ++cell) {
    for (int a = 0; a < 4; ++a) {
      const auto [it, inserted] = index.try_emplace(cell->vertex(a), int(points.size()));
      if (inserted) points.push_back(cell->vertex(a)->point().point());
      mesh.elements(e, a) = it->second;
    }
    const auto& p = [&](int a) -> const Point& { return points[mesh.elements(e, a)]; };
    if (CGAL::orientation(p(0), p(1), p(2), p(3)) == CGAL::NEGATIVE) {
      std::swap(mesh.elements(e, 2), mesh.elements(e, 3));
    }
    ++e;
  }
  mesh.vertices.resize(Eigen::Index(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) {
    mesh.vertices.row(Eigen::Index(v)) << points[v].x(), points[v].y(), points[v].z();
  }
  return mesh;
}

}  // namespace

VolumeMesh tetrahedralize(const TriangleMesh& closed_surface,
                          const TetrahedralizeOptions& options) {
  check_options(options);
  const MeshReport report = check_surface(closed_surface);
  const double diagonal = report.bounding_box.diagonal().norm();
  const auto or_automatic = [](double value, double automatic) {
    return value > 0.0 ? value : automatic;
  };
  const double facet_size = or_automatic(options.facet_size, diagonal / 45);
  const SurfaceMesh surface = to_surface_mesh(closed_surface);

  // Every random choice (initial points on the surface, perturbation) draws from these two
  // generators; seeding both makes a run reproducible.
  CGAL::Random domain_random(options.seed);
  const Domain domain(surface, &domain_random);
  CGAL::get_default_random() = CGAL::Random(options.seed);

  namespace p = CGAL::parameters;
  const Criteria criteria(p::facet_angle = options.facet_angle, p::facet_size = facet_size,
                          p::facet_distance = or_automatic(options.facet_distance, diagonal / 1000),
                          p::cell_radius_edge_ratio = options.cell_radius_edge_ratio,
                          p::cell_size = or_automatic(options.cell_size, facet_size));
  // Perturbation and exudation stop by default after as much wall-clock time as refinement
  // took, which makes the result depend on the machine's load; time_limit = 0 removes that
  // limit and the sliver bound ends them instead.
  const double bound = options.sliver_bound;
  const Complex complex = CGAL::make_mesh_3<Complex>(
      domain, criteria, p::no_lloyd(), p::no_odt(),
      options.perturb ? p::perturb(p::time_limit = 0, p::sliver_bound = bound) : p::no_perturb(),
      options.exude ? p::exude(p::time_limit = 0, p::sliver_bound = bound) : p::no_exude());
  VolumeMesh mesh = to_volume_mesh(complex);
  if (mesh.num_elements() == 0) {
    throw Error("tetrahedralize produced no tetrahedra; the sizes are too coarse for the surface");
  }
  return mesh;
}

}  // namespace khz::reduced
