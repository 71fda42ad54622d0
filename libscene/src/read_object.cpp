#include "read_object.hpp"

#include "names.hpp"
#include "option_tables.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/scene/procedural_shape.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>

namespace khz::scene::detail {
namespace {

/// Largest point count of a pointshell: point trees index points with int.
constexpr double most_points = std::numeric_limits<std::int32_t>::max();

void check_name(const std::string& name, const Location& at) {
  const bool allowed = std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
  if (!allowed || name.front() == '.') {
    at.fail("expected a name of letters, digits, '_', '-' and '.' not starting with '.', got " +
            in_quotes(name));
  }
}

void check_mesh_extension(const std::string& written, const Location& at) {
  std::string extension = std::filesystem::path(written).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  if (extension != ".obj" && extension != ".off" && extension != ".stl" && extension != ".ply") {
    at.fail("expected a surface mesh file (.obj, .off, .stl or .ply), got " + in_quotes(written));
  }
}

/// The canonical spec of a "shape:SPEC" mesh; a spec procedural_shape() refuses fails at `at`
/// with its message.
std::string read_shape(std::string_view spec, const Location& at) {
  try {
    return canonical_shape_spec(spec);
  } catch (const reduced::Error& error) {
    at.fail(error.what());
  }
}

ObjectRoles read_roles(const ObjectReader& object) {
  const Json& value = object.required("roles", "\"pointshell\", \"distance_field\" or both");
  const Location at = object.at("roles");
  if (!value.is_array()) at.expected("an array of roles, e.g. [\"pointshell\"]", value);
  if (value.empty()) {
    at.fail("an object needs a role: expected \"pointshell\", \"distance_field\" or both, got []");
  }
  ObjectRoles roles;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const contact::HapticObject role = to_choice(value[i], at.element(i), role_names);
    bool& flag =
        role == contact::HapticObject::pointshell ? roles.pointshell : roles.distance_field;
    if (flag) at.element(i).fail("duplicate role " + describe_value(value[i]));
    flag = true;
  }
  return roles;
}

MaterialDescription read_material(const ObjectReader& model) {
  const ObjectReader material(
      model.required("material", "young_modulus, poisson_ratio and density"), model.at("material"),
      option_table<MaterialDescription>().keys(),
      {{"E", "young_modulus"}, {"nu", "poisson_ratio"}, {"rho", "density"}});
  MaterialDescription result;
  read_options(material, result);
  return result;
}

MeshingDescription read_meshing(const ObjectReader& model) {
  MeshingDescription result;
  const auto& voxel_settings = option_table<reduced::VoxelizeOptions>();
  const auto& tetrahedra_settings = option_table<reduced::TetrahedralizeOptions>();
  const auto meshing =
      model.object("meshing", KeyList("method", voxel_settings, tetrahedra_settings),
                   {{"cells", "resolution"}, {"box_expansion", "enlargement"}});
  if (!meshing) return result;
  result.method = meshing->choice("method", result.method, meshing_methods);
  if (result.method == MeshingMethod::voxels) {
    meshing->refuse(tetrahedra_settings.keys(), "method \"tetrahedra\" (method is \"voxels\")");
    voxel_settings.read(*meshing, result.voxels);
  } else {
    meshing->refuse(voxel_settings.keys(), "method \"voxels\" (method is \"tetrahedra\")");
    tetrahedra_settings.read(*meshing, result.tetrahedra);
  }
  return result;
}

std::vector<AnchorRegion> read_anchors(const ObjectReader& model) {
  std::vector<AnchorRegion> result;
  const Json* anchors = model.array("anchors");
  if (anchors == nullptr) return result;
  for (std::size_t i = 0; i < anchors->size(); ++i) {
    const ObjectReader anchor((*anchors)[i], model.at("anchors").element(i),
                              {"type", "min", "max", "point", "normal"});
    AnchorRegion region;
    region.kind = to_choice(anchor.required("type", "\"box\" or \"half_space\""), anchor.at("type"),
                            anchor_kinds);
    if (region.kind == AnchorRegion::Kind::box) {
      anchor.refuse({"point", "normal"}, "type \"half_space\" (type is \"box\")");
      region.min = anchor.required_vector3("min", "the box's lower corner [x, y, z] in m");
      region.max = anchor.required_vector3("max", "the box's upper corner [x, y, z] in m");
      if (!(region.min.array() <= region.max.array()).all()) {
        anchor.at("max").expected(
            "a corner ≥ min " + describe_value(anchor.value("min")) + " in every coordinate",
            anchor.value("max"));
      }
    } else {
      anchor.refuse({"min", "max"}, "type \"box\" (type is \"half_space\")");
      region.point = anchor.required_vector3("point", "a point on the plane [x, y, z] in m");
      const Eigen::Vector3d normal =
          anchor.required_vector3("normal", "the normal [x, y, z] pointing into the half-space");
      if (!(normal.norm() > 0.0)) {
        anchor.at("normal").expected("a non-zero normal", anchor.value("normal"));
      }
      region.normal = normal.normalized();
    }
    result.push_back(region);
  }
  return result;
}

SimulationRunDescription read_simulation(const ObjectReader& basis) {
  SimulationRunDescription result;
  const ObjectReader run(basis.required("simulation", "the full simulation to take snapshots of"),
                         basis.at("simulation"), option_table<SimulationRunDescription>().keys());
  read_options(run, result);
  return result;
}

/// r for a modes basis: bounded by what the modes (and derivatives) span.
int read_modes_basis_size(const ObjectReader& basis, const BasisDescription& result,
                          bool anchored) {
  const std::int64_t k = result.modal.modes.num_modes;
  if (!result.modal_derivatives) {
    return basis.integer("r", result.modal.modes.num_modes,
                         with_text(closed(1, static_cast<double>(k)),
                                   "an integer in [1, " + std::to_string(k) + "] (at most k = " +
                                       std::to_string(k) + " without modal derivatives)"));
  }
  const std::int64_t most = anchored ? k + k * (k + 1) / 2 : k + k * k;
  const std::string why = anchored ? "k + k(k+1)/2 for k = " + std::to_string(k) + " with anchors"
                                   : "k + k² for k = " + std::to_string(k) + " without anchors";
  return basis.integer("r", result.modal.basis_size,
                       with_text(closed(1, static_cast<double>(most)),
                                 "an integer in [1, " + std::to_string(most) + "] (" + why + ")"));
}

BasisDescription read_basis(const ObjectReader& model, const ReadContext& context, bool anchored) {
  BasisDescription result;
  const auto& modal_settings = option_table<reduced::ModalDerivativeBasisOptions>();
  const auto& sketch_settings = option_table<reduced::SketchBasisOptions>();
  const auto& simulation_data_settings = option_table<reduced::SimulationDataBasisOptions>();
  const auto basis =
      model.object("basis",
                   KeyList("method", "r", modal_settings, "modal_derivatives", "loads",
                           sketch_settings, "simulation", simulation_data_settings),
                   {{"num_modes", "k"}, {"basis_size", "r"}, {"derivatives", "modal_derivatives"}});
  if (!basis) return result;
  result.method = basis->choice("method", result.method, basis_methods);
  const std::string method = in_quotes(name_of(result.method, basis_methods));
  if (result.method == BasisMethod::modes) {
    basis->refuse({"loads", "force_separation", "force_kernel_width", "deformation_separation",
                   "deformation_kernel_width", "static_solve", "skip_failed_solves"},
                  "method \"sketch\" (method is \"modes\")");
    basis->refuse({"simulation", "fixed_tolerance"},
                  "method \"simulation_data\" (method is \"modes\")");
    basis->refuse({"rank_tolerance"},
                  "methods \"sketch\" and \"simulation_data\" (method is \"modes\")");
    result.modal_derivatives = basis->boolean("modal_derivatives", result.modal_derivatives);
    if (!result.modal_derivatives) {
      basis->refuse({"metric"},
                    "modal derivatives (their mass-PCA); without them the basis is the first r "
                    "modes");
    }
    modal_settings.read(*basis, result.modal);
    result.modal.basis_size = read_modes_basis_size(*basis, result, anchored);
    return result;
  }
  basis->refuse({"k", "modal_derivatives", "mass", "tolerance", "max_restarts"},
                "method \"modes\" (method is " + method + ")");
  if (result.method == BasisMethod::sketch) {
    basis->refuse({"simulation", "fixed_tolerance"},
                  "method \"simulation_data\" (method is \"sketch\")");
  } else {
    basis->refuse({"force_separation", "force_kernel_width", "deformation_separation",
                   "deformation_kernel_width", "static_solve", "skip_failed_solves"},
                  "method \"sketch\" (method is \"simulation_data\")");
  }
  const int basis_size = basis->required_integer<int>("r", at_least(1), "the basis size");
  result.loads = basis->required_string("loads", "the recorded force loads, a CSV file");
  result.loads_path =
      resolve_file(result.loads, basis->at("loads"), context, "load file", /*allow_cgal=*/false);
  if (result.method == BasisMethod::sketch) {
    if (!anchored) {
      basis->fail("method",
                  "a sketch basis needs anchors (model.anchors): its static solves need the "
                  "rigid motions removed");
    }
    result.sketch.basis_size = basis_size;
    sketch_settings.read(*basis, result.sketch);
  } else {
    result.simulation_data_basis_size = basis_size;
    simulation_data_settings.read(*basis, result.simulation_data);
    result.simulation = read_simulation(*basis);
  }
  return result;
}

reduced::ReducedNewmarkOptions read_integrator(const ObjectReader& model,
                                               const ReadContext& context) {
  reduced::ReducedNewmarkOptions result;
  result.newmark.time_step = 1.0 / context.rate_hz;
  read_block(model, "integrator", result,
             {{"damping", "mass_damping"}, {"newton_iterations", "max_newton_iterations"}});
  return result;
}

ModelDescription read_model(const ObjectReader& object, const ReadContext& context) {
  ModelDescription result;
  const auto model =
      object.object("model", {"type", "meshing", "material", "anchors", "basis", "integrator"},
                    {{"fixed", "anchors"}, {"anchor", "anchors"}});
  if (!model) return result;
  result.type = model->choice("type", result.type, model_types);
  if (result.type == ModelType::rigid) {
    const std::string type =
        model->has("type") ? "model.type is \"rigid\"" : "model.type is \"rigid\" by default";
    for (const std::string_view key : {"meshing", "material", "anchors", "basis", "integrator"}) {
      if (model->has(key)) {
        model->fail(key, "reduced-model settings on a rigid object (" + type +
                             "); set \"type\": \"reduced\" or remove this key");
      }
    }
    return result;
  }
  result.meshing = read_meshing(*model);
  result.material = read_material(*model);
  result.anchors = read_anchors(*model);
  result.basis = read_basis(*model, context, !result.anchors.empty());
  result.integrator = read_integrator(*model, context);
  return result;
}

PointshellDescription read_pointshell(const ObjectReader& object) {
  PointshellDescription result;
  const auto shell =
      object.object("pointshell",
                    KeyList("method", option_table<contact::RepulsionOptions>(), "points",
                            option_table<contact::NestedLevelOptions>(), "cell_size"),
                    {{"count", "points"}, {"first_level_size", "first_level_points"}});
  if (!shell) return result;
  result.method = shell->choice("method", result.method, pointshell_methods);
  const std::string method = in_quotes(name_of(result.method, pointshell_methods));
  if (result.method == PointshellMethod::repulsion) {
    shell->refuse({"growth"},
                  "the methods \"vertices\", \"random\" and \"voxels\" (repulsion's levels grow "
                  "by 4)");
    shell->refuse({"cell_size"}, "method \"voxels\" (method is \"repulsion\")");
    if (shell->has("first_level_points") && shell->has("points")) {
      shell->fail("points", "give either \"first_level_points\" or \"points\", not both");
    }
    contact::RepulsionOptions& repulsion = result.repulsion;
    read_options(*shell, repulsion);
    // "points" is the scene's own way to give n₀: through the total over all levels.
    const double level_factor = (std::pow(4.0, repulsion.levels) - 1.0) / 3.0;  // N = n₀ × this
    std::string_view count_key = "levels";
    if (shell->has("points")) {
      count_key = "points";
      const auto points = shell->integer<Eigen::Index>("points", 0, closed(1, most_points));
      repulsion.first_level_points =
          std::max<Eigen::Index>(1, std::llround(static_cast<double>(points) / level_factor));
    } else if (shell->has("first_level_points")) {
      count_key = "first_level_points";
    }
    const double total = static_cast<double>(repulsion.first_level_points) * level_factor;
    if (total > most_points) {
      shell->fail(count_key, "n₀(4ᴸ − 1)/3 = " + format_number(total) + " points for n₀ = " +
                                 std::to_string(repulsion.first_level_points) +
                                 " and L = " + std::to_string(repulsion.levels) +
                                 ": expected at most 2147483647 points in all");
    }
    return result;
  }
  shell->refuse({"max_iterations", "tolerance", "radius_factor"},
                "method \"repulsion\" (method is " + method + ")");
  if (result.method != PointshellMethod::random) {
    shell->refuse({"points"}, "methods \"repulsion\" and \"random\" (method is " + method + ")");
  }
  if (result.method != PointshellMethod::voxels) {
    shell->refuse({"cell_size"}, "method \"voxels\" (method is " + method + ")");
  }
  if (result.method == PointshellMethod::random) {
    result.count = shell->required_integer<Eigen::Index>("points", closed(1, most_points),
                                                         "the number of random samples");
  } else if (result.method == PointshellMethod::voxels) {
    result.cell_size = shell->required_number("cell_size", above(0.0), "the voxels' side in m");
  }
  read_options(*shell, result.nested);
  return result;
}

FieldDescription read_field(const ObjectReader& object, const ObjectDescription& description) {
  FieldDescription result;
  const auto& deformed_settings = option_table<contact::DeformedFieldOptions>();
  const auto field = object.object(
      "field",
      KeyList(option_table<contact::DistanceFieldOptions>(), "soup", "offset", deformed_settings),
      {{"resolution", "cells"},
       {"enlargement", "box_expansion"},
       {"expansion", "box_expansion"},
       {"sigma", "offset"},
       {"k", "neighbours"}});
  if (!field) return result;
  if (!description.is_reduced() || !description.roles.distance_field) {
    field->refuse(deformed_settings.keys(),
                  "a reduced object with the distance_field role (its deformed field's proxies)");
  }
  read_options(*field, result.distance);
  result.soup = field->boolean("soup", result.soup);
  if (!result.soup) field->refuse({"offset"}, "polygon soups (\"soup\": true)");
  result.offset = field->number("offset", result.offset, at_least(0.0));
  deformed_settings.read(*field, result.deformed);
  return result;
}

/// "dynamics": a free rigid body's density (or mass) and its motion at the start.
std::optional<DynamicsDescription> read_dynamics(const ObjectReader& object,
                                                 const ObjectDescription& description) {
  const auto dynamics =
      object.object("dynamics", {"density", "mass", "velocity", "angular_velocity"},
                    {{"rho", "density"}, {"omega", "angular_velocity"}, {"v", "velocity"}});
  if (!dynamics) return std::nullopt;
  if (description.is_reduced()) {
    object.fail("dynamics",
                "a free body is rigid, but model.type is \"reduced\"; remove \"model\" or "
                "\"dynamics\"");
  }
  if (dynamics->has("density") && dynamics->has("mass")) {
    dynamics->fail("mass", "give either \"density\" or \"mass\", not both");
  }
  DynamicsDescription result;
  result.density = dynamics->number("density", result.density, above(0.0));
  if (dynamics->has("mass")) result.mass = dynamics->number("mass", 0.0, above(0.0));
  result.velocity = dynamics->vector3("velocity", result.velocity);
  result.angular_velocity = dynamics->vector3("angular_velocity", result.angular_velocity);
  return result;
}

}  // namespace

