#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "fem/element_coloring.hpp"
#include "fem/element_kernel.hpp"
#include "fem/stiffness_layout.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>

namespace khz::reduced {
namespace {

using detail::ElementMatrix3;
using detail::NodeRows;
using detail::quadrature_points;

/// Calls visit(std::integral_constant<int, N>) with the mesh's node count, so element loops are
/// compiled once per element type with fixed-size kernels.
template <typename Visitor>
decltype(auto) with_node_count(ElementType type, Visitor&& visit) {
  if (type == ElementType::tetrahedron) return visit(std::integral_constant<int, 4>{});
  return visit(std::integral_constant<int, 8>{});
}

/// Below this many elements the loops run on one thread: a colour sweep has a barrier per colour
/// (15–20 on box meshes), which costs more than the element work of a small mesh, and far more
/// when the machine is oversubscribed and a waiting thread loses its core.
constexpr Eigen::Index min_parallel_elements = 2000;
/// Elements per colouring chunk: enough for neighbours to share cache lines of R and K, few
/// enough that a colour of a 10k-element mesh still has dozens of chunks to share out.
constexpr int chunk_size = 32;

void check_size(const Eigen::VectorXd& vector, Eigen::Index dofs, const char* what) {
  if (vector.size() != dofs) {
    throw Error(std::string("FemModel::") + what + ": vector has " + std::to_string(vector.size()) +
                " entries, the model has " + std::to_string(dofs) + " dofs");
  }
}

}  // namespace

// Per-element data is stored in "slots": slot s holds element coloring.order[s], the order the
// assembly loops visit elements, so they stream through gradients, weights and scatter positions
// instead of jumping around memory.
struct FemModel::Data {
  VolumeMesh mesh;
  std::vector<Material> materials;
  int nodes = 0;
  int points = 0;
  detail::ElementColoring coloring;
  std::vector<int> slot_of_element;
  ElementMatrix slot_nodes;        ///< Row s: the nodes of slot s's element.
  std::vector<int> slot_material;  ///< Per slot, into `materials`.
  /// Per slot, per quadrature point: ∇φ (nodes × 3, row-major) and the weight.
  std::vector<double> gradients;
  std::vector<double> weights;
  detail::StiffnessLayout layout;  ///< Built from slot_nodes: block positions per slot.

  Eigen::Index dofs() const noexcept { return 3 * mesh.num_vertices(); }
  int num_slots() const noexcept { return static_cast<int>(coloring.order.size()); }

  /// Index of quadrature point q of slot `slot` in `weights` (× nodes × 3 in `gradients`).
  std::size_t point_index(int slot, int q) const noexcept {
    return static_cast<std::size_t>(slot) * points + q;
  }
  const double* gradient_data(int slot, int q) const noexcept {
    return gradients.data() + point_index(slot, q) * nodes * 3;
  }
  double weight(int slot, int q) const noexcept { return weights[point_index(slot, q)]; }
  const Material& material(int slot) const noexcept { return materials[slot_material[slot]]; }

  void arrange_slots() {
    const int count = static_cast<int>(mesh.num_elements());
    slot_of_element.resize(count);
    slot_nodes.resize(count, nodes);
    for (int slot = 0; slot < count; ++slot) {
      const int element = coloring.order[slot];
      slot_of_element[element] = slot;
      slot_nodes.row(slot) = mesh.elements.row(element);
    }
  }

  void assign_materials() {
    if (materials.empty()) throw Error("FemModel needs at least one material");
    slot_material.assign(num_slots(), 0);
    if (mesh.element_groups.size() == 0) return;
    for (int element = 0; element < num_slots(); ++element) {
      const int group = mesh.element_groups[element];
      if (group >= static_cast<int>(materials.size())) {
        throw Error("element " + std::to_string(element) + " is in material group " +
                    std::to_string(group) + " but only " + std::to_string(materials.size()) +
                    " materials were given (groups 0.." + std::to_string(materials.size() - 1) +
                    ")");
      }
      slot_material[slot_of_element[element]] = group;
    }
  }

