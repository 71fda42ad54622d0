// kilohertz.reduced: volume meshing, materials, the full FEM model (mass, K, R, energy) and its
// Newmark integrator, the reference reduced models are measured against.

#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"

namespace khz::python {

namespace {

using reduced::FemModel;
using reduced::Material;
using reduced::TriangleMesh;
using reduced::VolumeMesh;

void bind_meshing(py::module_& module) {
  const auto box = [&module](const char* name, auto make, const char* doc) {
    module.def(
        name,
        [make](const py::handle& min_corner, const py::handle& max_corner,
               const std::array<int, 3>& cells) {
          return make(vector3_in(min_corner, "min_corner"), vector3_in(max_corner, "max_corner"),
                      Eigen::Vector3i(cells[0], cells[1], cells[2]));
        },
        py::arg("min_corner"), py::arg("max_corner"), py::arg("cells"), doc);
  };
  box("box_hex_mesh", &reduced::box_hex_mesh,
      "The box [min_corner, max_corner] (m) in cells (nx, ny, nz) hexahedra; vertex (i, j, k) "
      "has index i + (nx+1)(j + (ny+1)k). Raises Error for cells < 1 or an empty box.");
  box("box_tet_mesh", &reduced::box_tet_mesh,
      "box_hex_mesh() with each cell split into six tetrahedra (same vertices).");
  module.def(
      "voxelize",
      [](const TriangleMesh& mesh, int resolution, double enlargement, bool fill_interior) {
        const py::gil_scoped_release unlocked;
        return reduced::voxelize(
            mesh,
            {.resolution = resolution, .enlargement = enlargement, .fill_interior = fill_interior});
      },
      py::arg("mesh"), py::arg("resolution") = 64, py::arg("enlargement") = 1.2,
      py::arg("fill_interior") = false,
      R"(Hexahedra on the voxels a surface touches (thesis §2.5.2), for any triangle set (soups,
open or self-intersecting surfaces): resolution voxels per side of a cube `enlargement` times the
mesh's largest extent; fill_interior keeps the enclosed voxels too.)");
  module.def(
      "tetrahedralize",
      [](const TriangleMesh& mesh, double facet_size, double facet_distance, double facet_angle,
         double cell_size, double cell_radius_edge_ratio, std::uint32_t seed) {
        reduced::TetrahedralizeOptions options;
        options.facet_size = facet_size;
        options.facet_distance = facet_distance;
        options.facet_angle = facet_angle;
        options.cell_size = cell_size;
        options.cell_radius_edge_ratio = cell_radius_edge_ratio;
        options.seed = seed;
        const py::gil_scoped_release unlocked;
        return reduced::tetrahedralize(mesh, options);
      },
      py::arg("mesh"), py::arg("facet_size") = 0.0, py::arg("facet_distance") = 0.0,
      py::arg("facet_angle") = 25.0, py::arg("cell_size") = 0.0,
      py::arg("cell_radius_edge_ratio") = 2.0, py::arg("seed") = 0,
      R"(Tetrahedra filling a closed, oriented surface (CGAL Mesh_3). Sizes in m (0: chosen from
the mesh's size); the same seed gives the same mesh. Raises MeshError for an open or
self-intersecting surface.)");
}

void bind_material(py::module_& module) {
  py::class_<Material>(module, "Material", R"(A linear material of the FEM model: StVK (Lamé λ, μ)
or a general 6×6 elasticity in Voigt order, with a density (khz::reduced::Material).)")
      .def_static("stvk", &Material::stvk, py::arg("young_modulus"), py::arg("poisson_ratio"),
                  py::arg("density"),
                  "StVK from Young's modulus (Pa) and Poisson's ratio (< 0.5); density kg/m³.")
      .def_static(
          "stvk_lame",
          [](double lambda, double mu, double density) {
            return Material::stvk_lame({.lambda = lambda, .mu = mu}, density);
          },
          py::arg("lame_lambda"), py::arg("lame_mu"), py::arg("density"),
          "StVK from the Lamé parameters λ, μ (Pa).")
      .def_static(
          "general",
          [](const py::handle& elasticity, double density) {
            return Material::general(real_matrix(elasticity, "elasticity", 6, 6), density);
          },
          py::arg("elasticity"), py::arg("density"),
          "A general linear material: elasticity (6, 6) Pa, symmetric positive definite.")
      .def_property_readonly("elasticity",
                             [](const Material& m) {
                               const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c =
                                   m.elasticity();
                               return copy_of(c);
                             })
      .def_property_readonly("density", &Material::density, "kg/m³.")
      .def(py::pickle(
          [](const Material& m) {
            const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c = m.elasticity();
            return py::make_tuple(m.is_stvk(), m.lame().lambda, m.lame().mu, copy_of(c),
                                  m.density());
          },
          [](const py::tuple& state) {
            if (state.size() != 5) throw py::value_error("Material: bad pickle state");
            if (state[0].cast<bool>()) {
              return Material::stvk_lame(
                  {.lambda = state[1].cast<double>(), .mu = state[2].cast<double>()},
                  state[4].cast<double>());
            }
            return Material::general(real_matrix(state[3], "elasticity", 6, 6),
                                     state[4].cast<double>());
          }))
      .def_property_readonly("is_stvk", &Material::is_stvk)
      .def_property_readonly(
          "lame", [](const Material& m) { return py::make_tuple(m.lame().lambda, m.lame().mu); },
          "(λ, μ) in Pa, for StVK materials.");
}

Eigen::VectorXd dofs_in(const FemModel& model, const py::handle& input, const char* what) {
  return real_vector(input, what, model.num_dofs());
}

void bind_fem_model(py::module_& module) {
  py::class_<FemModel>(module, "FemModel", R"(The geometrically nonlinear FEM model of a volume
mesh (khz::reduced::FemModel): mass, internal forces R(u), tangent stiffness K(u) and strain
energy, with u the 3n displacements (m), vertex-major (x, y, z of vertex 0, then vertex 1, ...),
given as (3n,) or (n, 3). Sparse results are scipy.sparse CSC matrices.)")
      .def(py::init([](const VolumeMesh& mesh, const py::object& materials) {
             std::vector<Material> list;
             if (py::isinstance<Material>(materials)) {
               list.push_back(materials.cast<Material>());
             } else {
               list = materials.cast<std::vector<Material>>();
             }
             const py::gil_scoped_release unlocked;
             return FemModel(mesh, std::move(list));
           }),
           py::arg("mesh"), py::arg("materials"),
           "materials: one Material, or a list indexed by the mesh's element_groups. Raises "
           "MeshError naming the first inverted element.")
      .def_property_readonly("num_dofs", &FemModel::num_dofs, "3n.")
      .def_property_readonly("mesh", &FemModel::mesh, py::return_value_policy::copy)
      .def(
          "mass_matrix",
          [](const FemModel& model, bool lumped) {
            return sparse_out(model.mass_matrix(lumped ? reduced::MassLumping::lumped
                                                       : reduced::MassLumping::consistent));
          },
          py::arg("lumped") = false, "M (kg), 3n×3n, consistent or lumped.")
      .def(
          "internal_forces",
          [](const FemModel& model, const py::handle& u) {
            Eigen::VectorXd forces;
            const Eigen::VectorXd displacement = dofs_in(model, u, "u");
            {
              const py::gil_scoped_release unlocked;
              model.internal_forces(displacement, forces);
            }
            return vector_out(forces);
          },
          py::arg("u"), "R(u) = ∂E/∂u (N), (3n,).")
      .def(
          "stiffness_matrix",
          [](const FemModel& model, const py::object& u) {
            const Eigen::VectorXd displacement =
                u.is_none() ? Eigen::VectorXd::Zero(model.num_dofs()) : dofs_in(model, u, "u");
            reduced::SparseMatrix stiffness = model.stiffness_pattern();
            {
              const py::gil_scoped_release unlocked;
              model.tangent_stiffness(displacement, stiffness);
            }
            return sparse_out(stiffness);
          },
          py::arg("u") = py::none(), "K(u) = ∂R/∂u (N/m), 3n×3n; u = None: the rest shape.")
      .def(
          "strain_energy",
          [](const FemModel& model, const py::handle& u) {
            return model.strain_energy(dofs_in(model, u, "u"));
          },
          py::arg("u"), "E(u) (J).");
}

/// FullNewmark with the size of its vectors, which it does not expose.
struct FullNewmarkRun {
  reduced::FullNewmark integrator;
  Eigen::Index dofs;
};

void bind_full_newmark(py::module_& module) {
  py::class_<FullNewmarkRun>(module, "FullNewmark", R"(Implicit Newmark on the full FEM model
with Newton iterations and Rayleigh damping (thesis §2.9): the reference a reduced model is
checked against (khz::reduced::FullNewmark). Vectors are (3n,) or (n, 3); keeps the model alive.)")
      .def(py::init([](const FemModel& model, const py::handle& fixed_vertices, double time_step,
                       double beta, double gamma, double mass_damping, double stiffness_damping,
                       bool lumped, int max_newton_iterations, double tolerance) {
             reduced::FullNewmarkOptions options;
             options.newmark = {time_step, beta, gamma, mass_damping, stiffness_damping};
             options.mass =
                 lumped ? reduced::MassLumping::lumped : reduced::MassLumping::consistent;
             options.max_newton_iterations = max_newton_iterations;
             options.tolerance = tolerance;
             return FullNewmarkRun{
                 reduced::FullNewmark(model, index_list(fixed_vertices, "fixed_vertices"), options),
                 model.num_dofs()};
           }),
           py::arg("model"), py::arg("fixed_vertices") = std::vector<int>{}, py::kw_only(),
           py::arg("time_step") = 1e-3, py::arg("beta") = 0.25, py::arg("gamma") = 0.5,
           py::arg("mass_damping") = 0.0, py::arg("stiffness_damping") = 0.0,
           py::arg("lumped") = false, py::arg("max_newton_iterations") = 10,
           py::arg("tolerance") = 1e-9, py::keep_alive<1, 2>(),
           "fixed_vertices: vertex indices held at zero displacement; time_step s; Rayleigh "
           "mass_damping (1/s) and stiffness_damping (s). Raises Error for invalid options.")
      .def(
          "step",
          [](FullNewmarkRun& run, const py::handle& force) {
            const Eigen::VectorXd f = real_vector(force, "force", run.dofs);
            reduced::StepReport report;
            {
              const py::gil_scoped_release unlocked;
              report = run.integrator.step(f);
            }
            return py::make_tuple(report.converged, report.iterations, report.residual_norm);
          },
          py::arg("force"),
          "One step under the external force (N), held over the step; returns (converged, "
          "iterations, residual N). Raises SolverError if Newton diverges (state unchanged).")
      .def(
          "set_state",
          [](FullNewmarkRun& run, const py::handle& u, const py::handle& v, const py::handle& a) {
            run.integrator.set_state(real_vector(u, "displacement", run.dofs),
                                     real_vector(v, "velocity", run.dofs),
                                     real_vector(a, "acceleration", run.dofs));
          },
          py::arg("displacement"), py::arg("velocity"), py::arg("acceleration"),
          "Sets u (m), u̇ (m/s), ü (m/s²); fixed dofs are zeroed.")
      .def_property_readonly(
          "displacement",
          [](const FullNewmarkRun& r) { return vector_out(r.integrator.displacement()); },
          "u (m), (3n,).")
      .def_property_readonly(
          "velocity", [](const FullNewmarkRun& r) { return vector_out(r.integrator.velocity()); },
          "u̇ (m/s), (3n,).")
      .def_property_readonly(
          "time", [](const FullNewmarkRun& r) { return r.integrator.time(); }, "Steps × Δt (s).")
      .def_property_readonly(
          "kinetic_energy", [](const FullNewmarkRun& r) { return r.integrator.kinetic_energy(); },
          "J.")
      .def_property_readonly(
          "strain_energy", [](const FullNewmarkRun& r) { return r.integrator.strain_energy(); },
          "J.");
}

}  // namespace

void bind_reduced_fem(py::module_& reduced) {
  bind_meshing(reduced);
  bind_material(reduced);
  bind_fem_model(reduced);
  bind_full_newmark(reduced);
}

}  // namespace khz::python
