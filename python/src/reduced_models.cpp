// kilohertz.reduced: bases (linear modes, modal derivatives, mass-PCA, simulation data), basis
// files and exports, the reduced model (precompute, material edits, files), its integrators
// stepped with reduced forces, and the reconstruction of positions and normals.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/io/basis_export.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/subspace/central_differences.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reconstruction.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "progress.hpp"

namespace khz::python {

namespace {

using reduced::Basis;
using reduced::FemModel;
using reduced::ReducedModel;

using ColumnMajor = Eigen::MatrixXd;

/// A NumPy copy of a column-major matrix (Fortran order, as Eigen stores it).
py::array matrix_out(const ColumnMajor& matrix) {
  const auto item = static_cast<py::ssize_t>(sizeof(double));
  return py::array_t<double>({matrix.rows(), matrix.cols()}, {item, item * matrix.rows()},
                             matrix.data());
}

reduced::PcaMetric metric_from(const std::string& name) {
  if (name == "mass") return reduced::PcaMetric::mass;
  if (name == "lumped_mass") return reduced::PcaMetric::lumped_mass;
  throw py::value_error("metric: expected 'mass' or 'lumped_mass', got '" + name + "'");
}

void bind_basis(py::module_& module) {
  py::class_<Basis>(module, "Basis", R"(A reduced basis of a volume mesh
(khz::reduced::Basis): vectors U (3n, r) m per unit of q, mass-orthonormal from the generators,
with zero rows at fixed_vertices; recipe says how it was made.)")
      .def(py::init(
               [](const py::handle& vectors, const py::handle& fixed_vertices, std::string recipe) {
                 const auto array = py::array::ensure(vectors);
                 if (!array || array.ndim() != 2)
                   throw py::value_error("vectors: expected (3n, r)");
                 return Basis{real_matrix(array, "vectors", -1, array.shape(1)),
                              index_list(fixed_vertices, "fixed_vertices"), std::move(recipe)};
               }),
           py::arg("vectors"), py::arg("fixed_vertices") = std::vector<int>{},
           py::arg("recipe") = "")
      .def_property_readonly(
          "vectors", [](const Basis& b) { return matrix_out(b.vectors); }, "U, (3n, r).")
      .def_readonly("fixed_vertices", &Basis::fixed_vertices)
      .def_readonly("recipe", &Basis::recipe)
      .def_property_readonly("size", &Basis::size, "r.")
      .def("__repr__",
           [](const Basis& b) {
             return "Basis(r=" + std::to_string(b.size()) +
                    ", 3n=" + std::to_string(b.vectors.rows()) + ", '" + b.recipe + "')";
           })
      .def(py::pickle(
          [](const Basis& b) {
            return py::make_tuple(matrix_out(b.vectors), b.fixed_vertices, b.recipe);
          },
          [](const py::tuple& state) {
            const auto array = py::array::ensure(state[0]);
            return Basis{real_matrix(array, "vectors", -1, array.shape(1)),
                         state[1].cast<std::vector<int>>(), state[2].cast<std::string>()};
          }));
  module.def(
      "write_basis",
      [](const std::filesystem::path& file, const Basis& basis, const reduced::VolumeMesh& mesh) {
        const py::gil_scoped_release unlocked;
        reduced::write_basis(file, basis, mesh);
      },
      py::arg("file"), py::arg("basis"), py::arg("mesh"),
      "Writes a .khzbasis file (checksummed, tied to the mesh's fingerprint).");
  module.def(
      "read_basis",
      [](const std::filesystem::path& file, const reduced::VolumeMesh& mesh) {
        const py::gil_scoped_release unlocked;
        return reduced::read_basis(file, mesh);
      },
      py::arg("file"), py::arg("mesh"),
      "Reads a .khzbasis file; ParseError if it is corrupt or belongs to another mesh.");
  module.def("write_basis_npy", &reduced::write_basis_npy, py::arg("file"), py::arg("basis"),
             "Exports U as a NumPy .npy file (float64, (3n, r)).");
  module.def("write_basis_mat", &reduced::write_basis_mat, py::arg("file"), py::arg("basis"),
             "Exports U as a MATLAB Level 5 .mat file.");
}

void bind_generators(py::module_& module) {
  py::class_<reduced::LinearModes>(module, "LinearModes",
                                   "The lowest vibration modes (khz::reduced::LinearModes).")
      .def_property_readonly(
          "eigenvalues", [](const reduced::LinearModes& m) { return vector_out(m.eigenvalues); },
          "ω² (1/s²), ascending.")
      .def_property_readonly(
          "modes", [](const reduced::LinearModes& m) { return matrix_out(m.modes); },
          "(3n, k), mass-orthonormal.")
      .def_property_readonly(
          "frequencies_hz",
          [](const reduced::LinearModes& m) { return vector_out(m.frequencies_hz()); })
      .def_readonly("fixed_vertices", &reduced::LinearModes::fixed_vertices);
  module.def(
      "linear_modes",
      [](const FemModel& model, const py::handle& fixed_vertices, int num_modes,
         const py::object& progress) {
        const auto fixed = index_list(fixed_vertices, "fixed_vertices");
        reduced::LinearModesOptions options;
        options.num_modes = num_modes;
        options.progress = python_progress(progress);
        const py::gil_scoped_release unlocked;
        return reduced::compute_linear_modes(model, fixed, options);
      },
      py::arg("model"), py::arg("fixed_vertices") = std::vector<int>{}, py::kw_only(),
      py::arg("num_modes") = 20, py::arg("progress") = py::none(),
      R"(The num_modes lowest modes of K(0) u = ω² M u with the fixed vertices held (ARPACK
shift-invert); an unanchored model also reports its rigid modes apart. progress and Ctrl-C as
signed_distance_field().)");
  module.def(
      "modal_derivatives",
      [](const FemModel& model, const reduced::LinearModes& modes, const py::object& progress) {
        reduced::ModalDerivativesOptions options;
        options.progress = python_progress(progress);
        const py::gil_scoped_release unlocked;
        return matrix_out(reduced::compute_modal_derivatives(model, modes, options).vectors);
      },
      py::arg("model"), py::arg("modes"), py::kw_only(), py::arg("progress") = py::none(),
      "The k(k+1)/2 modal derivatives of the modes (thesis eq. 2.47), (3n, k(k+1)/2).");
  module.def(
      "modal_derivative_basis",
      [](const FemModel& model, const py::handle& fixed_vertices, int basis_size, int num_modes,
         const std::string& metric, const py::object& progress) {
        const auto fixed = index_list(fixed_vertices, "fixed_vertices");
        reduced::ModalDerivativeBasisOptions options;
        options.basis_size = basis_size;
        options.metric = metric_from(metric);
        options.modes.num_modes = num_modes;
        options.progress = python_progress(progress);
        const py::gil_scoped_release unlocked;
        return reduced::modal_derivative_basis(model, fixed, options);
      },
      py::arg("model"), py::arg("fixed_vertices") = std::vector<int>{}, py::kw_only(),
      py::arg("basis_size") = 30, py::arg("num_modes") = 20, py::arg("metric") = "mass",
      py::arg("progress") = py::none(),
      R"(The thesis's basis (eq. 2.52): linear modes and their modal derivatives, weighted and
reduced to basis_size vectors by mass-PCA (metric 'mass' or 'lumped_mass').)");
  module.def(
      "principal_components",
      [](const py::handle& samples, const py::handle& mass, int basis_size,
         const std::string& metric) {
        const auto array = py::array::ensure(samples);
        if (!array || array.ndim() != 2) throw py::value_error("samples: expected (3n, s)");
        const ColumnMajor x = real_matrix(array, "samples", -1, array.shape(1));
        // The mass matrix as scipy.sparse (anything with .tocsc()) or a dense array.
        reduced::SparseMatrix m;
        if (py::hasattr(mass, "tocsc")) {
          const py::object csc = mass.attr("tocsc")();
          const auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
              csc.attr("data"));
          const auto indices = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(
              csc.attr("indices"));
          const auto indptr = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(
              csc.attr("indptr"));
          const auto shape = csc.attr("shape").cast<std::pair<Eigen::Index, Eigen::Index>>();
          m = Eigen::Map<const reduced::SparseMatrix>(shape.first, shape.second, data.size(),
                                                      indptr.data(), indices.data(), data.data());
        } else {
          m = real_matrix(mass, "mass", x.rows(), x.rows()).sparseView();
        }
        reduced::PcaOptions options;
        options.basis_size = basis_size;
        options.metric = metric_from(metric);
        reduced::PcaResult result;
        {
          const py::gil_scoped_release unlocked;
          result = reduced::principal_components(x, m, options);
        }
        return py::make_tuple(matrix_out(result.basis), vector_out(result.singular_values));
      },
      py::arg("samples"), py::arg("mass"), py::kw_only(), py::arg("basis_size") = 0,
      py::arg("metric") = "mass",
      R"(Mass-PCA of sample columns (3n, s) (thesis eq. 2.39–2.40): (basis (3n, r) M-orthonormal,
singular values). mass: scipy.sparse or dense (3n, 3n); basis_size 0 keeps the numerical rank.)");
  module.def(
      "sketch_basis",
      [](const FemModel& model, const py::handle& fixed_vertices, const py::handle& loads,
         int basis_size, double force_separation, double deformation_separation,
         const std::string& metric, bool skip_failed_solves, const py::object& progress) {
        const auto fixed = index_list(fixed_vertices, "fixed_vertices");
        const Eigen::Index vertices = model.num_dofs() / 3;
        std::vector<reduced::ForceLoad> list;
        if (py::isinstance<py::str>(loads) || py::hasattr(loads, "__fspath__")) {
          list = reduced::read_force_loads(loads.cast<std::filesystem::path>(), vertices);
        } else {
          for (const py::handle load : loads) {
            const auto pair = load.cast<py::tuple>();
            if (pair.size() != 2) {
              throw py::value_error("loads: each load is a (vertices, forces) pair");
            }
            const auto indices = index_list(pair[0], "load vertices");
            const auto forces =
                real_matrix(pair[1], "load forces", static_cast<Eigen::Index>(indices.size()), 3);
            reduced::ForceLoad force_load;
            for (std::size_t i = 0; i < indices.size(); ++i) {
              force_load.forces.push_back(
                  {indices[i], forces.row(static_cast<Eigen::Index>(i)).transpose()});
            }
            force_load.validate(vertices);
            list.push_back(std::move(force_load));
          }
        }
        reduced::SketchBasisOptions options;
        options.basis_size = basis_size;
        options.force_separation = force_separation;
        options.deformation_separation = deformation_separation;
        options.metric = metric_from(metric);
        options.skip_failed_solves = skip_failed_solves;
        options.progress = python_progress(progress);
        const py::gil_scoped_release unlocked;
        return reduced::sketch_basis(model, fixed, list, options);
      },
      py::arg("model"), py::arg("fixed_vertices"), py::arg("loads"), py::kw_only(),
      py::arg("basis_size"), py::arg("force_separation") = 0.0,
      py::arg("deformation_separation") = 0.0, py::arg("metric") = "mass",
      py::arg("skip_failed_solves") = false, py::arg("progress") = py::none(),
      R"(A basis from static deformations under example loads (thesis §2.8.2): loads is a load
file (CSV load,vertex,fx,fy,fz) or a list of (vertices (k,), forces (k, 3) N) pairs; loads closer
than force_separation (N) and deformations closer than deformation_separation (m·√kg) are
thinned, then mass-PCA keeps basis_size vectors. A failed static solve raises SolverError naming
the load, unless skip_failed_solves.)");
  module.def(
      "simulation_data_basis",
      [](const FemModel& model, const py::handle& fixed_vertices, const py::handle& snapshots,
         int basis_size, const py::object& progress) {
        const auto fixed = index_list(fixed_vertices, "fixed_vertices");
        const ColumnMajor x = real_matrix(snapshots, "snapshots", model.num_dofs(),
                                          py::array::ensure(snapshots).shape(1));
        reduced::SimulationDataBasisOptions options;
        options.progress = python_progress(progress);
        const py::gil_scoped_release unlocked;
        return reduced::simulation_data_basis(model, fixed, x, basis_size, options);
      },
      py::arg("model"), py::arg("fixed_vertices"), py::arg("snapshots"), py::arg("basis_size"),
      py::kw_only(), py::arg("progress") = py::none(),
      "A basis from displacement snapshots (3n, s) of a simulation (mass-PCA).");
}

