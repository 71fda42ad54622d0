#pragma once
// The deformed distance field of a reduced deformable object (thesis §3.12, §3.12.1): signed
// distances to the deformed surface, approximated from precomputed rest-shape fields by pulling
// the query point back through the deformation gradients at a few nearby "proxies".

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/reduced/fem/embedding.hpp>

#include <Eigen/Core>

#include <cassert>
#include <cstdint>
#include <span>
#include <vector>

namespace khz::contact {

/// Options of DeformedDistanceField.
struct KHZ_CONTACT_API DeformedFieldOptions {
  /// Largest `neighbours` allowed: the queries keep their k nearest proxies in fixed-size
  /// buffers on the stack, so that they allocate nothing (the thesis uses k = 5).
  static constexpr int max_neighbours = 16;

  /// Proxies fitted per domain by particle repulsion (the thesis's "typically ~40"), ≥
  /// `neighbours`. Used only by the constructor that fits them.
  Eigen::Index proxies = 40;
  /// k, the nearest proxies blended per domain (eq. 3.16), in [2, max_neighbours]. The k-th
  /// gets weight 0, so k − 1 rest-field lookups are made per domain and query. The thesis
  /// uses 5: five points in general position do not lie on one sphere, so the k distances
  /// are rarely all equal.
  int neighbours = 5;
  /// Seed of the proxies' random starting positions (RepulsionOptions::seed); domain i uses
  /// seed + i. The same seed gives the same proxies, bit for bit.
  std::uint64_t seed = 0;
  /// Reports, per fitted domain, the stages of repulsion_pointshell() ("pointshell level set",
  /// "particle repulsion level 0", "pointshell normals"), then "proxy modes" (units: proxies
  /// of all domains). Returning false cancels (Cancelled).
  ProgressCallback progress;

  /// @throws Error naming the first invalid option.
  void validate() const;
};

/// The precomputed, immutable part of the deformed distance field of one reduced deformable
/// object (thesis §3.12): one or more domains (§3.12.1), each a signed rest-shape DistanceGrid
/// and a proxyshell of points on that field's zero level set, with each proxy's rest position
/// P_i, displacement modes U_i (3×r) and deformation-gradient modes F_ij (r matrices 3×3)
/// sampled from a reduced basis U (3n×r) of the object's volume mesh, so that
///   p_i(q) = P_i + U_i q,   F_i(q) = I + Σ_j F_ij q_j    (eq. 3.6, 3.7).
/// The per-cycle evaluation lives in DeformedFieldState.
///
/// Coordinates are the object's own body frame (metres) throughout: the rest fields, the basis
/// and the queries; the contact query applies rigid poses itself.
///
/// Layout (structure of arrays, proxies of all domains numbered consecutively, domain d owning
/// [domain_begin(d), domain_end(d))): the rest positions are one vector of 3N values (all x,
/// then all y, then all z); the displacement modes one column-major 3N×r matrix in the same row
/// order, so p(q) = P + U q is one matrix-vector product giving the x, y and z arrays the
/// nearest-neighbour search reads; the deformation-gradient modes one column-major 9N×r matrix,
/// rows (3a + b)·N + i holding entry (a, b) of proxy i's F_ij in column j.
///
/// Immutable after construction; every const member is thread-safe.
class KHZ_CONTACT_API DeformedDistanceField {
 public:
  /// Fits options.proxies proxies on the zero level set of each field by particle repulsion
  /// (repulsion_pointshell() with one level, normals from isosurface(field, 0)), then samples
  /// their modes from the basis (MeshEmbedding::locate() and modes(); proxies outside the
  /// volume mesh extrapolate the nearest element).
  /// @param fields One signed rest-shape distance field (m) per domain, ≥ 1 domain. Several
  ///        domains (e.g. one per leg of a figure) remove the "mirror" artefacts of a single
  ///        field when parts move apart (§3.12.1); the field value is then the minimum.
  /// @param embedding The object's volume mesh (n vertices); used only here.
  /// @param basis U, 3n×r (m per unit q), r ≥ 1.
  /// @throws Error for invalid options, no fields, an unsigned field, a field whose zero level
  ///         set does not cross its grid, or a basis without 3n rows or columns (each message
  ///         names the domain or the sizes); what repulsion_pointshell() throws; Cancelled.
  DeformedDistanceField(std::vector<DistanceGrid> fields, const reduced::MeshEmbedding& embedding,
                        const Eigen::MatrixXd& basis, const DeformedFieldOptions& options = {});

