#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>

#include "detail/file_bytes.hpp"
#include "detail/number_text.hpp"
#include "io/basis_payload.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

constexpr std::uint32_t stvk_kind = 0;
constexpr std::uint32_t general_kind = 1;

/// Names of a group's energy parts, in file order.
std::vector<std::string> part_names(bool stvk) {
  if (stvk) return {"λ part", "μ part"};
  return {"C₀ part"};
}

/// Runs `make`, turning an Error it throws (a factory or validate() rejecting a value read from
/// the file) into a ParseError at `offset`: "<context>: <what>".
template <typename Make>
auto parse_checked(const ContainerReader& reader, std::size_t offset, const std::string& context,
                   Make&& make) {
  try {
    return make();
  } catch (const Error& error) {
    reader.fail_at(offset, context + ": " + error.what());
  }
}

/// Reads a double that must be finite.
double read_finite(ContainerReader& reader, const std::string& what) {
  const double value = reader.read_f64(what);
  if (!std::isfinite(value)) {
    reader.fail_at(reader.value_offset(),
                   what + " = " + detail::number_text(value) + " is not finite");
  }
  return value;
}

/// Reads doubles that must number `expected` and be finite.
Eigen::VectorXd read_coefficients(ContainerReader& reader, const std::string& what,
                                  Eigen::Index expected, const std::string& rule) {
  const std::size_t count_offset = reader.offset();
  const std::vector<double> values = reader.read_doubles(what);
  if (static_cast<Eigen::Index>(values.size()) != expected) {
    reader.fail_at(count_offset, what + ": " + std::to_string(values.size()) +
                                     " coefficients, expected " + std::to_string(expected) + " (" +
                                     rule + ")");
  }
  detail::check_finite(reader, values, what);
  return Eigen::Map<const Eigen::VectorXd>(values.data(), expected);
}

/// Reads an r × r matrix with finite entries.
Eigen::MatrixXd read_square(ContainerReader& reader, const std::string& what, Eigen::Index r) {
  const std::size_t offset = reader.offset();
  Eigen::MatrixXd matrix = reader.read_matrix(what);
  detail::check_shape(reader, offset, matrix, what, r, r, "r × r");
  detail::check_finite(reader, matrix, what);
  return matrix;
}

/// Reads the header and checks 1 ≤ r ≤ reduced_model_file_max_dimension.
detail::BasisHeader read_header(ContainerReader& reader) {
  detail::BasisHeader header = detail::read_basis_header(reader, reduced_model_file_max_dimension);
  if (header.size == 0) {
    reader.fail_at(header.size_offset, "basis size 0: a reduced model needs at least one vector");
  }
  return header;
}

ReducedIntegratorDefaults read_defaults(ContainerReader& reader) {
  ReducedIntegratorDefaults defaults;
  NewmarkParameters& newmark = defaults.newmark;
  newmark.time_step = read_finite(reader, "the default time step");
  const std::size_t newmark_offset = reader.value_offset();
  newmark.beta = read_finite(reader, "the default Newmark beta");
  newmark.gamma = read_finite(reader, "the default Newmark gamma");
  newmark.mass_damping = read_finite(reader, "the default Rayleigh alpha");
  newmark.stiffness_damping = read_finite(reader, "the default Rayleigh beta");
  parse_checked(reader, newmark_offset, "invalid default integrator parameters",
                [&] { newmark.validate(); });
  defaults.max_newton_iterations = reader.read_i32("the default Newton iteration limit");
  if (defaults.max_newton_iterations < 1) {
    reader.fail_at(reader.value_offset(), "the default Newton iteration limit is " +
                                              std::to_string(defaults.max_newton_iterations) +
                                              ", it must be at least 1");
  }
  defaults.newton_tolerance = read_finite(reader, "the default Newton tolerance");
  if (!(defaults.newton_tolerance > 0)) {
    reader.fail_at(reader.value_offset(), "the default Newton tolerance is " +
                                              detail::number_text(defaults.newton_tolerance) +
                                              ", it must be positive");
  }
  return defaults;
}

ReducedMaterialGroup read_group(ContainerReader& reader, std::size_t g, Eigen::Index r) {
  const std::string name = "group " + std::to_string(g);
  const std::uint32_t kind = reader.read_u32(name + "'s material kind");
  const std::size_t kind_offset = reader.value_offset();
  if (kind != stvk_kind && kind != general_kind) {
    reader.fail_at(kind_offset, name + ": unknown material kind " + std::to_string(kind) +
                                    " (0 = StVK, 1 = general)");
  }
  const bool stvk = kind == stvk_kind;
  LameParameters lame;
  VoigtMatrix reference = VoigtMatrix::Zero();
  double scale = 1.0;
  if (stvk) {
    lame.lambda = read_finite(reader, name + "'s λ");
    lame.mu = read_finite(reader, name + "'s μ");
  } else {
    const std::size_t offset = reader.offset();
    const Eigen::MatrixXd elasticity = reader.read_matrix(name + "'s reference elasticity C₀");
    detail::check_shape(reader, offset, elasticity, name + "'s C₀", 6, 6, "a Voigt matrix");
    detail::check_finite(reader, elasticity, name + "'s C₀");
    reference = elasticity;
    scale = read_finite(reader, name + "'s elasticity scale s");
    if (!(scale > 0)) {
      reader.fail_at(reader.value_offset(), name + "'s elasticity scale s = " +
                                                detail::number_text(scale) + " must be positive");
    }
  }
  const double density = read_finite(reader, name + "'s density");
  // As ReducedModel::set_lame and set_elasticity_scale build them, so the bits match.
  Material material = parse_checked(reader, kind_offset, name + ": invalid material", [&] {
    return stvk ? Material::stvk_lame(lame, density)
                : Material::general(scale * reference, density);
  });

  std::vector<EnergyPolynomial> parts;
  for (const std::string& part_name : part_names(stvk)) {
    const std::string what = name + "'s " + part_name;
    const std::size_t offset = reader.offset();
    EnergyPolynomial part;
    part.quadratic = read_square(reader, what + " K", r);
    part.cubic = read_coefficients(reader, what + " cubic coefficients",
                                   EnergyPolynomial::cubic_size(r), "C(r+2, 3)");
    part.quartic = read_coefficients(reader, what + " quartic coefficients",
                                     EnergyPolynomial::quartic_size(r), "C(r+3, 4)");
    parse_checked(reader, offset, what, [&] { part.validate(); });
    parts.push_back(std::move(part));
  }
  Eigen::MatrixXd mass = read_square(reader, name + "'s unit-density mass", r);
  return {std::move(material), reference, scale, std::move(parts), std::move(mass)};
}