/// A reduced integrator with the forces it steps: what a user holds to simulate a model.
struct ReducedSimulation {
  std::unique_ptr<reduced::PolynomialForces> forces;
  std::unique_ptr<reduced::ReducedIntegrator> integrator;
};

/// Overrides of the model's integrator defaults; None keeps the default.
struct IntegratorOverrides {
  py::object time_step, max_newton_iterations, tolerance;
  double acceleration_limit = std::numeric_limits<double>::infinity();
};

ReducedSimulation make_simulation(const ReducedModel& model, bool central_differences,
                                  const IntegratorOverrides& overrides) {
  const py::object& time_step = overrides.time_step;
  ReducedSimulation simulation;
  simulation.forces = std::make_unique<reduced::PolynomialForces>(model.energy_polynomial());
  if (central_differences) {
    reduced::ReducedCentralDifferencesOptions options;
    options.time_step =
        time_step.is_none() ? model.defaults().newmark.time_step : time_step.cast<double>();
    options.mass_damping = model.defaults().newmark.mass_damping;
    options.stiffness_damping = model.defaults().newmark.stiffness_damping;
    simulation.integrator =
        reduced::make_reduced_central_differences(*simulation.forces, model.mass(), options);
  } else {
    auto options = model.defaults().newmark_options();
    if (!time_step.is_none()) options.newmark.time_step = time_step.cast<double>();
    if (!overrides.max_newton_iterations.is_none()) {
      options.max_newton_iterations = overrides.max_newton_iterations.cast<int>();
    }
    if (!overrides.tolerance.is_none()) options.tolerance = overrides.tolerance.cast<double>();
    options.acceleration_limit = overrides.acceleration_limit;
    simulation.integrator =
        reduced::make_reduced_newmark(*simulation.forces, model.mass(), options);
  }
  return simulation;
}

