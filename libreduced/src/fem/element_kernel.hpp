#pragma once
// What one quadrature point contributes to an element's strain energy, internal forces, tangent
// stiffness and Hessian contraction, for geometrically nonlinear elasticity with a linear
// material (thesis §2.1.2–2.1.8). Templated on the node count N (4: tetrahedron, 8: hexahedron)
// so both element types share one implementation with fixed-size, allocation-free Eigen types.
//
// Notation at a quadrature point with weight w and rest gradients G (row a = ∇φ_a):
//   F = I + Σ_a u_a ⊗ ∇φ_a = I + Uᵀ G         deformation gradient (§2.1.2)
//   E = ½(FᵀF − I)                              Green–Lagrange strain (§2.1.2)
//   S = C : E, in Voigt form S_v = C E_v        second Piola–Kirchhoff stress (eq. 2.14)
//   P = F S                                     first Piola–Kirchhoff stress (§2.1.8)
// Energy w·½ E:S (eq. 2.1 with the ½ of a linear law), force R_a = w P ∇φ_a (eq. 2.20, first
// term; the sign makes R the energy gradient as in eq. 2.4).

#include <khz/reduced/fem/material.hpp>

#include <Eigen/Core>

namespace khz::reduced::detail {

using VoigtVector = Eigen::Matrix<double, 6, 1>;

/// Quadrature points of an element with N nodes: one for the linear tetrahedron (gradients are
/// constant), 2×2×2 Gauss for the trilinear hexahedron.
template <int N>
inline constexpr int quadrature_points = N == 4 ? 1 : 8;

/// Per-node 3-vectors of an element, one row per node (displacements u_a, gradients ∇φ_a).
template <int N>
using NodeRows = Eigen::Matrix<double, N, 3, Eigen::RowMajor>;
/// An element's 3N×3N stiffness block, dof 3a+i = node a's axis i (as in the global K).
template <int N>
using ElementMatrix3 = Eigen::Matrix<double, 3 * N, 3 * N>;
/// (∂E_v/∂u)ᵀ for an element, stored transposed: row 3b+k is the strain change per unit
/// displacement of node b along axis k. The transposed layout makes the 3N-long columns the
/// vectorized dimension of the products below.
template <int N>
using StrainDisplacementT = Eigen::Matrix<double, 3 * N, 6>;

/// E_v = (E11, E22, E33, 2E23, 2E13, 2E12) of E = ½(FᵀF − I).
inline VoigtVector green_strain(const Eigen::Matrix3d& deformation_gradient) {
  const Eigen::Matrix3d c = deformation_gradient.transpose() * deformation_gradient;
  VoigtVector strain;
  strain << 0.5 * (c(0, 0) - 1.0), 0.5 * (c(1, 1) - 1.0), 0.5 * (c(2, 2) - 1.0), c(1, 2), c(0, 2),
      c(0, 1);
  return strain;
}

/// The linearized strain sym(H) of a displacement gradient H, in the same Voigt form: the first
/// variation of E at F = I.
inline VoigtVector small_strain(const Eigen::Matrix3d& h) {
  VoigtVector strain;
  strain << h(0, 0), h(1, 1), h(2, 2), h(1, 2) + h(2, 1), h(0, 2) + h(2, 0), h(0, 1) + h(1, 0);
  return strain;
}

/// The symmetric 3×3 tensor of a Voigt stress (S11, S22, S33, S23, S13, S12).
inline Eigen::Matrix3d stress_tensor(const VoigtVector& s) {
  Eigen::Matrix3d stress;
  stress << s[0], s[5], s[4],  //
      s[5], s[1], s[3],        //
      s[4], s[3], s[2];
  return stress;
}

/// B(A)ᵀ with row 3b+k the Voigt form of sym(Aᵀ (e_k ⊗ ∇φ_b)). With A = F this is (∂E_v/∂u)ᵀ,
/// since dE = sym(Fᵀ dF) and dF = du_b ⊗ ∇φ_b; B is linear in A, which the Hessian
/// contraction uses (B(I + εH) = B(I) + ε B(H)).
template <int N>
StrainDisplacementT<N> strain_displacement_t(const NodeRows<N>& gradients,
                                             const Eigen::Matrix3d& a) {
  StrainDisplacementT<N> bt;
  for (int node = 0; node < N; ++node) {
    const double g0 = gradients(node, 0), g1 = gradients(node, 1), g2 = gradients(node, 2);
    for (int k = 0; k < 3; ++k) {
      // Row k of A is the vector Aᵀ e_k.
      const double f0 = a(k, 0), f1 = a(k, 1), f2 = a(k, 2);
      bt.row(3 * node + k) << f0 * g0, f1 * g1, f2 * g2, f1 * g2 + f2 * g1, f0 * g2 + f2 * g0,
          f0 * g1 + f1 * g0;
    }
  }
  return bt;
}

/// Deformation, strain and stress at one quadrature point.
struct PointState {
  Eigen::Matrix3d deformation_gradient;
  VoigtVector strain;
  VoigtVector stress;
};

template <int N>
PointState point_state(const NodeRows<N>& displacements, const NodeRows<N>& gradients,
                       const VoigtMatrix& elasticity) {
  PointState state;
  state.deformation_gradient = Eigen::Matrix3d::Identity() + displacements.transpose() * gradients;
  state.strain = green_strain(state.deformation_gradient);
  state.stress = elasticity * state.strain;
  return state;
}

/// w·½ E:S; with engineering shears E:S = E_v·S_v.
inline double point_energy(const PointState& state, double weight) {
  return 0.5 * weight * state.strain.dot(state.stress);
}

/// R_a += w P ∇φ_a with P = F S, i.e. rows R += w G (F S)ᵀ = w G S Fᵀ.
template <int N>
void add_point_forces(const PointState& state, const NodeRows<N>& gradients, double weight,
                      NodeRows<N>& forces) {
  const Eigen::Matrix3d stress_ft =
      weight * stress_tensor(state.stress) * state.deformation_gradient.transpose();
  forces.noalias() += gradients * stress_ft;
}

/// Sums an element's stiffness-like matrix over its quadrature points,
///   Σ_q w_q B_qᵀ C B'_q  (material part)  +  Σ_q w_q (∇φ_a · S_q ∇φ_b) I₃  (geometric part),
/// and forms it once at the end. The points' factors (w_q C B_q)ᵀ and B'_qᵀ are stored side by
/// side (3N × 6Q), so the material part is one product with inner dimension 6Q instead of Q
/// passes over the 3N×3N result; the geometric scalars are summed as an N×N matrix and spread
/// onto the blocks' diagonals once. Products are lazy (coefficient-based) or hand-blocked:
/// Eigen's blocked GEMM, which it picks for these sizes otherwise, spends more time packing than
/// multiplying.
template <int N>
class ElementStiffnessSum {
 public:
  /// Adds w B_leftᵀ C B_right for quadrature point q (each point exactly once).
  void add_material(int q, const StrainDisplacementT<N>& bt_left,
                    const StrainDisplacementT<N>& bt_right, const VoigtMatrix& elasticity,
                    double weight) {
    m_left.template middleCols<6>(6 * q).noalias() = bt_left.lazyProduct(weight * elasticity);
    m_right.template middleCols<6>(6 * q) = bt_right;
  }

