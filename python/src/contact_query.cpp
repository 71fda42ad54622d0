// kilohertz.contact: pointshells, point trees (rigid and deformable), contact options and the
// contact query (thesis ch. 3), one pose or a whole path of poses per call.

#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/pointshell/pointshell.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/query/contact_workspace.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/fem/embedding.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "progress.hpp"

namespace khz::python {

namespace {

using contact::ContactOptions;
using contact::ContactResult;
using contact::DeformablePointTree;
using contact::DistanceGrid;
using contact::Pointshell;
using contact::PointTree;

void bind_pointshells(py::module_& module) {
  py::class_<Pointshell>(module, "Pointshell", R"(Points on a surface with inward unit normals,
in nested levels, coarsest first (thesis §3.9; khz::contact::Pointshell).)")
      .def(py::init([](const py::handle& points, const py::handle& normals,
                       const py::object& level_ends) {
             Pointshell p;
             p.points = point_rows(points, "points").rows();
             p.normals = point_rows(normals, "normals").rows();
             if (level_ends.is_none()) {
               p.level_ends = {p.points.rows()};
             } else {
               for (const int end : index_list(level_ends, "level_ends"))
                 p.level_ends.push_back(end);
             }
             contact::validate(p);
             return p;
           }),
           py::arg("points"), py::arg("normals"), py::arg("level_ends") = py::none(),
           "points (N, 3) m, normals (N, 3) unit inward, level_ends: the end of each level "
           "(default: one level). Raises Error for inconsistent sizes or normals.")
      .def_property_readonly(
          "points",
          [](py::object self) { return view_of(self.cast<Pointshell&>().points, self, false); },
          "(N, 3) m, level 0 first.")
      .def_property_readonly(
          "normals",
          [](py::object self) { return view_of(self.cast<Pointshell&>().normals, self, false); },
          "(N, 3) unit inward normals.")
      .def_readonly("level_ends", &Pointshell::level_ends)
      .def_property_readonly("size", &Pointshell::size)
      .def("__repr__",
           [](const Pointshell& p) {
             return "Pointshell(" + std::to_string(p.size()) + " points, " +
                    std::to_string(p.num_levels()) + " levels)";
           })
      .def(py::pickle(
          [](const Pointshell& p) {
            return py::make_tuple(copy_of(p.points), copy_of(p.normals), p.level_ends);
          },
          [](const py::tuple& state) {
            if (state.size() != 3) throw py::value_error("Pointshell: bad pickle state");
            Pointshell p;
            p.points = point_rows(state[0], "points").rows();
            p.normals = point_rows(state[1], "normals").rows();
            p.level_ends = state[2].cast<std::vector<Eigen::Index>>();
            contact::validate(p);
            return p;
          }));
  module.def(
      "repulsion_pointshell",
      [](const reduced::TriangleMesh& mesh, const py::object& field, int cells,
         Eigen::Index first_level_points, int levels, std::uint64_t seed,
         const py::object& progress) {
        contact::RepulsionOptions options;
        options.first_level_points = first_level_points;
        options.levels = levels;
        options.seed = seed;
        options.progress = python_progress(progress);
        if (field.is_none()) {
          contact::DistanceFieldOptions field_options;
          field_options.cells = cells;
          const py::gil_scoped_release unlocked;
          return contact::repulsion_pointshell(mesh, field_options, options);
        }
        const auto& grid = field.cast<const DistanceGrid&>();
        const py::gil_scoped_release unlocked;
        return contact::repulsion_pointshell(grid, 0.0, mesh, options);
      },
      py::arg("mesh"), py::arg("field") = py::none(), py::kw_only(), py::arg("cells") = 128,
      py::arg("first_level_points") = 64, py::arg("levels") = 4, py::arg("seed") = 0,
      py::arg("progress") = py::none(),
      R"(Evenly spread points on the zero level set of `field` (a signed DistanceGrid; default:
one computed from the closed `mesh` at `cells`), first_level_points·4^i on level i, normals from
the mesh (thesis §3.9.2). progress and Ctrl-C as signed_distance_field().)");
  module.def("vertex_pointshell", &contact::vertex_pointshell, py::arg("mesh"),
             "The mesh's vertices with inward area-weighted normals, one level.");
  module.def("random_pointshell", &contact::random_pointshell, py::arg("mesh"), py::arg("count"),
             py::arg("seed") = 0, "count points uniformly at random on the surface.");
  module.def("write_pointshell", &contact::write_pointshell, py::arg("file"), py::arg("pointshell"),
             "Writes a .khzshell file atomically.");
  module.def("read_pointshell", &contact::read_pointshell, py::arg("file"),
             "Reads a .khzshell file; ParseError names the byte.");
}

void bind_trees(py::module_& module) {
  py::class_<PointTree>(module, "PointTree", R"(A pointshell's nested point tree with bounding
radii (thesis §3.9; khz::contact::PointTree), what a rigid object's contact query traverses.)")
      .def(py::init([](const Pointshell& pointshell) {
             const py::gil_scoped_release unlocked;
             return PointTree(pointshell);
           }),
           py::arg("pointshell"))
      .def_property_readonly("num_levels", &PointTree::num_levels)
      .def_property_readonly("num_nodes", &PointTree::num_nodes)
      .def_property_readonly("pointshell", &PointTree::pointshell, py::return_value_policy::copy,
                             "The points in tree order.");
  py::class_<DeformablePointTree>(module, "DeformablePointTree", R"(A point tree whose points
follow a reduced model's basis, with the BD-tree radius bounds of thesis §3.7
(khz::contact::DeformablePointTree).)")
      .def(py::init([](const PointTree& tree, const reduced::MeshEmbedding& embedding,
                       const reduced::Basis& basis, const py::object& progress) {
             const auto report = python_progress(progress);
             const py::gil_scoped_release unlocked;
             return DeformablePointTree(tree, embedding, basis.vectors, report);
           }),
           py::arg("tree"), py::arg("embedding"), py::arg("basis"), py::kw_only(),
           py::arg("progress") = py::none(),
           "Samples the basis at the tree's points (the embedding's volume mesh carries it).")
      .def_property_readonly("dimension", &DeformablePointTree::dimension, "r.")
      .def_property_readonly("tree", &DeformablePointTree::tree, py::return_value_policy::copy);
  module.def(
      "write_deformable_point_tree",
      [](const std::filesystem::path& file, const DeformablePointTree& tree) {
        contact::write_deformable_point_tree(file, tree);
      },
      py::arg("file"), py::arg("tree"), "Writes a .khztree file atomically.");
  module.def(
      "read_deformable_point_tree",
      [](const std::filesystem::path& file) {
        const py::gil_scoped_release unlocked;
        return contact::read_deformable_point_tree(file);
      },
      py::arg("file"), "Reads a .khztree file.");
}

void bind_options(py::module_& module) {
  py::class_<ContactOptions>(module, "ContactOptions", R"(How the contact query computes
(khz::contact::ContactOptions); see docs/CONTACT.md for each setting.)")
      .def(py::init([](double stiffness, double scaling_count, int max_level,
                       const std::string& gradient, const std::string& degradation,
                       double warm_threshold, double budget_microseconds, bool coherence,
                       double static_friction, double kinetic_friction, double stick_distance,
                       double onset_voxels, double onset_depth) {
             ContactOptions o;
             o.stiffness = stiffness;
             o.scaling_count = scaling_count;
             o.max_level = max_level;
             if (gradient == "field_gradient") {
               o.gradient = contact::ContactGradient::field_gradient;
             } else if (gradient == "normal_direction") {
               o.gradient = contact::ContactGradient::normal_direction;
             } else {
               throw py::value_error(
                   "gradient: expected 'field_gradient' or 'normal_direction', got '" + gradient +
                   "'");
             }
             using Mode = contact::DegradationOptions::Mode;
             if (degradation == "none") {
               o.degradation.mode = Mode::none;
             } else if (degradation == "node_count") {
               o.degradation.mode = Mode::node_count;
             } else if (degradation == "time_budget") {
               o.degradation.mode = Mode::time_budget;
             } else {
               throw py::value_error(
                   "degradation: expected 'none', 'node_count' or 'time_budget', got '" +
                   degradation + "'");
             }
             o.degradation.warm_threshold = warm_threshold;
             o.degradation.budget_microseconds = budget_microseconds;
             o.coherence.enabled = coherence;
             o.friction.static_coefficient = static_friction;
             o.friction.kinetic_coefficient = kinetic_friction;
             o.friction.stick_distance = stick_distance;
             o.onset_voxels = onset_voxels;
             o.onset_depth = onset_depth;
             o.validate();
             return o;
           }),
           py::kw_only(), py::arg("stiffness") = 1000.0, py::arg("scaling_count") = 10.0,
           py::arg("max_level") = -1, py::arg("gradient") = "field_gradient",
           py::arg("degradation") = "none", py::arg("warm_threshold") = 2500.0,
           py::arg("budget_microseconds") = 250.0, py::arg("coherence") = false,
           py::arg("static_friction") = 0.0, py::arg("kinetic_friction") = 0.0,
           py::arg("stick_distance") = 0.0, py::arg("onset_voxels") = 0.1,
           py::arg("onset_depth") = 0.0,
           R"(stiffness k_C (N/m); scaling_count ℓ of the L/ℓ normalisation; max_level (-1: all);
gradient 'field_gradient' or 'normal_direction'; degradation 'none', 'node_count'
(warm_threshold) or 'time_budget' (budget_microseconds); coherence: temporal coherence;
static_/kinetic_friction μ_s ≥ μ_k, stick_distance δ (m; 0: μ_s times the field's voxel);
onset_voxels, onset_depth: the contact onset δ over which a point's force and count grow from
zero (in the field's voxels, or m when onset_depth > 0; onset_voxels 0: eq. 3.1's step).
Raises Error naming an invalid value.)")
      .def_readonly("stiffness", &ContactOptions::stiffness)
      .def_readonly("scaling_count", &ContactOptions::scaling_count)
      .def_readonly("max_level", &ContactOptions::max_level)
      .def_readonly("onset_voxels", &ContactOptions::onset_voxels)
      .def_readonly("onset_depth", &ContactOptions::onset_depth);
}

/// A 4×4 world ← body matrix as a pose; the rotation must be orthonormal.
Eigen::Isometry3d pose_from_matrix(const Eigen::Ref<const Eigen::Matrix4d>& m,
                                   std::string_view what) {
  const Eigen::Matrix3d r = m.topLeftCorner(3, 3);
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
      r.determinant() < 0.0) {
    throw py::value_error(std::string(what) +
                          ": the upper-left 3×3 block is not a rotation (orthonormal, det +1)");
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = r;
  pose.translation() = m.topRightCorner(3, 1);
  return pose;
}

/// 4×4 world ← body from a (4, 4) array-like (None: identity).
Eigen::Isometry3d pose_in(const py::handle& input, std::string_view what) {
  if (input.is_none()) return Eigen::Isometry3d::Identity();
  return pose_from_matrix(real_matrix(input, what, 4, 4), what);
}

py::dict statistics_out(const contact::ContactStatistics& s) {
  py::dict d;
  d["nodes_traversed"] = s.nodes_traversed;
  d["nodes_skipped"] = s.nodes_skipped;
  d["points_in_contact"] = s.points_in_contact;
  d["points_sliding"] = s.points_sliding;
  d["deepest_level"] = s.deepest_level;
  d["deepest_penetration"] = s.deepest_penetration;
  d["complete"] = s.complete;
  d["coherence_reset"] = s.coherence_reset;
  d["microseconds"] = s.microseconds;
  return d;
}

py::array matrix3_out(const Eigen::Matrix3d& m) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> rows = m;
  return copy_of(rows);
}

void bind_result(py::module_& module) {
  py::class_<ContactResult>(module, "ContactResult", R"(One contact query's result
(khz::contact::ContactResult): force on the pointshell object (N) and torque about the grasp
point (N·m), their gradients by translation (per m) and rotation (per rad), the reduced forces
for deformable objects, and the query's statistics.)")
      .def_property_readonly("force", [](const ContactResult& r) { return vector_out(r.force); })
      .def_property_readonly("torque", [](const ContactResult& r) { return vector_out(r.torque); })
      .def_property_readonly(
          "force_by_translation",
          [](const ContactResult& r) { return matrix3_out(r.force_by_translation); }, "∂F/∂x, N/m.")
      .def_property_readonly(
          "force_by_rotation",
          [](const ContactResult& r) { return matrix3_out(r.force_by_rotation); }, "∂F/∂ω, N/rad.")
      .def_property_readonly(
          "torque_by_translation",
          [](const ContactResult& r) { return matrix3_out(r.torque_by_translation); }, "∂T/∂x, N.")
      .def_property_readonly(
          "torque_by_rotation",
          [](const ContactResult& r) { return matrix3_out(r.torque_by_rotation); },
          "∂T/∂ω, N·m/rad.")
      .def_property_readonly(
          "pointshell_reduced_force",
          [](const ContactResult& r) { return vector_out(r.pointshell_reduced_force); },
          "Σ U_sᵀ f_s (r,) for a deformable pointshell; empty otherwise.")
      .def_property_readonly("statistics",
                             [](const ContactResult& r) { return statistics_out(r.statistics); });
}

/// A contact query's state: the tree it traverses (kept alive) and its workspace.
class ContactQuery {
 public:
  ContactQuery(const py::object& tree, const ContactOptions& options) : m_tree_object(tree) {
    if (py::isinstance<PointTree>(tree)) {
      const auto* rigid = &tree.cast<const PointTree&>();
      m_tree = rigid;
      m_workspace.emplace(*rigid, options);
    } else {
      const auto* deformable = &tree.cast<const DeformablePointTree&>();
      m_tree = deformable;
      m_workspace.emplace(*deformable, options);
    }
  }

  /// One query; false when the library refused the input (result then zero).
  bool query(const DistanceGrid& field, const contact::ContactFrames& frames,
             const Eigen::VectorXd& q) noexcept {
    if (const auto* const* rigid = std::get_if<const PointTree*>(&m_tree)) {
      return contact::query_contact(**rigid, field, frames, *m_workspace);
    }
    return contact::query_contact(*std::get<const DeformablePointTree*>(m_tree), q, field, frames,
                                  *m_workspace);
  }

  Eigen::Index dimension() const noexcept {
    if (const auto* const* deformable = std::get_if<const DeformablePointTree*>(&m_tree)) {
      return (*deformable)->dimension();
    }
    return 0;
  }

  Eigen::VectorXd coordinates(const py::object& q) const {
    if (dimension() == 0) {
      if (!q.is_none()) throw py::value_error("q: a rigid pointshell's query takes no q");
      return {};
    }
    if (q.is_none()) throw py::value_error("q: a deformable pointshell's query needs q (r,)");
    return real_vector(q, "q", dimension());
  }

  contact::ContactWorkspace& workspace() noexcept { return *m_workspace; }

 private:
  py::object m_tree_object;
  std::variant<const PointTree*, const DeformablePointTree*> m_tree;
  std::optional<contact::ContactWorkspace> m_workspace;
};

void bind_query(py::module_& module) {
  py::class_<ContactQuery>(module, "ContactQuery", R"(The contact query of a pointshell's tree
against distance fields (thesis ch. 3; khz::contact::query_contact): keeps the tree alive and the
workspace (temporal coherence, friction anchors) from one query to the next.)")
      .def(py::init<const py::object&, const ContactOptions&>(), py::arg("tree"),
           py::arg("options") = ContactOptions{},
           "tree: a PointTree (rigid) or DeformablePointTree (reduced).")
      .def(
          "query",
          [](ContactQuery& self, const DistanceGrid& field, const py::handle& pointshell_pose,
             const py::handle& field_pose, const py::handle& grasp_point, const py::object& q) {
            contact::ContactFrames frames;
            frames.pointshell = pose_in(pointshell_pose, "pointshell_pose");
            frames.field = pose_in(field_pose, "field_pose");
            if (!grasp_point.is_none()) frames.grasp_point = vector3_in(grasp_point, "grasp_point");
            const Eigen::VectorXd coordinates = self.coordinates(q);
            if (!self.query(field, frames, coordinates)) {
              throw py::value_error(
                  "the contact query refused its input (see ContactQuery.query's doc)");
            }
            return self.workspace().result();
          },
          py::arg("field"), py::arg("pointshell_pose") = py::none(),
          py::arg("field_pose") = py::none(), py::arg("grasp_point") = py::none(),
          py::arg("q") = py::none(),
          R"(One query: the pointshell at pointshell_pose and the field at field_pose (4×4 world ←
body, None: identity), torque and rotations about grasp_point (m, world), q (r,) for a
deformable pointshell. Returns a ContactResult. Raises ValueError if the library refuses the
input (friction with its default stick distance on a field without cells, say).)")
      .def(
          "sweep",
          [](ContactQuery& self, const DistanceGrid& field, const py::handle& poses,
             const py::handle& field_pose, const py::object& q) {
            const auto array = py::array::ensure(poses);
            if (!array || array.ndim() != 3 || array.shape(1) != 4 || array.shape(2) != 4) {
              throw py::value_error("pointshell_poses: expected shape (N, 4, 4)");
            }
            const auto n = static_cast<Eigen::Index>(array.shape(0));
            std::vector<contact::ContactFrames> frames(static_cast<std::size_t>(n));
            const auto stack =
                real_matrix(array.attr("reshape")(-1, 4), "pointshell_poses", 4 * n, 4);
            const Eigen::Isometry3d field_frame = pose_in(field_pose, "field_pose");
            for (Eigen::Index i = 0; i < n; ++i) {
              auto& f = frames[static_cast<std::size_t>(i)];
              f.pointshell = pose_from_matrix(stack.middleRows(4 * i, 4), "pointshell_poses");
              f.field = field_frame;
              f.grasp_point = f.pointshell.translation();
            }
            const Eigen::VectorXd coordinates = self.coordinates(q);
            Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> force(n, 3), torque(n, 3);
            Eigen::VectorXd microseconds(n);
            Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> points(n);
            Eigen::Index refused = 0;
            {
              const py::gil_scoped_release unlocked;
              for (Eigen::Index i = 0; i < n; ++i) {
                if (!self.query(field, frames[static_cast<std::size_t>(i)], coordinates)) ++refused;
                const ContactResult& r = self.workspace().result();
                force.row(i) = r.force.transpose();
                torque.row(i) = r.torque.transpose();
                microseconds(i) = r.statistics.microseconds;
                points(i) = r.statistics.points_in_contact;
              }
            }
            if (refused > 0) {
              throw py::value_error("the contact query refused " + std::to_string(refused) +
                                    " of " + std::to_string(n) + " poses");
            }
            py::dict out;
            out["force"] = copy_of(force);
            out["torque"] = copy_of(torque);
            out["points_in_contact"] = copy_of(points);
            out["microseconds"] = copy_of(microseconds);
            return out;
          },
          py::arg("field"), py::arg("pointshell_poses"), py::arg("field_pose") = py::none(),
          py::arg("q") = py::none(),
          R"(One query per pose of pointshell_poses (N, 4, 4), in order and without the GIL,
each about the pose's own origin: a dict of force (N, 3) N, torque (N, 3) N·m,
points_in_contact (N,) and microseconds (N,) per query.)")
      .def(
          "reset", [](ContactQuery& self) { self.workspace().reset(); },
          "Forgets temporal coherence and friction anchors.");
}

}  // namespace

void bind_contact_query(py::module_& contact) {
  bind_pointshells(contact);
  bind_trees(contact);
  bind_options(contact);
  bind_result(contact);
  bind_query(contact);
}

}  // namespace khz::python