  /// With given proxies instead of fitted ones: proxies[d] (#P_d×3, m) are domain d's rest
  /// positions, usually on its field's zero level set (anywhere works; the approximation is
  /// best with the proxies spread over the surface). options.proxies and options.seed are not
  /// used.
  /// @throws Error as above, and if `proxies` does not have one matrix per field, a domain has
  ///         fewer than options.neighbours proxies, or a proxy coordinate is not finite.
  DeformedDistanceField(std::vector<DistanceGrid> fields, const std::vector<PointMatrix>& proxies,
                        const reduced::MeshEmbedding& embedding, const Eigen::MatrixXd& basis,
                        const DeformedFieldOptions& options = {});

  /// r, the number of reduced coordinates.
  Eigen::Index dimension() const noexcept { return m_dimension; }
  /// k, the proxies blended per domain.
  int neighbours() const noexcept { return m_neighbours; }
  /// The number of domains.
  Eigen::Index num_domains() const noexcept { return static_cast<Eigen::Index>(m_fields.size()); }
  /// Domain d's rest-shape field, 0 ≤ d < num_domains().
  const DistanceGrid& field(Eigen::Index d) const noexcept {
    assert(d >= 0 && d < num_domains());
    return m_fields[static_cast<std::size_t>(d)];
  }
  /// N, the proxies of all domains.
  Eigen::Index num_proxies() const noexcept { return m_rest.size() / 3; }
  /// First proxy of domain d.
  Eigen::Index domain_begin(Eigen::Index d) const noexcept {
    return d == 0 ? 0 : m_domain_ends[static_cast<std::size_t>(d - 1)];
  }
  /// One past the last proxy of domain d.
  Eigen::Index domain_end(Eigen::Index d) const noexcept {
    return m_domain_ends[static_cast<std::size_t>(d)];
  }

  /// P_i (m), 0 ≤ i < num_proxies().
  Eigen::Vector3d rest_position(Eigen::Index i) const noexcept;
  /// U_i (3×r, m per unit q), gathered from the structure-of-arrays layout (not for hot loops).
  Eigen::Matrix<double, 3, Eigen::Dynamic> displacement_modes(Eigen::Index i) const;
  /// F_ij (per unit q), 0 ≤ j < dimension().
  Eigen::Matrix3d gradient_mode(Eigen::Index i, Eigen::Index j) const noexcept;

  /// max_v ‖U_v‖_F over the vertices v of the volume mesh (m per unit q): no point of the
  /// object, its surface included (FEM interpolation stays within its element's vertex
  /// displacements), moves more than this times ‖Δq‖ when q changes by Δq. Temporal coherence
  /// uses it to bound how fast the distance to the deformed surface can change (§3.10.2).
  double displacement_bound() const noexcept { return m_displacement_bound; }
  /// The largest difference between neighbouring node values of domain d's field along an
  /// axis, per metre (about 1 for a distance field): the field's value changes by at most this
  /// times ‖Δx‖₁ within its box. DeformedFieldState::culling_distance() bounds with it.
  double field_slope(Eigen::Index d) const noexcept {
    assert(d >= 0 && d < num_domains());
    return m_slopes[static_cast<std::size_t>(d)];
  }
  /// The layout described above, for DeformedFieldState.
  const Eigen::VectorXd& rest_positions() const noexcept { return m_rest; }
  const Eigen::MatrixXd& displacement_matrix() const noexcept { return m_displacement; }
  const Eigen::MatrixXd& gradient_matrix() const noexcept { return m_gradient; }

 private:
  void initialize(const std::vector<PointMatrix>& proxies, const reduced::MeshEmbedding& embedding,
                  const Eigen::MatrixXd& basis, const ProgressCallback& progress);