  template <int N>
  void precompute_quadrature() {
    using Corners = Eigen::Matrix<double, N, 3, Eigen::RowMajor>;
    gradients.resize(static_cast<std::size_t>(num_slots()) * points * N * 3);
    weights.resize(static_cast<std::size_t>(num_slots()) * points);
    // In element order, so an error names the lowest offending element.
    for (int element = 0; element < num_slots(); ++element) {
      const int slot = slot_of_element[element];
      Corners corners;
      for (int a = 0; a < N; ++a) corners.row(a) = mesh.vertices.row(mesh.elements(element, a));
      for (int q = 0; q < points; ++q) {
        Eigen::Map<NodeRows<N>> gradient(gradients.data() + point_index(slot, q) * N * 3);
        double& w = weights[point_index(slot, q)];
        if constexpr (N == 4) {
          gradient = tet_shape_gradients(corners);
          w = tet_signed_volume(corners);
        } else {
          const QuadraturePoint& point = hex_gauss_points()[q];
          const HexGradients shape = hex_shape_gradients(corners, point.xi);
          gradient = shape.gradients;
          w = shape.jacobian_determinant * point.weight;
        }
        // require_valid_elements() checks hexahedra at their corners; a trilinear map can still
        // fold at an interior Gauss point, which would make the weight non-positive.
        if (!(w > 0.0)) {
          throw MeshError("element " + std::to_string(element) +
                              " has a non-positive Jacobian determinant at quadrature point " +
                              std::to_string(q),
                          element);
        }
      }
    }
  }

  template <int N>
  NodeRows<N> gather(const Eigen::VectorXd& u, int slot) const {
    NodeRows<N> values;
    for (int a = 0; a < N; ++a) values.row(a) = u.segment<3>(3 * slot_nodes(slot, a));
    return values;
  }

  template <int N>
  void scatter_forces(int slot, const NodeRows<N>& element_forces, double* forces) const {
    for (int a = 0; a < N; ++a) {
      Eigen::Map<Eigen::Vector3d>(forces + 3 * slot_nodes(slot, a)) +=
          element_forces.row(a).transpose();
    }
  }

  template <int N>
  void scatter_matrix(int slot, const ElementMatrix3<N>& block, double* values) const {
    const int* position = layout.block_positions.data() + static_cast<std::size_t>(slot) * N * N;
    for (int b = 0; b < N; ++b) {
      const int stride = layout.column_stride[slot_nodes(slot, b)];
      for (int a = 0; a < N; ++a, ++position) {
        for (int k = 0; k < 3; ++k) {
          Eigen::Map<Eigen::Vector3d>(values + *position + k * stride) +=
              block.template block<3, 1>(3 * a, 3 * b + k);
        }
      }
    }
  }

  /// Runs body(slot) for every slot, in parallel over the chunks of each colour: chunks of a
  /// colour share no vertex, so bodies may scatter into shared R and K without synchronization,
  /// and every entry receives its contributions in the same order for any thread count.
  template <typename Body>
  void for_each_slot_by_color(const Body& body) const {
    const int colors = coloring.num_colors();
#pragma omp parallel num_threads(worker_threads()) if (num_slots() >= min_parallel_elements)
    for (int c = 0; c < colors; ++c) {
      const int end = coloring.color_offsets[c + 1];
#pragma omp for schedule(static)
      for (int chunk = coloring.color_offsets[c]; chunk < end; ++chunk) {
        const int last = coloring.chunk_offsets[chunk + 1];
        for (int slot = coloring.chunk_offsets[chunk]; slot < last; ++slot) body(slot);
      }
    }
  }

  /// The shared element loop of internal_forces, tangent_stiffness and forces_and_stiffness.
  template <int N, bool WithForces, bool WithStiffness>
  void assemble(const Eigen::VectorXd& u, double* forces, double* stiffness) const {
    for_each_slot_by_color([&](int slot) {
      const NodeRows<N> displacements = gather<N>(u, slot);
      const VoigtMatrix& elasticity = material(slot).elasticity();
      NodeRows<N> element_forces = NodeRows<N>::Zero();
      detail::ElementStiffnessSum<N> element_stiffness;
      for (int q = 0; q < quadrature_points<N>; ++q) {
        const Eigen::Map<const NodeRows<N>> gradient(gradient_data(slot, q));
        const detail::PointState state =
            detail::point_state<N>(displacements, gradient, elasticity);
        if constexpr (WithForces) {
          detail::add_point_forces<N>(state, gradient, weight(slot, q), element_forces);
        }
        if constexpr (WithStiffness) {
          detail::add_point_stiffness<N>(q, state, gradient, elasticity, weight(slot, q),
                                         element_stiffness);
        }
      }
      if constexpr (WithForces) scatter_forces<N>(slot, element_forces, forces);
      if constexpr (WithStiffness) {
        ElementMatrix3<N> block;
        element_stiffness.result(block);
        scatter_matrix<N>(slot, block, stiffness);
      }
    });
  }