void bind_model(py::module_& module) {
  py::class_<ReducedModel>(module, "ReducedModel", R"(A reduced nonlinear deformable model
(thesis §2.5–§2.6, §2.11; khz::reduced::ReducedModel): the basis, the exact reduced StVK energy
of each material group as a quartic polynomial in q, and the reduced mass. Materials change at
runtime without a new precompute.)")
      .def_static(
          "precompute",
          [](const FemModel& fem, const Basis& basis, const py::object& progress) {
            reduced::ReducedModelOptions options;
            options.progress = python_progress(progress);
            const py::gil_scoped_release unlocked;
            return ReducedModel::precompute(fem, basis, options);
          },
          py::arg("fem"), py::arg("basis"), py::kw_only(), py::arg("progress") = py::none(),
          "Precomputes the energy polynomials of `fem` in `basis` (about a second at r = 30 on "
          "11.5k tetrahedra). Raises Error for a basis of the wrong size; Cancelled.")
      .def_property_readonly("dimension", &ReducedModel::dimension, "r.")
      .def_property_readonly("basis", &ReducedModel::basis, py::return_value_policy::copy)
      .def_property_readonly("group_count", [](const ReducedModel& m) { return m.groups().size(); })
      .def_property_readonly(
          "mass", [](const ReducedModel& m) { return matrix_out(m.mass()); }, "M̃ (r, r).")
      .def(
          "set_lame",
          [](ReducedModel& m, int group, double lambda, double mu) {
            m.set_lame(group, {.lambda = lambda, .mu = mu});
          },
          py::arg("group"), py::arg("lame_lambda"), py::arg("lame_mu"),
          "Changes an StVK group's Lamé parameters (Pa); integrators made afterwards use them.")
      .def("set_density", &ReducedModel::set_density, py::arg("group"), py::arg("density"),
           "Changes a group's density (kg/m³).")
      .def("set_elasticity_scale", &ReducedModel::set_elasticity_scale, py::arg("group"),
           py::arg("scale"), "Scales a general group's elasticity.")
      .def("truncated", &ReducedModel::truncated, py::arg("dimension"),
           "The model in its first r' basis vectors.")
      .def(
          "energy",
          [](const ReducedModel& m, const py::handle& q) {
            reduced::PolynomialForces forces(m.energy_polynomial());
            return forces.energy(real_vector(q, "q", m.dimension()));
          },
          py::arg("q"), "The reduced strain energy Ẽ(q) (J).")
      .def(
          "forces",
          [](const ReducedModel& m, const py::handle& q) {
            reduced::PolynomialForces forces(m.energy_polynomial());
            Eigen::VectorXd r(m.dimension());
            Eigen::MatrixXd k(m.dimension(), m.dimension());
            forces.evaluate(real_vector(q, "q", m.dimension()), r, k);
            return py::make_tuple(vector_out(r), matrix_out(k));
          },
          py::arg("q"), "(R̃(q) (r,), K̃(q) (r, r)): reduced internal forces and stiffness.")
      .def("__repr__", [](const ReducedModel& m) {
        return "ReducedModel(r=" + std::to_string(m.dimension()) + ", " +
               std::to_string(m.groups().size()) + " material group(s))";
      });
  module.def(
      "write_reduced_model",
      [](const std::filesystem::path& file, const ReducedModel& model,
         const reduced::VolumeMesh& mesh) {
        const py::gil_scoped_release unlocked;
        reduced::write_reduced_model(file, model, mesh);
      },
      py::arg("file"), py::arg("model"), py::arg("mesh"), "Writes a .khzmodel file atomically.");
  module.def(
      "read_reduced_model",
      [](const std::filesystem::path& file, const py::object& mesh) {
        std::optional<reduced::VolumeMesh> volume;
        if (!mesh.is_none()) volume = mesh.cast<reduced::VolumeMesh>();
        const py::gil_scoped_release unlocked;
        return volume ? reduced::read_reduced_model(file, *volume)
                      : reduced::read_reduced_model(file);
      },
      py::arg("file"), py::arg("mesh") = py::none(),
      "Reads a .khzmodel file (checked against the mesh's fingerprint when given).");
}