ObjectDescription read_object(const Json& value, const Location& at, const ReadContext& context) {
  const ObjectReader object(value, at,
                            {"name", "mesh", "scale", "size", "centre", "fill_holes", "pose",
                             "roles", "model", "field", "pointshell", "dynamics"},
                            {{"role", "roles"},
                             {"position", "pose"},
                             {"rotation", "pose"},
                             {"path", "mesh"},
                             {"dynamic", "dynamics"},
                             {"density", "dynamics"},
                             {"mass", "dynamics"},
                             {"velocity", "dynamics"}});
  ObjectDescription result;
  result.name = object.required_string("name", "the object's name");
  check_name(result.name, object.at("name"));
  result.mesh = object.required_string("mesh", "the surface mesh file, or \"cgal:NAME\"");
  constexpr std::string_view shape_prefix = "shape:";
  if (result.mesh.starts_with(shape_prefix)) {
    result.shape =
        read_shape(std::string_view(result.mesh).substr(shape_prefix.size()), object.at("mesh"));
  } else {
    check_mesh_extension(result.mesh, object.at("mesh"));
    result.mesh_path =
        resolve_file(result.mesh, object.at("mesh"), context, "mesh file", /*allow_cgal=*/true);
  }
  if (object.has("scale") && object.has("size")) {
    object.fail("size", "give either \"scale\" or \"size\", not both");
  }
  result.scale = object.number("scale", result.scale, above(0.0));
  if (object.has("size")) result.size = object.number("size", 0.0, above(0.0));
  result.centre = object.boolean("centre", result.centre);
  result.fill_holes = object.boolean("fill_holes", result.fill_holes);
  if (object.has("pose")) result.pose = read_pose(object.value("pose"), object.at("pose"));
  result.roles = read_roles(object);
  result.model = read_model(object, context);
  if (object.has("pointshell") && !result.roles.pointshell) {
    object.fail("pointshell", "pointshell settings on an object without the \"pointshell\" role");
  }
  result.pointshell = read_pointshell(object);
  if (object.has("field") && !result.uses_field()) {
    object.fail("field",
                "field settings on an object that has no distance field: it has no "
                "\"distance_field\" role and no repulsion pointshell");
  }
  result.field = read_field(object, result);
  if (result.field.soup && result.is_reduced() &&
      result.model.meshing.method == MeshingMethod::tetrahedra) {
    object.at("model").child("meshing").child("method").fail(
        "\"tetrahedra\" needs a closed surface, but field.soup says the mesh is a polygon soup; "
        "use \"voxels\"");
  }
  result.dynamics = read_dynamics(object, result);
  return result;
}

}  // namespace khz::scene::detail
