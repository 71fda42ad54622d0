#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <Eigen/Cholesky>

#include <cmath>
#include <string>
#include <utility>

namespace khz::reduced {

namespace {

std::string group_name(int group) { return "material group " + std::to_string(group); }

}  // namespace

std::vector<double> ReducedMaterialGroup::part_weights() const {
  if (material.is_stvk()) return {material.lame().lambda, material.lame().mu};
  return {elasticity_scale};
}

ReducedModel::ReducedModel(Basis basis, std::vector<ReducedMaterialGroup> groups,
                           const ReducedIntegratorDefaults& defaults)
    : m_basis(std::move(basis)), m_groups(std::move(groups)), m_defaults(defaults) {}

ReducedModel ReducedModel::from_parts(Basis basis, std::vector<ReducedMaterialGroup> groups,
                                      const ReducedIntegratorDefaults& defaults) {
  const Eigen::Index r = basis.size();
  if (r == 0) throw Error("ReducedModel: the basis has no vectors");
  if (!basis.vectors.allFinite()) throw Error("ReducedModel: the basis has a non-finite entry");
  if (groups.empty()) throw Error("ReducedModel: no material groups");
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const ReducedMaterialGroup& group = groups[g];
    const std::string name = group_name(static_cast<int>(g));
    const std::size_t expected_parts = group.material.is_stvk() ? 2 : 1;
    if (group.parts.size() != expected_parts) {
      throw Error("ReducedModel: " + name + " has " + std::to_string(group.parts.size()) +
                  " energy parts, expected " + std::to_string(expected_parts));
    }
    for (const EnergyPolynomial& part : group.parts) {
      if (part.dimension() != r) {
        throw Error("ReducedModel: " + name + " has a polynomial in " +
                    std::to_string(part.dimension()) + " coordinates, the basis has " +
                    std::to_string(r));
      }
      part.validate();
    }
    if (group.unit_density_mass.rows() != r || group.unit_density_mass.cols() != r ||
        !group.unit_density_mass.allFinite()) {
      throw Error("ReducedModel: " + name + " has no finite " + std::to_string(r) + "×" +
                  std::to_string(r) + " unit-density mass");
    }
    if (!group.material.is_stvk()) {
      const VoigtMatrix expected = group.elasticity_scale * group.reference_elasticity;
      if (!(group.elasticity_scale > 0) || !std::isfinite(group.elasticity_scale) ||
          !(group.material.elasticity() - expected).isZero(1e-12 * expected.norm())) {
        throw Error("ReducedModel: " + name +
                    "'s elasticity is not its scale times its reference elasticity");
      }
    }
  }
  ReducedModel model(std::move(basis), std::move(groups), defaults);
  model.set_defaults(defaults);
  if (model.mass().llt().info() != Eigen::Success) {
    throw Error("ReducedModel: the reduced mass is not positive definite");
  }
  return model;
}

ReducedNewmarkOptions ReducedIntegratorDefaults::newmark_options() const {
  ReducedNewmarkOptions options;
  options.newmark = newmark;
  options.max_newton_iterations = max_newton_iterations;
  options.tolerance = newton_tolerance;
  return options;
}

void ReducedModel::set_defaults(const ReducedIntegratorDefaults& defaults) {
  defaults.newmark_options().validate();
  m_defaults = defaults;
}

ReducedMaterialGroup& ReducedModel::group_at(int group, const char* caller) {
  if (group < 0 || group >= static_cast<int>(m_groups.size())) {
    throw Error(std::string("ReducedModel::") + caller + ": there is no " + group_name(group) +
                " (the model has " + std::to_string(m_groups.size()) + ")");
  }
  return m_groups[group];
}

void ReducedModel::set_lame(int group, LameParameters lame) {
  ReducedMaterialGroup& target = group_at(group, "set_lame");
  if (!target.material.is_stvk()) {
    throw Error("ReducedModel::set_lame: " + group_name(group) +
                " has a general material; use set_elasticity_scale");
  }
  target.material = Material::stvk_lame(lame, target.material.density());
}

void ReducedModel::set_elasticity_scale(int group, double scale) {
  ReducedMaterialGroup& target = group_at(group, "set_elasticity_scale");
  if (target.material.is_stvk()) {
    throw Error("ReducedModel::set_elasticity_scale: " + group_name(group) +
                " is StVK; use set_lame");
  }
  if (!(scale > 0) || !std::isfinite(scale)) {
    throw Error("ReducedModel::set_elasticity_scale: the scale must be positive and finite");
  }
  target.material =
      Material::general(scale * target.reference_elasticity, target.material.density());
  target.elasticity_scale = scale;
}

void ReducedModel::set_density(int group, double density) {
  ReducedMaterialGroup& target = group_at(group, "set_density");
  if (!(density > 0) || !std::isfinite(density)) {
    throw Error("ReducedModel::set_density: the density must be positive and finite");
  }
  target.material = target.material.is_stvk()
                        ? Material::stvk_lame(target.material.lame(), density)
                        : Material::general(target.material.elasticity(), density);
}

EnergyPolynomial ReducedModel::energy_polynomial() const {
  EnergyPolynomial sum;
  energy_polynomial(sum);
  return sum;
}

void ReducedModel::energy_polynomial(EnergyPolynomial& out) const {
  const Eigen::Index r = dimension();
  if (out.dimension() != r || out.cubic.size() != EnergyPolynomial::cubic_size(r) ||
      out.quartic.size() != EnergyPolynomial::quartic_size(r)) {
    out = EnergyPolynomial::zero(r);
  } else {
    out.quadratic.setZero();
    out.cubic.setZero();
    out.quartic.setZero();
  }
  for (const ReducedMaterialGroup& group : m_groups) {
    const std::vector<double> weights = group.part_weights();
    for (std::size_t p = 0; p < group.parts.size(); ++p) out.add_scaled(weights[p], group.parts[p]);
  }
}

Eigen::MatrixXd ReducedModel::mass() const {
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(dimension(), dimension());
  for (const ReducedMaterialGroup& group : m_groups) {
    sum += group.material.density() * group.unit_density_mass;
  }
  return sum;
}

ReducedModel ReducedModel::truncated(Eigen::Index dimension) const {
  if (dimension < 1 || dimension > this->dimension()) {
    throw Error("ReducedModel::truncated: r' = " + std::to_string(dimension) + " is not in [1, " +
                std::to_string(this->dimension()) + "]");
  }
  Basis basis{m_basis.vectors.leftCols(dimension), m_basis.fixed_vertices,
              m_basis.recipe + ", first " + std::to_string(dimension) + " vectors"};
  std::vector<ReducedMaterialGroup> groups = m_groups;
  for (ReducedMaterialGroup& group : groups) {
    for (EnergyPolynomial& part : group.parts) part = part.truncated(dimension);
    group.unit_density_mass = group.unit_density_mass.topLeftCorner(dimension, dimension).eval();
  }
  return ReducedModel(std::move(basis), std::move(groups), m_defaults);
}

}  // namespace khz::reduced