/// Reads everything after the header and assembles the model.
ReducedModel read_body(ContainerReader& reader, detail::BasisHeader header) {
  const Eigen::Index r = header.size;
  Basis basis = detail::read_basis_body(reader, std::move(header));
  const ReducedIntegratorDefaults defaults = read_defaults(reader);

  const std::uint64_t count = reader.read_u64("the material group count");
  const std::size_t groups_offset = reader.value_offset();
  if (count == 0) reader.fail_at(groups_offset, "no material groups");
  if (count > reader.remaining_bytes()) {  // each group takes dozens of bytes
    reader.fail_at(groups_offset, std::to_string(count) + " material groups cannot fit in the " +
                                      std::to_string(reader.remaining_bytes()) +
                                      " bytes that remain");
  }
  std::vector<ReducedMaterialGroup> groups;
  for (std::uint64_t g = 0; g < count; ++g) groups.push_back(read_group(reader, g, r));
  reader.finish("the last material group");

  return parse_checked(reader, groups_offset, "the material groups do not form a valid model", [&] {
    return ReducedModel::from_parts(std::move(basis), std::move(groups), defaults);
  });
}

}  // namespace

void write_reduced_model(const std::filesystem::path& file, const ReducedModel& model,
                         const VolumeMesh& mesh) {
  detail::check_basis_writable(file, "reduced model", model.basis(), mesh,
                               reduced_model_file_max_dimension);
  ContainerWriter writer(reduced_model_file_format);
  detail::write_basis_payload(writer, model.basis(), mesh);

  const ReducedIntegratorDefaults& defaults = model.defaults();
  writer.write_f64(defaults.newmark.time_step);
  writer.write_f64(defaults.newmark.beta);
  writer.write_f64(defaults.newmark.gamma);
  writer.write_f64(defaults.newmark.mass_damping);
  writer.write_f64(defaults.newmark.stiffness_damping);
  writer.write_i32(defaults.max_newton_iterations);
  writer.write_f64(defaults.newton_tolerance);

  writer.write_u64(model.groups().size());
  for (const ReducedMaterialGroup& group : model.groups()) {
    const Material& material = group.material;
    if (material.is_stvk()) {
      writer.write_u32(stvk_kind);
      writer.write_f64(material.lame().lambda);
      writer.write_f64(material.lame().mu);
    } else {
      writer.write_u32(general_kind);
      writer.write_matrix(group.reference_elasticity);
      writer.write_f64(group.elasticity_scale);
    }
    writer.write_f64(material.density());
    for (const EnergyPolynomial& part : group.parts) {
      writer.write_matrix(part.quadratic);
      writer.write_doubles({part.cubic.data(), static_cast<std::size_t>(part.cubic.size())});
      writer.write_doubles({part.quartic.data(), static_cast<std::size_t>(part.quartic.size())});
    }
    writer.write_matrix(group.unit_density_mass);
  }
  writer.write_file(file);
}

ReducedModel read_reduced_model(const std::filesystem::path& file, const VolumeMesh& mesh) {
  ContainerReader reader = ContainerReader::open(file, reduced_model_file_format);
  detail::BasisHeader header = read_header(reader);
  detail::check_basis_mesh(reader, header, mesh, "the reduced model");
  return read_body(reader, std::move(header));
}

ReducedModel read_reduced_model(const std::filesystem::path& file) {
  return parse_reduced_model(detail::read_file_bytes(file), file.string());
}

ReducedModel parse_reduced_model(std::string bytes, std::string source) {
  ContainerReader reader(std::move(bytes), std::move(source), reduced_model_file_format);
  detail::BasisHeader header = read_header(reader);
  return read_body(reader, std::move(header));
}

ReducedModelFileInfo read_reduced_model_info(const std::filesystem::path& file) {
  ContainerReader reader = ContainerReader::open(file, reduced_model_file_format);
  detail::BasisHeader header = read_header(reader);
  const ReducedModel model = read_body(reader, header);
  const auto num_fixed = static_cast<Eigen::Index>(model.basis().fixed_vertices.size());
  ReducedModelFileInfo info{
      detail::basis_file_info(reader, std::move(header), num_fixed), {}, model.defaults()};
  for (const ReducedMaterialGroup& group : model.groups()) {
    info.groups.push_back({group.material, group.elasticity_scale});
  }
  return info;
}

}  // namespace khz::reduced