void bind_simulation(py::module_& module) {
  py::class_<ReducedSimulation>(module, "ReducedIntegrator", R"(A reduced model stepped in time
under reduced forces f̃ = Uᵀf (khz::reduced::ReducedIntegrator): implicit Newmark with the
model's integrator defaults (reduced_newmark()) or explicit central differences. A step
takes microseconds; it never raises: a failed step reports status 'failed' and leaves the
state as it was.)")
      .def(
          "step",
          [](ReducedSimulation& s, const py::handle& force, const py::handle& stiffness) {
            const Eigen::Index r = s.integrator->dimension();
            const Eigen::VectorXd f = real_vector(force, "force", r);
            const auto report =
                stiffness.is_none()
                    ? s.integrator->step(f)
                    : s.integrator->step(
                          f, Eigen::MatrixXd(real_matrix(stiffness, "stiffness", r, r)));
            static const char* names[] = {"converged", "iteration_limit", "failed"};
            return py::make_tuple(names[static_cast<int>(report.status)], report.iterations,
                                  report.residual_norm);
          },
          py::arg("force"), py::arg("stiffness") = py::none(),
          "One step under f̃ (r,); returns (status, iterations, residual): status 'converged', "
          "'iteration_limit' or 'failed'. With `stiffness` K̃ₑ = −∂f̃/∂q (r, r, "
          "symmetric) the force acts as f̃ − K̃ₑ (q − q_n) at the "
          "step's new coordinates.")
      .def(
          "run",
          [](ReducedSimulation& s, const py::handle& forces) {
            const auto r = s.integrator->dimension();
            const auto f = real_matrix(forces, "forces", -1, r);
            Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> q(f.rows(), r);
            int failed = 0;
            {
              const py::gil_scoped_release unlocked;
              for (Eigen::Index i = 0; i < f.rows(); ++i) {
                const Eigen::VectorXd fi = f.row(i).transpose();
                if (s.integrator->step(fi).status == reduced::ReducedStepStatus::failed) ++failed;
                q.row(i) = s.integrator->coordinates().transpose();
              }
            }
            if (failed > 0) {
              throw reduced::SolverError(std::to_string(failed) + " of " +
                                         std::to_string(f.rows()) + " reduced steps failed");
            }
            return copy_of(q);
          },
          py::arg("forces"),
          "Steps once per row of forces (steps, r) without the GIL; returns q after each step "
          "(steps, r). Raises SolverError if a step failed.")
      .def_property_readonly("dimension",
                             [](const ReducedSimulation& s) { return s.integrator->dimension(); })
      .def_property_readonly(
          "q", [](const ReducedSimulation& s) { return vector_out(s.integrator->coordinates()); },
          "q (r,).")
      .def_property_readonly(
          "velocity",
          [](const ReducedSimulation& s) { return vector_out(s.integrator->velocity()); },
          "q̇ (r,) per s.")
      .def_property_readonly(
          "time", [](const ReducedSimulation& s) { return s.integrator->time(); },
          "Steps × Δt (s).")
      .def(
          "set_state",
          [](ReducedSimulation& s, const py::handle& q, const py::handle& v,
             const py::handle& force) {
            const auto r = s.integrator->dimension();
            s.integrator->set_state_in_equilibrium(
                real_vector(q, "q", r), real_vector(v, "velocity", r),
                force.is_none() ? Eigen::VectorXd::Zero(r) : real_vector(force, "force", r));
          },
          py::arg("q"), py::arg("velocity"), py::arg("force") = py::none(),
          "Sets q and q̇ with the acceleration the equation of motion gives under f̃ (default 0).")
      .def(
          "reset", [](ReducedSimulation& s) { s.integrator->reset(); },
          "The rest shape at rest, time 0.");
  module.def(
      "reduced_newmark",
      [](const ReducedModel& model, const py::object& time_step,
         const py::object& max_newton_iterations, const py::object& tolerance,
         double acceleration_limit) {
        return make_simulation(model, false,
                               {time_step, max_newton_iterations, tolerance, acceleration_limit});
      },
      py::arg("model"), py::kw_only(), py::arg("time_step") = py::none(),
      py::arg("max_newton_iterations") = py::none(), py::arg("tolerance") = py::none(),
      py::arg("acceleration_limit") = std::numeric_limits<double>::infinity(),
      "Implicit Newmark with the model's integrator defaults; time_step (s), "
      "max_newton_iterations and tolerance (relative residual) override them. Raises Error for "
      "invalid values.");
  module.def(
      "reduced_central_differences",
      [](const ReducedModel& model, double time_step) {
        return make_simulation(model, true, {py::float_(time_step), py::none(), py::none()});
      },
      py::arg("model"), py::arg("time_step"),
      "Explicit central differences at Δt (s); stable below the critical step only.");
}