  /// Adds w (∇φ_a · S ∇φ_b) I₃ to every block (a, b).
  void add_geometric(const NodeRows<N>& gradients, const Eigen::Matrix3d& stress, double weight) {
    m_coupling.noalias() += gradients * (weight * stress) * gradients.transpose();
  }

  /// Writes the sum into `matrix`; with `symmetrize_material` the material part M is replaced by
  /// M + Mᵀ (for the Hessian contraction's two cross terms).
  void result(ElementMatrix3<N>& matrix, bool symmetrize_material = false) const {
    // One node's 3 columns at a time, as a sum of rank-1 updates: the 3N×3 panel stays in
    // registers (measured 3× faster than Eigen's lazy or GEMM products for the hexahedron).
    for (int b = 0; b < N; ++b) {
      Eigen::Matrix<double, 3 * N, 3> panel = Eigen::Matrix<double, 3 * N, 3>::Zero();
      for (int k = 0; k < 6 * quadrature_points<N>; ++k) {
        panel.noalias() += m_left.col(k) * m_right.template block<3, 1>(3 * b, k).transpose();
      }
      matrix.template middleCols<3>(3 * b) = panel;
    }
    if (symmetrize_material) matrix += matrix.transpose().eval();
    for (int b = 0; b < N; ++b) {
      for (int a = 0; a < N; ++a) {
        matrix.template block<3, 3>(3 * a, 3 * b).diagonal().array() += m_coupling(a, b);
      }
    }
  }

 private:
  Eigen::Matrix<double, 3 * N, 6 * quadrature_points<N>> m_left;
  Eigen::Matrix<double, 3 * N, 6 * quadrature_points<N>> m_right;
  Eigen::Matrix<double, N, N> m_coupling = Eigen::Matrix<double, N, N>::Zero();
};

/// K += ∂(w P ∇φ_a)/∂u_b at quadrature point q. From dP = dF S + F dS with dF = du_b ⊗ ∇φ_b and
/// dS = C : sym(Fᵀ dF): the dF S term gives the geometric part (∇φ_a · S ∇φ_b) I₃, the F dS term
/// the material part w Bᵀ C B with B = B(F) = ∂E_v/∂u (R = w Bᵀ S_v, so this is its derivative
/// at fixed S).
template <int N>
void add_point_stiffness(int q, const PointState& state, const NodeRows<N>& gradients,
                         const VoigtMatrix& elasticity, double weight,
                         ElementStiffnessSum<N>& stiffness) {
  const StrainDisplacementT<N> bt = strain_displacement_t<N>(gradients, state.deformation_gradient);
  stiffness.add_material(q, bt, bt, elasticity, weight);
  stiffness.add_geometric(gradients, stress_tensor(state.stress), weight);
}

/// (H : v) += d/dε K(εv)|₀ at quadrature point q (thesis eq. 2.48–2.50), with the material part
/// to be symmetrized by result(). With H = Vᵀ G = ∇v, along u = εv: F = I + εH, so
/// B(F) = B(I) + ε B(H) and S = ε C sym(H) + O(ε²). Differentiating w [B(F)ᵀ C B(F) + geometric(S)]
/// at ε = 0 (where S = 0) leaves w [B(H)ᵀ C B(I) + B(I)ᵀ C B(H)] + geometric(C sym(H)).
template <int N>
void add_point_hessian_contraction(int q, const NodeRows<N>& direction,
                                   const NodeRows<N>& gradients, const VoigtMatrix& elasticity,
                                   double weight, ElementStiffnessSum<N>& contraction) {
  const Eigen::Matrix3d h = direction.transpose() * gradients;
  contraction.add_material(q, strain_displacement_t<N>(gradients, h),
                           strain_displacement_t<N>(gradients, Eigen::Matrix3d::Identity()),
                           elasticity, weight);
  contraction.add_geometric(gradients, stress_tensor(elasticity * small_strain(h)), weight);
}

}  // namespace khz::reduced::detail