  std::vector<DistanceGrid> m_fields;
  std::vector<Eigen::Index> m_domain_ends;
  Eigen::Index m_dimension = 0;
  int m_neighbours = 5;
  Eigen::VectorXd m_rest;          // 3N: x, y, z blocks
  Eigen::MatrixXd m_displacement;  // 3N × r, same rows
  Eigen::MatrixXd m_gradient;      // 9N × r, rows (3a + b)·N + i
  double m_displacement_bound = 0.0;
  std::vector<double> m_slopes;  // per domain: field_slope()
};

/// The per-cycle state of a DeformedDistanceField at reduced coordinates q, owned by the caller
/// (one per thread that calls update()); its buffers are allocated once, here. It evaluates the
/// deformed signed distance d(x) of thesis §3.12 and satisfies the DistanceField concept.
///
/// update(q) deforms the proxies: p_i = P_i + U_i q and F_i = I + Σ_j F_ij q_j, with F_i⁻¹.
/// A query at x, per domain:
///  1. the k proxies nearest to x (distances δ_1 ≤ … ≤ δ_k to the deformed p_i; ties, to 2⁻⁴⁶
///     relative, go to the lower index), by brute force over the domain's proxies;
///  2. the weights of eq. 3.16, w_i = v_i / Σ v, v_i = 1/δ_i − 1/δ_k (the normalization
///     cancels eq. 3.16's common factor 1/(1/δ_min − 1/δ_max)), evaluated in the bounded form
///     (δ_1/δ_i)(δ_k − δ_i), so that x on a proxy (δ_1 = 0) gives that proxy weight 1, the
///     limit. Only if all k distances are equal (x the centre of a sphere through them) are
///     the weights undefined; the k − 1 nearest then get 1/(k − 1) each;
///  3. the pull-backs X_i = P_i + F_i⁻¹(x − p_i) (eq. 3.17) and d_i = the rest field at X_i
///     (DistanceGrid::distance(): a conservative lower bound outside its box);
///  4. d = Σ w_i d_i.
/// The value is the minimum over the domains (§3.12.1). w_k = 0 and all weights vary
/// continuously with x and q, so d is continuous in both, including where the set of nearest
/// proxies changes (§3.12); it is differentiable wherever the neighbour set and the grid cells
/// of the X_i stay the same.
///
/// Cost (bench_deformed_distance_field: dino.off, 128³ field, r = 15, 40 proxies, k = 5, points
/// within 2h of the deformed surface; one core of this project's Xeon, load from other jobs):
/// distance() about 140 ns, distance_and_gradient() 169 ns, culling_distance() 131 ns where
/// every point is culled and 137 ns at threshold 0, culling_distances() 16 points at a time 80
/// and 91 ns per point, update() 1.0 µs. The neighbour search takes about half of a query.
///
/// All members but the constructor and assignment are noexcept and allocate nothing; the const
/// queries are thread-safe. The field must outlive the state.
class KHZ_CONTACT_API DeformedFieldState {
 public:
  /// update() refuses a q for which some det F_i ≤ this: a deformation gradient that inverts
  /// (det < 0) or collapses the neighbourhood of a proxy to under a thousandth of its volume.
  /// F_i⁻¹ stretches pull-backs by up to 1/σ_min(F_i); past this the local linear model
  /// (eq. 3.17) means nothing, and the pull-backs would land anywhere in the rest field.
  static constexpr double min_determinant = 1e-3;

  /// The state at q = 0 (p_i = P_i, F_i = I): the rest shape.
  explicit DeformedFieldState(const DeformedDistanceField& field);

  const DeformedDistanceField& field() const noexcept { return *m_field; }
  /// r: the size update() expects and add_reduced_force() adds to.
  Eigen::Index dimension() const noexcept { return m_field->dimension(); }