  template <int N>
  double strain_energy(const Eigen::VectorXd& u) const {
    const int count = num_slots();
    double energy = 0.0;
#pragma omp parallel for num_threads(worker_threads()) schedule(static) reduction(+ : energy) if (count >= min_parallel_elements)
    for (int slot = 0; slot < count; ++slot) {
      const NodeRows<N> displacements = gather<N>(u, slot);
      const VoigtMatrix& elasticity = material(slot).elasticity();
      for (int q = 0; q < quadrature_points<N>; ++q) {
        const Eigen::Map<const NodeRows<N>> gradient(gradient_data(slot, q));
        energy += detail::point_energy(detail::point_state<N>(displacements, gradient, elasticity),
                                       weight(slot, q));
      }
    }
    return energy;
  }

  template <int N>
  void hessian_contraction(const Eigen::VectorXd& v, double* values) const {
    for_each_slot_by_color([&](int slot) {
      const NodeRows<N> direction = gather<N>(v, slot);
      const VoigtMatrix& elasticity = material(slot).elasticity();
      detail::ElementStiffnessSum<N> contraction;
      for (int q = 0; q < quadrature_points<N>; ++q) {
        const Eigen::Map<const NodeRows<N>> gradient(gradient_data(slot, q));
        detail::add_point_hessian_contraction<N>(q, direction, gradient, elasticity,
                                                 weight(slot, q), contraction);
      }
      ElementMatrix3<N> block;
      contraction.result(block, true);
      scatter_matrix<N>(slot, block, values);
    });
  }

  /// ∫ρ φ_a φ_b dV of a slot's element (thesis eq. 2.49), without the I₃ factor.
  template <int N>
  Eigen::Matrix<double, N, N> element_mass(int slot, double density) const {
    if constexpr (N == 4) {
      // Exact for linear shape functions: ∫φ_a φ_b dV = V/20 (1 + δ_ab). The one-point rule the
      // stiffness uses would not integrate this quadratic.
      return density * weight(slot, 0) / 20.0 *
             (Eigen::Matrix4d::Ones() + Eigen::Matrix4d::Identity());
    } else {
      // 2×2×2 Gauss is exact for the trilinear products on parallelepipeds.
      Eigen::Matrix<double, N, N> mass = Eigen::Matrix<double, N, N>::Zero();
      for (int q = 0; q < quadrature_points<N>; ++q) {
        const Eigen::Matrix<double, N, 1> phi = hex_shape_values(hex_gauss_points()[q].xi);
        mass.noalias() += density * weight(slot, q) * phi * phi.transpose();
      }
      return mass;
    }
  }

  /// The mass matrix; with `unit_density_group` ≥ 0, only that group's elements at density 1.
  template <int N>
  SparseMatrix mass_matrix(MassLumping lumping, int unit_density_group) const {
    std::vector<Eigen::Triplet<double, int>> triplets;
    triplets.reserve(static_cast<std::size_t>(num_slots()) * 3 *
                     (lumping == MassLumping::consistent ? N * N : N));
    for (int slot = 0; slot < num_slots(); ++slot) {
      if (unit_density_group >= 0 && slot_material[slot] != unit_density_group) continue;
      const Eigen::Matrix<double, N, N> mass =
          element_mass<N>(slot, unit_density_group >= 0 ? 1.0 : material(slot).density());
      for (int a = 0; a < N; ++a) {
        const int row = 3 * slot_nodes(slot, a);
        if (lumping == MassLumping::lumped) {
          const double total = mass.row(a).sum();
          for (int i = 0; i < 3; ++i) triplets.emplace_back(row + i, row + i, total);
          continue;
        }
        for (int b = 0; b < N; ++b) {
          const int column = 3 * slot_nodes(slot, b);
          for (int i = 0; i < 3; ++i) triplets.emplace_back(row + i, column + i, mass(a, b));
        }
      }
    }
    SparseMatrix matrix(dofs(), dofs());
    matrix.setFromTriplets(triplets.begin(), triplets.end());
    return matrix;
  }