void bind_reconstruction(py::module_& module) {
  module.def(
      "reconstruct_positions",
      [](const py::handle& rest, const Basis& basis, const py::handle& q) {
        const reduced::VertexMatrix x = point_rows(rest, "rest").rows();
        const Eigen::VectorXd coordinates = real_vector(q, "q", basis.size());
        if (basis.vectors.rows() != 3 * x.rows()) {
          throw py::value_error("rest: expected " + std::to_string(basis.vectors.rows() / 3) +
                                " rows, one per vertex of the basis");
        }
        reduced::VertexMatrix positions(x.rows(), 3);
        reduced::reconstruct_positions(x, basis.vectors, coordinates, positions);
        return copy_of(positions);
      },
      py::arg("rest"), py::arg("basis"), py::arg("q"),
      "x = X + U q at every vertex: rest (n, 3) m, q (r,) → (n, 3) m.");
  py::class_<reduced::MeshEmbedding>(
      module, "MeshEmbedding", "Locates points in a volume mesh (khz::reduced::MeshEmbedding).")
      .def(py::init<const reduced::VolumeMesh&>(), py::arg("mesh"));
  py::class_<reduced::EmbeddedSurface>(module, "EmbeddedSurface", R"(Surface points embedded in
the volume mesh, deformed by q (thesis eq. 3.6, 3.8; khz::reduced::EmbeddedSurface).)")
      .def(py::init([](const reduced::MeshEmbedding& embedding,
                       const reduced::TriangleMesh& surface, const Basis& basis) {
             const py::gil_scoped_release unlocked;
             return reduced::EmbeddedSurface(embedding, surface, basis.vectors);
           }),
           py::arg("embedding"), py::arg("surface"), py::arg("basis"),
           "Embeds the surface's vertices, with their area-weighted normals.")
      .def(
          "positions",
          [](const reduced::EmbeddedSurface& s, const py::handle& q) {
            reduced::VertexMatrix out(s.size(), 3);
            s.deformed_positions(real_vector(q, "q", -1), out);
            return copy_of(out);
          },
          py::arg("q"), "Deformed positions (S, 3) m at q (r,).")
      .def(
          "normals",
          [](const reduced::EmbeddedSurface& s, const py::handle& q) {
            reduced::VertexMatrix out(s.size(), 3);
            s.deformed_normals(real_vector(q, "q", -1), out);
            return copy_of(out);
          },
          py::arg("q"), "Deformed unit normals (S, 3) at q (r,).");
}

}  // namespace

void bind_reduced_models(py::module_& reduced) {
  bind_basis(reduced);
  bind_generators(reduced);
  bind_model(reduced);
  bind_simulation(reduced);
  bind_reconstruction(reduced);
}

}  // namespace khz::python