  /// field().displacement_bound(): with coordinates(), what lets temporal coherence bound how
  /// fast the deformed surface moves (BoundedDeformableDistanceField).
  double displacement_bound() const noexcept { return m_field->displacement_bound(); }
  /// h (m): the finest spacing of the domains' rest-shape grids (a CellSizedDistanceField).
  double cell_size() const noexcept;
  /// The reduced coordinates of the last successful update() (zero before the first).
  const Eigen::VectorXd& coordinates() const noexcept { return m_q; }
  /// Deforms the proxies to reduced coordinates q (r entries): ~12 N r flops and N 3×3
  /// inversions. Returns false and keeps the previous state if q does not have r entries, has
  /// a non-finite entry, or gives some proxy det F_i ≤ min_determinant (or a non-finite
  /// position or gradient).
  bool update(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept;

  /// The deformed signed distance d(x) (m, negative inside) at x (m, body frame). NaN for a
  /// non-finite x.
  double distance(const Eigen::Vector3d& x) const noexcept;
  /// d(x), and in `gradient` the exact gradient of the returned function where it is
  /// differentiable: Σ_i w_i F_i⁻ᵀ ∇d_i(X_i) + Σ_i d_i ∇w_i for the domain giving the minimum.
  /// Where it is not (x on a proxy, all k distances equal, a grid cell face, a change of the
  /// neighbour set or of the minimizing domain) it is that of one side, or without the weights'
  /// term at x on a proxy or in the equal-distance case. NaN value and gradient for a
  /// non-finite x.
  double distance_and_gradient(const Eigen::Vector3d& x, Eigen::Vector3d& gradient) const noexcept;

  /// distance(x), bit for bit, when it is at most `threshold` (m); otherwise some lower bound of
  /// it above `threshold`, often from one rest-field lookup per domain instead of k − 1: the
  /// pull-backs of nearby proxies land close together, and the rest field changes by at most
  /// field_slope() per metre along each axis. What the contact query culls with (a node whose
  /// bound exceeds its radius needs no exact value). NaN for a non-finite x.
  double culling_distance(const Eigen::Vector3d& x, double threshold) const noexcept;
  /// out[i] = culling_distance(x[i], thresholds[i]), bit for bit, for every i: faster per point,
  /// since up to eight neighbour searches run side by side in SIMD lanes and a group's rest-field
  /// memory is requested before it is read. The three spans have the same size (asserted in
  /// debug builds; otherwise the shortest is used).
  void culling_distances(std::span<const Eigen::Vector3d> x, std::span<const double> thresholds,
                         std::span<double> out) const noexcept;
  /// The same, and nearest[i] = nearest_proxy(x[i]) wherever out[i] ≤ thresholds[i] (elsewhere
  /// the nearest proxy of the domain giving the bound; −1 for a non-finite x[i]): the proxy the
  /// contact query applies a point's reaction at (add_proxy_reduced_force()), found by the
  /// neighbour search the value needed anyway. The four spans have the same size.
  void culling_distances(std::span<const Eigen::Vector3d> x, std::span<const double> thresholds,
                         std::span<double> out, std::span<Eigen::Index> nearest) const noexcept;

  /// The proxy nearest to x (a global index) in the domain giving the minimum in distance(x),
  /// as the neighbour search orders them (squared distances equal to within 2⁻⁴⁶ relative by
  /// index); with one domain, only the search runs, otherwise a full distance(x). −1 for a
  /// non-finite x.
  Eigen::Index nearest_proxy(const Eigen::Vector3d& x) const noexcept;

  /// Adds to `reduced` (r entries) the generalized force U_nᵀ f of a force f (N, body frame)
  /// acting on the object at x (m, body frame), with U_n the displacement modes of the proxy
  /// n = nearest_proxy(x): the thesis's approximation of the modes at the contact location
  /// (§3.12). Units: N·m per unit q (work per unit q). Does nothing if `reduced` does not have
  /// r entries (asserted in debug builds) or x is not finite.
  void add_reduced_force(const Eigen::Vector3d& x, const Eigen::Vector3d& force,
                         Eigen::Ref<Eigen::VectorXd> reduced) const noexcept;
  /// add_reduced_force() at a proxy found already (culling_distances() with `nearest`): adds
  /// U_nᵀ f for proxy n = `proxy`. Does nothing if `reduced` does not have r entries or `proxy`
  /// is not in [0, field().num_proxies()) (both asserted in debug builds, except proxy −1).
  void add_proxy_reduced_force(Eigen::Index proxy, const Eigen::Vector3d& force,
                               Eigen::Ref<Eigen::VectorXd> reduced) const noexcept;

  /// p_i (m) at the current q, 0 ≤ i < field().num_proxies().
  Eigen::Vector3d position(Eigen::Index i) const noexcept;
  /// F_i⁻¹ at the current q.
  Eigen::Matrix3d inverse_gradient(Eigen::Index i) const noexcept;

 private:
  /// culling_distances(), with nearest proxies into `nearest` unless it is null.
  void cull(std::span<const Eigen::Vector3d> x, std::span<const double> thresholds,
            std::span<double> out, Eigen::Index* nearest) const noexcept;

  const DeformedDistanceField* m_field;
  Eigen::Index m_count;         // N
  Eigen::VectorXd m_positions;  // 3N: x, y, z blocks
  Eigen::VectorXd m_inverse;    // 9N: entry (a, b) of F_i⁻¹ at (3a + b)·N + i
  Eigen::VectorXd m_next_positions;
  Eigen::VectorXd m_next_inverse;
  Eigen::VectorXd m_gradient;  // 9N: F_i − I of the q being tried
  Eigen::VectorXd m_q;         // r: the current q
};

static_assert(BoundedDeformableDistanceField<DeformedFieldState>);
static_assert(CullingDistanceField<DeformedFieldState>);
static_assert(BatchCullingDistanceField<DeformedFieldState>);
static_assert(ProxyReactionDistanceField<DeformedFieldState>);

}  // namespace khz::contact