  void check_pattern(const SparseMatrix& stiffness) const {
    const SparseMatrix& pattern = layout.pattern;
    bool same = stiffness.rows() == pattern.rows() && stiffness.cols() == pattern.cols() &&
                stiffness.isCompressed() && stiffness.nonZeros() == pattern.nonZeros();
#ifndef NDEBUG
    // The full index comparison costs as much as an assembly: debug builds only.
    same = same &&
           std::equal(pattern.outerIndexPtr(), pattern.outerIndexPtr() + pattern.cols() + 1,
                      stiffness.outerIndexPtr()) &&
           std::equal(pattern.innerIndexPtr(), pattern.innerIndexPtr() + pattern.nonZeros(),
                      stiffness.innerIndexPtr());
#endif
    if (!same) {
      throw Error(
          "FemModel: the stiffness matrix passed in does not have stiffness_pattern()'s "
          "pattern");
    }
  }
};

FemModel::FemModel(VolumeMesh mesh, std::vector<Material> materials)
    : m_data(std::make_unique<Data>()) {
  require_valid_elements(mesh);
  Data& data = *m_data;
  data.mesh = std::move(mesh);
  data.materials = std::move(materials);
  data.nodes = nodes_per_element(data.mesh.element_type);
  data.coloring = detail::color_elements(data.mesh, chunk_size);
  data.arrange_slots();
  data.assign_materials();
  with_node_count(data.mesh.element_type, [&](auto n) {
    data.points = quadrature_points<decltype(n)::value>;
    data.precompute_quadrature<decltype(n)::value>();
  });
  data.layout =
      detail::build_stiffness_layout(data.slot_nodes, static_cast<int>(data.mesh.num_vertices()));
}

FemModel::~FemModel() = default;
FemModel::FemModel(FemModel&&) noexcept = default;
FemModel& FemModel::operator=(FemModel&&) noexcept = default;

const VolumeMesh& FemModel::mesh() const noexcept { return m_data->mesh; }

const std::vector<Material>& FemModel::materials() const noexcept { return m_data->materials; }

const Material& FemModel::element_material(Eigen::Index element) const noexcept {
  return m_data->material(m_data->slot_of_element[element]);
}

Eigen::Index FemModel::num_dofs() const noexcept { return m_data->dofs(); }

int FemModel::quadrature_points_per_element() const noexcept { return m_data->points; }

Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>
FemModel::shape_gradients(Eigen::Index element, int q) const noexcept {
  return {m_data->gradient_data(m_data->slot_of_element[element], q), m_data->nodes, 3};
}

double FemModel::quadrature_weight(Eigen::Index element, int q) const noexcept {
  return m_data->weight(m_data->slot_of_element[element], q);
}

SparseMatrix FemModel::mass_matrix(MassLumping lumping) const {
  return with_node_count(m_data->mesh.element_type, [&](auto n) {
    return m_data->mass_matrix<decltype(n)::value>(lumping, -1);
  });
}

SparseMatrix FemModel::unit_density_mass_matrix(int group, MassLumping lumping) const {
  if (group < 0 || group >= static_cast<int>(m_data->materials.size())) {
    throw Error("unit_density_mass_matrix: group " + std::to_string(group) +
                " is not one of the model's " + std::to_string(m_data->materials.size()) +
                " material groups");
  }
  return with_node_count(m_data->mesh.element_type, [&](auto n) {
    return m_data->mass_matrix<decltype(n)::value>(lumping, group);
  });
}

double FemModel::strain_energy(const Eigen::VectorXd& u) const {
  check_size(u, num_dofs(), "strain_energy");
  return with_node_count(m_data->mesh.element_type,
                         [&](auto n) { return m_data->strain_energy<decltype(n)::value>(u); });
}

void FemModel::internal_forces(const Eigen::VectorXd& u, Eigen::VectorXd& forces) const {
  check_size(u, num_dofs(), "internal_forces");
  forces.setZero(num_dofs());
  with_node_count(m_data->mesh.element_type, [&](auto n) {
    m_data->assemble<decltype(n)::value, true, false>(u, forces.data(), nullptr);
  });
}

SparseMatrix FemModel::stiffness_pattern() const { return m_data->layout.pattern; }

void FemModel::tangent_stiffness(const Eigen::VectorXd& u, SparseMatrix& stiffness) const {
  check_size(u, num_dofs(), "tangent_stiffness");
  m_data->check_pattern(stiffness);
  stiffness.coeffs().setZero();
  with_node_count(m_data->mesh.element_type, [&](auto n) {
    m_data->assemble<decltype(n)::value, false, true>(u, nullptr, stiffness.valuePtr());
  });
}

void FemModel::forces_and_stiffness(const Eigen::VectorXd& u, Eigen::VectorXd& forces,
                                    SparseMatrix& stiffness) const {
  check_size(u, num_dofs(), "forces_and_stiffness");
  m_data->check_pattern(stiffness);
  forces.setZero(num_dofs());
  stiffness.coeffs().setZero();
  with_node_count(m_data->mesh.element_type, [&](auto n) {
    m_data->assemble<decltype(n)::value, true, true>(u, forces.data(), stiffness.valuePtr());
  });
}

SparseMatrix FemModel::hessian_contraction(const Eigen::VectorXd& v) const {
  check_size(v, num_dofs(), "hessian_contraction");
  SparseMatrix contraction = m_data->layout.pattern;
  with_node_count(m_data->mesh.element_type, [&](auto n) {
    m_data->hessian_contraction<decltype(n)::value>(v, contraction.valuePtr());
  });
  return contraction;
}

}  // namespace khz::reduced
