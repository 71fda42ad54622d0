#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/field/mesh_distance.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

using Box = Eigen::AlignedBox3d;

/// Exact signed distance from p to the box.
double box_distance(const Eigen::Vector3d& p, const Box& box) {
  const Eigen::Vector3d q = (box.min() - p).cwiseMax(p - box.max());
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// A random point, its coordinates drawn z first, then y, then x: in an order of the test's own.
/// Vector3d(x(random), y(random), z(random)) leaves the order to the compiler (GCC, on which the
/// bounds below were measured, evaluates the arguments last to first, clang first to last), and
/// with it the sample.
Eigen::Vector3d draw_point(std::mt19937& random, std::uniform_real_distribution<double>& x,
                           std::uniform_real_distribution<double>& y,
                           std::uniform_real_distribution<double>& z) {
  const double pz = z(random);
  const double py = y(random);
  return {x(random), py, pz};
}

/// The exact signed distance to a union of disjoint boxes, sampled on `geometry`.
DistanceGrid box_field(const GridGeometry& geometry, std::initializer_list<Box> boxes) {
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (int k = 0; k <= geometry.cells; ++k) {
    for (int j = 0; j <= geometry.cells; ++j) {
      for (int i = 0; i <= geometry.cells; ++i) {
        double value = std::numeric_limits<double>::infinity();
        for (const Box& box : boxes) {
          value = std::min(value, box_distance(geometry.node_position(i, j, k), box));
        }
        values[static_cast<std::size_t>(geometry.node_index(i, j, k))] = static_cast<float>(value);
      }
    }
  }
  return DistanceGrid(geometry, std::move(values), true);
}

/// The rest positions of a field's proxies, one matrix per domain (to rebuild it with given
/// proxies).
std::vector<PointMatrix> proxy_sets(const DeformedDistanceField& field) {
  std::vector<PointMatrix> sets;
  for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
    PointMatrix points(field.domain_end(d) - field.domain_begin(d), 3);
    for (Eigen::Index i = field.domain_begin(d); i < field.domain_end(d); ++i) {
      points.row(i - field.domain_begin(d)) = field.rest_position(i).transpose();
    }
    sets.push_back(std::move(points));
  }
  return sets;
}

/// A basis whose columns are the displacement fields X ↦ A_j (X − centre) (exact in the FEM
/// interpolation of trilinear hexahedra, with deformation-gradient modes A_j everywhere).
Eigen::MatrixXd affine_basis(const reduced::VolumeMesh& mesh, const Eigen::Vector3d& centre,
                             const std::vector<Eigen::Matrix3d>& fields) {
  Eigen::MatrixXd basis(3 * mesh.num_vertices(), static_cast<Eigen::Index>(fields.size()));
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d rest = mesh.vertices.row(v).transpose();
    for (std::size_t j = 0; j < fields.size(); ++j) {
      basis.block<3, 1>(3 * v, static_cast<Eigen::Index>(j)) = fields[j] * (rest - centre);
    }
  }
  return basis;
}

// ---------------------------------------------------------------------------------------------
// The cantilever: a 1 m × 0.2 m × 0.2 m beam of 10 × 2 × 2 hexahedra clamped at x = 0, its six
// lowest linear modes, its exact box field on a 60³ grid (h = 2.5 cm) and 40 fitted proxies.

constexpr double kLength = 1.0, kSide = 0.2;
constexpr int kCells = 60;

struct Beam {
  test::Cantilever cantilever{kLength, kSide, 2, reduced::Material::stvk(1e6, 0.3, 1000.0)};
  reduced::MeshEmbedding embedding{cantilever.model.mesh()};
  /// No face of the box on a grid plane: nodes there would hold ±rounding, whose signs (which
  /// differ with FMA contraction) decide how the isosurface cuts the edges.
  GridGeometry geometry{Eigen::Vector3d(-0.2537, -0.6411, -0.6589), 1.5 / kCells, kCells};
  Box box{Eigen::Vector3d::Zero(), Eigen::Vector3d(kLength, kSide, kSide)};
  /// Six linear modes, each scaled to a largest vertex displacement of 1 m per unit q.
  Eigen::MatrixXd basis = linear_basis();
  /// A mixed direction of the modes, scaled to a largest vertex displacement of 1 m: q =
  /// a·direction moves the beam by up to a metres (the tip).
  Eigen::VectorXd direction = mixed_direction();
  DeformedDistanceField field{{box_field(geometry, {box})}, embedding, basis};
  /// The rest field's zero level set, the surface whose deformation is the reference.
  TriangleMesh rest_surface = isosurface(field.field(0), 0.0);
  std::vector<reduced::EmbeddedPoint> surface_points = embedding.locate_all(rest_surface.vertices);

  double spacing() const { return geometry.spacing; }

  Eigen::MatrixXd linear_basis() const {
    reduced::LinearModesOptions options;
    options.num_modes = 6;
    Eigen::MatrixXd modes =
        reduced::compute_linear_modes(cantilever.model, cantilever.clamped, options).modes;
    for (Eigen::Index j = 0; j < modes.cols(); ++j)
      modes.col(j) /= largest_displacement(modes.col(j));
    return modes;
  }
  /// The square beam's modes come in degenerate pairs (bending in y and z) whose orientation
  /// within each pair follows the eigensolver's rounding, which differs between builds; so the
  /// direction is the basis's best fit to a fixed displacement — bending along y and z and a
  /// twist growing from the clamp — which does not depend on how a pair is turned.
  Eigen::VectorXd mixed_direction() const {
    const reduced::VolumeMesh& mesh = cantilever.model.mesh();
    Eigen::VectorXd target(3 * mesh.num_vertices());
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
      const double t = x.x() / kLength, twist = 0.3 * t;
      const double y = x.y() - kSide / 2, z = x.z() - kSide / 2;
      target.segment<3>(3 * v) =
          Eigen::Vector3d(0.0, 0.8 * t * t - twist * z, 0.5 * t * t + twist * y);
    }
    const Eigen::VectorXd q = basis.colPivHouseholderQr().solve(target);
    return q / largest_displacement(basis * q);
  }
  static double largest_displacement(const Eigen::VectorXd& u) {
    return u.reshaped(3, u.size() / 3).colwise().norm().maxCoeff();
  }

  /// The rest surface moved by u = U q.
  TriangleMesh deformed_surface(const Eigen::VectorXd& q) const {
    TriangleMesh mesh = rest_surface;
    const Eigen::VectorXd u = basis * q;
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      mesh.vertices.row(v) +=
          embedding.interpolate(surface_points[static_cast<std::size_t>(v)], u).transpose();
    }
    return mesh;
  }
};

const Beam& beam() {
  static const Beam instance;
  return instance;
}

/// Random points within `radius` of the vertices of `mesh`.
std::vector<Eigen::Vector3d> points_near(const TriangleMesh& mesh, double radius, int count,
                                         unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<Eigen::Index> vertex(0, mesh.num_vertices() - 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < count) {
    const Eigen::Vector3d offset(uniform(random), uniform(random), uniform(random));
    if (offset.squaredNorm() > 1.0) continue;
    points.push_back(mesh.vertices.row(vertex(random)).transpose() + radius * offset);
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// An independent reference: eq. 3.16 and 3.17 as written, from the public accessors (p_i and F_i
// from the modes, F_i⁻¹ by Eigen, the neighbours by sorting).

struct ReferenceProxies {
  std::vector<Eigen::Vector3d> position;
  std::vector<Eigen::Matrix3d> inverse;
};

/// p_i(q) and, unless only the positions are asked for, F_i(q)⁻¹.
ReferenceProxies reference_proxies(const DeformedDistanceField& field, const Eigen::VectorXd& q,
                                   bool positions_only = false) {
  ReferenceProxies proxies;
  for (Eigen::Index i = 0; i < field.num_proxies(); ++i) {
    proxies.position.push_back(field.rest_position(i) + field.displacement_modes(i) * q);
    if (positions_only) continue;
    Eigen::Matrix3d gradient = Eigen::Matrix3d::Identity();
    for (Eigen::Index j = 0; j < q.size(); ++j) gradient += q[j] * field.gradient_mode(i, j);
    proxies.inverse.push_back(gradient.inverse());
  }
  return proxies;
}

/// The beam's state at q = amplitude · direction and the reference's proxies there.
struct PosedBeam {
  explicit PosedBeam(double amplitude)
      : q(amplitude * beam().direction), proxies(reference_proxies(beam().field, q)) {}
  DeformedFieldState state{beam().field};
  Eigen::VectorXd q;
  ReferenceProxies proxies;
  bool updated = state.update(q);
};

/// The k nearest proxies of domain d, nearest first (ties: lower index).
std::vector<Eigen::Index> reference_neighbours(const DeformedDistanceField& field,
                                               const ReferenceProxies& proxies, Eigen::Index d,
                                               const Eigen::Vector3d& x) {
  std::vector<std::pair<double, Eigen::Index>> order;
  for (Eigen::Index i = field.domain_begin(d); i < field.domain_end(d); ++i) {
    order.emplace_back((x - proxies.position[static_cast<std::size_t>(i)]).squaredNorm(), i);
  }
  std::sort(order.begin(), order.end());
  std::vector<Eigen::Index> nearest;
  for (int m = 0; m < field.neighbours(); ++m) {
    nearest.push_back(order[static_cast<std::size_t>(m)].second);
  }
  return nearest;
}

Eigen::Vector3d pull_back(const DeformedDistanceField& field, const ReferenceProxies& proxies,
                          Eigen::Index i, const Eigen::Vector3d& x) {
  const auto s = static_cast<std::size_t>(i);
  return field.rest_position(i) + proxies.inverse[s] * (x - proxies.position[s]);
}

enum class Weights {
  thesis,   ///< eq. 3.16
  shepard,  ///< w'_i = 1/d_i: no weight vanishes at the k-th neighbour
};

double reference_distance(const DeformedDistanceField& field, const ReferenceProxies& proxies,
                          const Eigen::Vector3d& x, Weights weights = Weights::thesis) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
    const std::vector<Eigen::Index> nearest = reference_neighbours(field, proxies, d, x);
    const auto distance = [&](Eigen::Index i) {
      return (x - proxies.position[static_cast<std::size_t>(i)]).norm();
    };
    const double d_min = distance(nearest.front()), d_max = distance(nearest.back());
    double sum = 0.0, value = 0.0;
    for (const Eigen::Index i : nearest) {
      const double w = weights == Weights::thesis
                           ? (1.0 / distance(i) - 1.0 / d_max) / (1.0 / d_min - 1.0 / d_max)
                           : 1.0 / distance(i);
      sum += w;
      value += w * field.field(d).distance(pull_back(field, proxies, i, x));
    }
    best = std::min(best, value / sum);
  }
  return best;
}

/// What a query's differentiability depends on: the ordered neighbours of each domain and the
/// grid cells their pull-backs fall in.
std::vector<Eigen::Index> query_signature(const DeformedDistanceField& field,
                                          const ReferenceProxies& proxies,
                                          const Eigen::Vector3d& x) {
  std::vector<Eigen::Index> signature;
  for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
    const GridGeometry& grid = field.field(d).geometry();
    for (const Eigen::Index i : reference_neighbours(field, proxies, d, x)) {
      signature.push_back(i);
      const Eigen::Vector3d cell =
          ((pull_back(field, proxies, i, x) - grid.origin) / grid.spacing).array().floor();
      for (int a = 0; a < 3; ++a) signature.push_back(static_cast<Eigen::Index>(cell[a]));
    }
  }
  return signature;
}

/// Whether the neighbour sets of x and y differ in some domain.
bool neighbours_differ(const DeformedDistanceField& field, const ReferenceProxies& proxies,
                       const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
    if (reference_neighbours(field, proxies, d, x) != reference_neighbours(field, proxies, d, y)) {
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------------------------

TEST(DeformedDistanceField, FitsTheProxiesOnTheZeroLevelSetWithTheEmbeddingsModes) {
  const Beam& s = beam();
  const DeformedDistanceField& field = s.field;
  ASSERT_EQ(field.num_domains(), 1);
  ASSERT_EQ(field.num_proxies(), 40);
  EXPECT_EQ(field.dimension(), 6);
  EXPECT_EQ(field.neighbours(), 5);
  for (Eigen::Index i = 0; i < field.num_proxies(); ++i) {
    const Eigen::Vector3d rest = field.rest_position(i);
    // On the level set to the repulsion's projection tolerance (1e-4 h).
    EXPECT_LT(std::abs(field.field(0).distance(rest)), 1e-4 * s.spacing()) << i;
    const reduced::PointModes modes = s.embedding.modes(s.embedding.locate(rest), s.basis);
    EXPECT_EQ(field.displacement_modes(i), modes.displacement) << i;
    for (Eigen::Index j = 0; j < field.dimension(); ++j) {
      EXPECT_EQ(field.gradient_mode(i, j), modes.gradient[static_cast<std::size_t>(j)]) << i;
    }
  }
  // Spread over the beam: every tenth of its length has proxies.
  std::vector<int> per_slice(10, 0);
  for (Eigen::Index i = 0; i < field.num_proxies(); ++i) {
    ++per_slice[static_cast<std::size_t>(
        std::clamp(static_cast<int>(field.rest_position(i).x() * 10.0), 0, 9))];
  }
  for (int slice = 0; slice < 10; ++slice) EXPECT_GT(per_slice[static_cast<std::size_t>(slice)], 0);
}

TEST(DeformedDistanceField, AtRestEqualsTheRestField) {
  const Beam& s = beam();
  const DeformedFieldState state(s.field);
  for (const Eigen::Vector3d& x : points_near(s.rest_surface, 3 * s.spacing(), 500, 1)) {
    Eigen::Vector3d gradient, expected_gradient;
    const double expected = s.field.field(0).distance_and_gradient(x, expected_gradient);
    // X_i = P_i + (x − P_i) = x up to one rounding: measured below 1e-16.
    EXPECT_NEAR(state.distance(x), expected, 1e-14);
    EXPECT_NEAR(state.distance_and_gradient(x, gradient), expected, 1e-14);
    // All d_i equal, so the weights' term vanishes (to rounding over the weights' 1/δ³).
    EXPECT_LT((gradient - expected_gradient).norm(), 1e-9) << x.transpose();
  }
}

TEST(DeformedDistanceField, TranslationsAndAffineDeformationsAreExact) {
  const Beam& s = beam();
  const reduced::VolumeMesh& mesh = s.cantilever.model.mesh();
  const Eigen::Vector3d centre(0.5, 0.1, 0.1);
  Eigen::Matrix3d rotation, stretch, shear;
  rotation << 0, -1, 0, 1, 0, 0, 0, 0, 0;  // the generator of rotations about z
  stretch = Eigen::Vector3d(0.5, -0.2, 0.1).asDiagonal();
  shear << 0, 0.3, 0, 0, 0, 0, 0.2, 0, 0;
  // Uniform translations along x, y, z.
  Eigen::MatrixXd translation_basis = Eigen::MatrixXd::Zero(3 * mesh.num_vertices(), 3);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    translation_basis.block<3, 3>(3 * v, 0).setIdentity();
  }
  const std::vector<PointMatrix> proxies = proxy_sets(s.field);
  const DeformedDistanceField moved({s.field.field(0)}, proxies, s.embedding, translation_basis);
  const DeformedDistanceField deformed({s.field.field(0)}, proxies, s.embedding,
                                       affine_basis(mesh, centre, {rotation, stretch, shear}));
  DeformedFieldState moved_state(moved), deformed_state(deformed);
  const Eigen::Vector3d t(0.1, -0.3, 0.25);
  ASSERT_TRUE(moved_state.update(t));
  const Eigen::Vector3d q(0.4, 0.3, -0.5);
  ASSERT_TRUE(deformed_state.update(q));
  const Eigen::Matrix3d F =
      Eigen::Matrix3d::Identity() + q[0] * rotation + q[1] * stretch + q[2] * shear;
  const Eigen::Matrix3d F_inverse = F.inverse();
  int points = 0;
  for (const Eigen::Vector3d& rest : points_near(s.rest_surface, 3 * s.spacing(), 300, 2)) {
    Eigen::Vector3d gradient, expected_gradient;
    // Translation: d(x) = d_rest(x − t), every pull-back the same point.
    Eigen::Vector3d x = rest + t;
    double expected = s.field.field(0).distance_and_gradient(x - t, expected_gradient);
    EXPECT_NEAR(moved_state.distance_and_gradient(x, gradient), expected, 1e-13);
    EXPECT_LT((gradient - expected_gradient).norm(), 1e-8);
    // Affine: x = c + F (X − c), so X = c + F⁻¹(x − c) from every proxy; ∇d = F⁻ᵀ ∇d_rest.
    x = centre + F * (rest - centre);
    expected = s.field.field(0).distance_and_gradient(centre + F_inverse * (x - centre),
                                                      expected_gradient);
    // Modes from FEM shape-function gradients: rounding of ~1e-15 per entry.
    EXPECT_NEAR(deformed_state.distance_and_gradient(x, gradient), expected, 1e-12);
    EXPECT_LT((gradient - F_inverse.transpose() * expected_gradient).norm(), 1e-7);
    ++points;
  }
  EXPECT_EQ(points, 300);
}

TEST(DeformedDistanceField, MatchesEquations316And317AsWritten) {
  const Beam& s = beam();
  DeformedFieldState state(s.field);
  for (const double amplitude : {0.0, 0.1, 0.3}) {
    const Eigen::VectorXd q = amplitude * s.direction;
    ASSERT_TRUE(state.update(q));
    const ReferenceProxies proxies = reference_proxies(s.field, q);
    for (Eigen::Index i = 0; i < s.field.num_proxies(); ++i) {
      const auto u = static_cast<std::size_t>(i);
      EXPECT_LT((state.position(i) - proxies.position[u]).norm(), 1e-14);
      EXPECT_LT((state.inverse_gradient(i) - proxies.inverse[u]).norm(), 1e-13);
    }
    const TriangleMesh surface = s.deformed_surface(q);
    for (const Eigen::Vector3d& x : points_near(surface, 4 * s.spacing(), 300, 3)) {
      // The two weight formulas round differently: measured up to 3e-17.
      EXPECT_NEAR(state.distance(x), reference_distance(s.field, proxies, x), 1e-14)
          << "amplitude " << amplitude << " at " << x.transpose();
    }
  }
}

TEST(DeformedDistanceField, DomainsOfManyProxiesTakeTheGeneralSearchAndMatchTheReference) {
  // Past 64 proxies a domain's neighbours are found by insertion rather than by packed keys.
  const Beam& s = beam();
  DeformedFieldOptions options;
  options.proxies = 100;
  const DeformedDistanceField field({s.field.field(0)}, s.embedding, s.basis, options);
  ASSERT_EQ(field.num_proxies(), 100);
  DeformedFieldState state(field);
  const Eigen::VectorXd q = 0.3 * s.direction;
  ASSERT_TRUE(state.update(q));
  const ReferenceProxies proxies = reference_proxies(field, q);
  for (const Eigen::Vector3d& x : points_near(s.deformed_surface(q), 4 * s.spacing(), 200, 5)) {
    EXPECT_NEAR(state.distance(x), reference_distance(field, proxies, x), 1e-14);
  }
}

TEST(DeformedDistanceField, CullingDistanceIsExactUpToTheThresholdAndABoundAboveIt) {
  const Beam& s = beam();
  DeformedFieldState state(s.field);
  int bounded = 0, exact = 0;
  for (const double amplitude : {0.0, 0.1, 0.3}) {
    const Eigen::VectorXd q = amplitude * s.direction;
    ASSERT_TRUE(state.update(q));
    const TriangleMesh surface = s.deformed_surface(q);
    for (const Eigen::Vector3d& x : points_near(surface, 6 * s.spacing(), 300, 4)) {
      const double d = state.distance(x);
      for (const double threshold : {-2.0, 0.0, 1.0, 3.0}) {
        const double t = threshold * s.spacing();
        const double culled = state.culling_distance(x, t);
        if (d <= t) {
          EXPECT_EQ(culled, d) << "at " << x.transpose() << ", threshold " << t;
          ++exact;
        } else {
          EXPECT_GT(culled, t) << "at " << x.transpose();
          EXPECT_LE(culled, d) << "at " << x.transpose();
          bounded += culled < d;
        }
      }
    }
  }
  // Both branches ran, and the one-lookup bound answered a good share of the culls.
  EXPECT_GT(exact, 500);
  EXPECT_GT(bounded, 500);
  EXPECT_TRUE(std::isnan(state.culling_distance(
      Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), 0.0)));
}

TEST(DeformedDistanceField, GradientMatchesCentralDifferences) {
  const Beam& s = beam();
  const PosedBeam posed(0.2);
  const auto& [state, q, proxies, updated] = posed;
  ASSERT_TRUE(updated);
  constexpr double h = 1e-7;
  int checked = 0, skipped = 0;
  const std::vector<Eigen::Vector3d> points =
      points_near(s.deformed_surface(q), 4 * s.spacing(), 300, 4);
  for (const Eigen::Vector3d& x : points) {
    Eigen::Vector3d gradient;
    const double value = state.distance_and_gradient(x, gradient);
    EXPECT_EQ(value, state.distance(x));  // the same function, bit for bit
    const std::vector<Eigen::Index> signature = query_signature(s.field, proxies, x);
    Eigen::Vector3d central;
    bool smooth = true;
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(a);
      smooth = smooth && query_signature(s.field, proxies, x + step) == signature &&
               query_signature(s.field, proxies, x - step) == signature;
      central[a] = (state.distance(x + step) - state.distance(x - step)) / (2 * h);
    }
    if (!smooth) {
      ++skipped;
      continue;
    }
    ++checked;
    // Truncation (h² times third derivatives of ~1/δ³, δ ≥ ~1 cm) and rounding (1e-17/h) stay
    // near 1e-8; the weights' term alone is ~0.1–1 here, so leaving it out would fail.
    EXPECT_LT((gradient - central).norm(), 1e-6 * std::max(1.0, gradient.norm()))
        << x.transpose() << ": " << gradient.transpose() << " vs " << central.transpose();
  }
  std::printf("gradient: %d points checked, %d skipped (neighbours or grid cells change)\n",
              checked, skipped);
  EXPECT_GE(checked, 280);
}

TEST(DeformedDistanceField, WeightsTermIsPartOfTheGradient) {
  // Where the proxies' estimates d_i disagree, Σ d_i ∇w_i is a large part of the gradient: the
  // check above would fail without it.
  const Beam& s = beam();
  const PosedBeam posed(0.2);
  const auto& [state, q, proxies, updated] = posed;
  ASSERT_TRUE(updated);
  double largest = 0.0;
  for (const Eigen::Vector3d& x : points_near(s.deformed_surface(q), 4 * s.spacing(), 100, 5)) {
    Eigen::Vector3d gradient;
    state.distance_and_gradient(x, gradient);
    // Σ w_i F_i⁻ᵀ ∇d_i alone, from the reference.
    const std::vector<Eigen::Index> nearest = reference_neighbours(s.field, proxies, 0, x);
    const double d_max = (x - proxies.position[static_cast<std::size_t>(nearest.back())]).norm();
    double sum = 0.0;
    Eigen::Vector3d field_term = Eigen::Vector3d::Zero();
    for (const Eigen::Index i : nearest) {
      const double w =
          1.0 / (x - proxies.position[static_cast<std::size_t>(i)]).norm() - 1.0 / d_max;
      Eigen::Vector3d g;
      s.field.field(0).distance_and_gradient(pull_back(s.field, proxies, i, x), g);
      field_term += w * proxies.inverse[static_cast<std::size_t>(i)].transpose() * g;
      sum += w;
    }
    largest = std::max(largest, (gradient - field_term / sum).norm());
  }
  EXPECT_GT(largest, 1e-3);
}

/// Finds, by bisection of [a, b] (parameters of `point`), an interval of width (b − a)·2⁻⁴⁰
/// across which the neighbour set changes, and returns the change of `value` across it.
template <typename Value, typename Changed>
double jump_at_switch(double a, double b, const Value& value, const Changed& changed) {
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double middle = 0.5 * (a + b);
    if (changed(a, middle)) {
      b = middle;
    } else {
      a = middle;
    }
  }
  return std::abs(value(b) - value(a));
}

TEST(DeformedDistanceField, ContinuousAcrossNeighbourChangesAlongAPathInX) {
  const Beam& s = beam();
  const PosedBeam posed(0.2);
  ASSERT_TRUE(posed.updated);
  // Named references, not a structured binding: clang 14 cannot capture one in a lambda.
  const DeformedFieldState& state = posed.state;
  const ReferenceProxies& proxies = posed.proxies;
  // Past the clamped end, along and through the bent beam, past the tip.
  const Eigen::Vector3d start(-0.1, 0.3, 0.1), end(1.1, 0.0, 0.2);
  const auto point = [&](double t) -> Eigen::Vector3d { return start + t * (end - start); };
  const auto value = [&](double t) { return state.distance(point(t)); };
  const auto changed = [&](double a, double b) {
    return neighbours_differ(s.field, proxies, point(a), point(b));
  };
  const auto shepard_value = [&](double t) {
    return reference_distance(s.field, proxies, point(t), Weights::shepard);
  };
  constexpr int steps = 2000;
  int switches = 0;
  double largest_jump = 0.0, largest_shepard_jump = 0.0;
  for (int n = 0; n < steps; ++n) {
    const double a = static_cast<double>(n) / steps, b = static_cast<double>(n + 1) / steps;
    if (!changed(a, b)) continue;
    ++switches;
    largest_jump = std::max(largest_jump, jump_at_switch(a, b, value, changed));
    largest_shepard_jump =
        std::max(largest_shepard_jump, jump_at_switch(a, b, shepard_value, changed));
  }
  std::printf("path in x: %d neighbour changes, largest jump %.2e m (Shepard weights: %.2e m)\n",
              switches, largest_jump, largest_shepard_jump);
  EXPECT_GE(switches, 10);
  // An interval of 1.2 m·2⁻⁴⁰·2⁻¹¹ ≈ 5e-16 m: a continuous function changes by rounding only.
  EXPECT_LT(largest_jump, 1e-12);
  // Weights that do not vanish at the k-th neighbour jump there by millimetres.
  EXPECT_GT(largest_shepard_jump, 1e-5);
}

TEST(DeformedDistanceField, ContinuousAcrossNeighbourChangesAlongAPathInQ) {
  const Beam& s = beam();
  DeformedFieldState state(s.field);
  const auto coordinates = [&](double t) -> Eigen::VectorXd { return 0.4 * t * s.direction; };
  int switches = 0;
  double largest_jump = 0.0;
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.9, 0.25, 0.1), Eigen::Vector3d(0.5, 0.1, 0.26),
                                   Eigen::Vector3d(0.7, 0.0, -0.05)}) {
    const auto value = [&](double t) {
      EXPECT_TRUE(state.update(coordinates(t)));
      return state.distance(x);
    };
    const auto changed = [&](double a, double b) {
      return reference_neighbours(s.field, reference_proxies(s.field, coordinates(a), true), 0,
                                  x) !=
             reference_neighbours(s.field, reference_proxies(s.field, coordinates(b), true), 0, x);
    };
    constexpr int steps = 100;
    for (int n = 0; n < steps; ++n) {
      const double a = static_cast<double>(n) / steps, b = static_cast<double>(n + 1) / steps;
      if (!changed(a, b)) continue;
      ++switches;
      largest_jump = std::max(largest_jump, jump_at_switch(a, b, value, changed));
    }
  }
  std::printf("paths in q: %d neighbour changes, largest jump %.2e m\n", switches, largest_jump);
  EXPECT_GE(switches, 3);
  EXPECT_LT(largest_jump, 1e-12);
}

/// 40 proxies on the beam's faces in a fixed pattern: four per 10 cm of length, one at the centre
/// of each side face. Fitted proxies land where the repulsion's rounding takes them, which
/// differs between builds (FMA contraction); the error against the exact surface depends on
/// where the proxies are, so the error table uses these.
std::vector<PointMatrix> regular_beam_proxies() {
  PointMatrix points(40, 3);
  for (int i = 0; i < 10; ++i) {
    const double x = (i + 0.5) * kLength / 10.0, c = kSide / 2.0;
    points.row(4 * i) = Eigen::RowVector3d(x, 0.0, c);
    points.row(4 * i + 1) = Eigen::RowVector3d(x, kSide, c);
    points.row(4 * i + 2) = Eigen::RowVector3d(x, c, 0.0);
    points.row(4 * i + 3) = Eigen::RowVector3d(x, c, kSide);
  }
  return {points};
}

TEST(DeformedDistanceField, ErrorAgainstTheExactDeformedSurface) {
  const Beam& s = beam();
  const DeformedDistanceField field({s.field.field(0)}, regular_beam_proxies(), s.embedding,
                                    s.basis);
  DeformedFieldState state(field);
  const double h = s.spacing();
  std::printf("amplitude (m)  mean |error| (h)  max |error| (h)  sign disagreement  (|d| > h/4)\n");
  struct Row {
    double amplitude, mean, max, sign_far;
  };
  std::vector<Row> rows;
  for (const double amplitude : {0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5}) {
    const Eigen::VectorXd q = amplitude * s.direction;
    ASSERT_TRUE(state.update(q));
    const TriangleMesh surface = s.deformed_surface(q);
    const MeshDistance exact(surface);
    double sum = 0.0, largest = 0.0;
    int disagree = 0, disagree_far = 0, far = 0, count = 0;
    for (const Eigen::Vector3d& x : points_near(surface, 3 * h, 1000, 6)) {
      const double reference = exact.closest(x).signed_distance(x);
      const double value = state.distance(x);
      const double error = std::abs(value - reference) / h;
      sum += error;
      largest = std::max(largest, error);
      const bool differ = (value < 0.0) != (reference < 0.0);
      disagree += differ ? 1 : 0;
      if (std::abs(reference) > 0.25 * h) {
        ++far;
        disagree_far += differ ? 1 : 0;
      }
      ++count;
    }
    const Row row{amplitude, sum / count, largest, static_cast<double>(disagree_far) / far};
    std::printf("%13.2f  %16.4f  %15.4f  %17.4f  %11.4f\n", amplitude, row.mean, row.max,
                static_cast<double>(disagree) / count, row.sign_far);
    rows.push_back(row);
  }
  // Bounds measured on this beam, with ~20% headroom. The approximation linearizes the
  // deformation at each proxy (eq. 3.17): exact for rigid and affine motions, it degrades as
  // the deformation gradient varies between the proxies and x (bending) and under the stretch
  // that linear modes add at large amplitudes (thesis §3.12: "progressively less accurate under
  // stretching/compression"). Amplitude 0 measures the grid itself against its own isosurface:
  // trilinear interpolation of the box's distance is exact on the faces but not at the edges
  // and corners, where marching tetrahedra also cut the isosurface's edges within a cell; this
  // part (0.03 h mean, 0.46 h max) is in every row. Sign disagreements happen only within h/4
  // of the surface.
  ASSERT_EQ(rows.size(), 7U);
  for (const Row& row : rows) {
    SCOPED_TRACE("amplitude " + std::to_string(row.amplitude));
    if (row.amplitude <= 0.1) {  // small: measured ≤ 0.034 h mean, 0.46 h max
      EXPECT_LT(row.mean, 0.042);
      EXPECT_LT(row.max, 0.55);
      EXPECT_EQ(row.sign_far, 0.0);
    } else if (row.amplitude <= 0.3) {  // moderate: measured ≤ 0.060 h mean, 0.49 h max
      EXPECT_LT(row.mean, 0.075);
      EXPECT_LT(row.max, 0.6);
      EXPECT_EQ(row.sign_far, 0.0);
    } else {  // large (the tip moved half the length): measured 0.101 h mean, 0.71 h max
      EXPECT_LT(row.mean, 0.125);
      EXPECT_LT(row.max, 0.85);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Two legs, 0.4 m × 0.4 m × 1 m boxes at x ∈ [−0.6, −0.2] and [0.2, 0.6], moved apart by the
// one basis column (left leg −x, right leg +x): the case of thesis Fig. 3.24. `split` has a
// domain per leg, `joined` one field of both.

const Box kLeft(Eigen::Vector3d(-0.6, 0.0, 0.0), Eigen::Vector3d(-0.2, 0.4, 1.0));
const Box kRight(Eigen::Vector3d(0.2, 0.0, 0.0), Eigen::Vector3d(0.6, 0.4, 1.0));

reduced::VolumeMesh two_legs() {
  const reduced::VolumeMesh left = reduced::box_hex_mesh(kLeft.min(), kLeft.max(), {2, 2, 5});
  const reduced::VolumeMesh right = reduced::box_hex_mesh(kRight.min(), kRight.max(), {2, 2, 5});
  reduced::VolumeMesh mesh;
  mesh.element_type = left.element_type;
  mesh.vertices.resize(left.num_vertices() + right.num_vertices(), 3);
  mesh.vertices << left.vertices, right.vertices;
  mesh.elements.resize(left.num_elements() + right.num_elements(), left.elements.cols());
  mesh.elements << left.elements,
      (right.elements.array() + static_cast<int>(left.num_vertices())).matrix();
  return mesh;
}

struct Legs {
  reduced::VolumeMesh mesh = two_legs();
  reduced::MeshEmbedding embedding{mesh};
  Eigen::MatrixXd basis = apart();
  GridGeometry geometry{Eigen::Vector3d(-1.5137, -1.3211, -1.0289), 3.0 / 40, 40};  // as Beam
  std::vector<std::string> stages;
  DeformedDistanceField split{
      {box_field(geometry, {kLeft}), box_field(geometry, {kRight})}, embedding, basis, recorded()};
  DeformedDistanceField joined{{box_field(geometry, {kLeft, kRight})}, embedding, basis};

  Eigen::MatrixXd apart() const {
    Eigen::MatrixXd u = Eigen::MatrixXd::Zero(3 * mesh.num_vertices(), 1);
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      u(3 * v) = mesh.vertices(v, 0) < 0.0 ? -1.0 : 1.0;
    }
    return u;
  }
  DeformedFieldOptions recorded() {
    DeformedFieldOptions options;
    options.progress = [this](const Progress& progress) {
      if (progress.done == progress.total) stages.emplace_back(progress.stage);
      return true;
    };
    return options;
  }
};

const Legs& legs() {
  static const Legs instance;
  return instance;
}

/// culling_distances() against culling_distance() at `x` (one of them made NaN) with
/// thresholds of both signs; with proxies, the same values and nearest_proxy() wherever the
/// value is at most the threshold.
void expect_batch_equals_single(const DeformedFieldState& state, std::vector<Eigen::Vector3d> x,
                                double spacing) {
  x[13].y() = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> thresholds, batched(x.size()), with_proxies(x.size());
  std::vector<Eigen::Index> proxies(x.size(), -7);
  for (std::size_t i = 0; i < x.size(); ++i) {
    thresholds.push_back((static_cast<double>(i % 5) - 2.0) * spacing);
  }
  state.culling_distances(x, thresholds, batched);
  state.culling_distances(x, thresholds, with_proxies, proxies);
  int exact = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i == 13) {
      EXPECT_TRUE(std::isnan(batched[i]));
      EXPECT_TRUE(std::isnan(with_proxies[i]));
      EXPECT_EQ(proxies[i], -1);
      continue;
    }
    EXPECT_EQ(batched[i], state.culling_distance(x[i], thresholds[i])) << "point " << i;
    EXPECT_EQ(with_proxies[i], batched[i]) << "point " << i;
    if (batched[i] <= thresholds[i]) {
      EXPECT_EQ(proxies[i], state.nearest_proxy(x[i])) << "point " << i;
      ++exact;
    }
  }
  EXPECT_GE(exact, 4);  // the proxies were checked somewhere
}

TEST(DeformedDistanceField, BatchedCullingEqualsOneAtATimeBitForBit) {
  // 21 points (not a multiple of the 8 lanes): one domain of 40 proxies (the packed search), one
  // of 100 (the general search), and two domains.
  const Beam& s = beam();
  DeformedFieldOptions many;
  many.proxies = 100;
  const DeformedDistanceField large({s.field.field(0)}, s.embedding, s.basis, many);
  const Eigen::VectorXd q = 0.3 * s.direction;
  const std::vector<Eigen::Vector3d> near_beam =
      points_near(s.deformed_surface(q), 4 * s.spacing(), 21, 6);
  for (const DeformedDistanceField* field : {&s.field, &large}) {
    SCOPED_TRACE(std::to_string(field->num_proxies()) + " proxies");
    DeformedFieldState state(*field);
    ASSERT_TRUE(state.update(q));
    expect_batch_equals_single(state, near_beam, s.spacing());
  }
  const Legs& l = legs();
  DeformedFieldState apart(l.split);
  ASSERT_TRUE(apart.update(Eigen::VectorXd::Constant(1, 0.2)));
  std::vector<Eigen::Vector3d> near_legs;
  for (int i = 0; i < 21; ++i) {
    near_legs.emplace_back(-0.9 + 0.09 * i, 0.2 + 0.01 * i, 0.5);
  }
  SCOPED_TRACE("two domains");
  expect_batch_equals_single(apart, near_legs, l.geometry.spacing);
}

TEST(DeformedDistanceField, ReportsProgressPerDomain) {
  const Legs& s = legs();
  const auto count = [&](const std::string& stage) {
    return std::count(s.stages.begin(), s.stages.end(), stage);
  };
  EXPECT_EQ(count("particle repulsion level 0"), 2);
  EXPECT_EQ(count("proxy modes"), 1);
  EXPECT_EQ(s.stages.back(), "proxy modes");
  ASSERT_EQ(s.split.num_domains(), 2);
  EXPECT_EQ(s.split.domain_end(0), 40);
  EXPECT_EQ(s.split.domain_end(1), 80);
  // Each domain's proxies lie on its own leg.
  for (Eigen::Index i = 0; i < 80; ++i) {
    EXPECT_EQ(s.split.rest_position(i).x() < 0.0, i < 40) << i;
  }
  DeformedFieldOptions cancelling;
  cancelling.progress = [](const Progress& progress) { return progress.stage != "proxy modes"; };
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { DeformedDistanceField({s.split.field(0)}, s.embedding, s.basis, cancelling); },
      "proxy modes"));
}

TEST(DeformedDistanceField, SeveralDomainsGiveTheMinimum) {
  const Legs& s = legs();
  const std::vector<PointMatrix> proxies = proxy_sets(s.split);
  const DeformedDistanceField left({s.split.field(0)}, {proxies[0]}, s.embedding, s.basis);
  const DeformedDistanceField right({s.split.field(1)}, {proxies[1]}, s.embedding, s.basis);
  DeformedFieldState split(s.split), left_state(left), right_state(right);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.35);
  ASSERT_TRUE(split.update(q) && left_state.update(q) && right_state.update(q));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(-1.3, 1.3), y(-0.3, 0.7), z(-0.3, 1.3);
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d p = draw_point(random, x, y, z);
    Eigen::Vector3d gradient, left_gradient, right_gradient;
    const double a = left_state.distance_and_gradient(p, left_gradient);
    const double b = right_state.distance_and_gradient(p, right_gradient);
    EXPECT_EQ(split.distance_and_gradient(p, gradient), std::min(a, b));
    EXPECT_EQ(gradient, b < a ? right_gradient : left_gradient);
    EXPECT_EQ(split.nearest_proxy(p),
              b < a ? right_state.nearest_proxy(p) + 40 : left_state.nearest_proxy(p));
  }
}

TEST(DeformedDistanceField, SeveralDomainsRemoveTheMirrorArtefact) {
  const Legs& s = legs();
  DeformedFieldState split(s.split), joined(s.joined);
  constexpr double apart = 0.6;  // left leg to [−1.2, −0.8], right leg to [0.8, 1.2]
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, apart);
  ASSERT_TRUE(split.update(q) && joined.update(q));
  const Eigen::Vector3d shift = apart * Eigen::Vector3d::UnitX();
  const auto exact = [&](const Eigen::Vector3d& x) {
    return std::min(box_distance(x + shift, kLeft), box_distance(x - shift, kRight));
  };
  // Where the right leg was, 0.6 m from either leg: the right leg's proxies pull it back into
  // the rest shape of the left leg (Fig. 3.24, middle): a phantom contact with one field.
  const Eigen::Vector3d gap(0.2, 0.2, 0.5);
  EXPECT_LT(joined.distance(gap), -0.1);
  EXPECT_NEAR(split.distance(gap), exact(gap), 1e-6);
  // Both legs move rigidly, so every domain's pull-back is exact: the split field is each rest
  // field shifted back, to rounding, while the joined one mirrors by up to the legs' gap.
  std::mt19937 random(8);
  std::uniform_real_distribution<double> x(-1.4, 1.4), y(-0.3, 0.7), z(-0.3, 1.3);
  double split_error = 0.0, joined_error = 0.0;
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Vector3d p = draw_point(random, x, y, z);
    const double shifted =
        std::min(s.split.field(0).distance(p + shift), s.split.field(1).distance(p - shift));
    EXPECT_NEAR(split.distance(p), shifted, 1e-12) << p.transpose();
    split_error = std::max(split_error, std::abs(split.distance(p) - exact(p)));
    joined_error = std::max(joined_error, std::abs(joined.distance(p) - exact(p)));
  }
  std::printf("two legs moved apart: largest error %.4f h with a domain per leg, %.4f h with one\n",
              split_error / s.geometry.spacing, joined_error / s.geometry.spacing);
  // What remains is the grid's own: trilinear interpolation of the box's distance near its
  // edges and corners, where it is not linear (measured 0.27 h).
  EXPECT_LT(split_error, 0.4 * s.geometry.spacing);
  EXPECT_GT(joined_error, 0.5);
}

// ---------------------------------------------------------------------------------------------

TEST(DeformedDistanceField, AddsTheNearestProxysModesTransposedTimesTheForce) {
  const Beam& s = beam();
  const PosedBeam posed(0.2);
  const auto& [state, q, proxies, updated] = posed;
  ASSERT_TRUE(updated);
  std::mt19937 random(9);
  std::normal_distribution<double> gauss;
  for (const Eigen::Vector3d& x : points_near(s.deformed_surface(q), 2 * s.spacing(), 100, 10)) {
    const Eigen::Vector3d force(gauss(random), gauss(random), gauss(random));
    Eigen::Index nearest = 0;
    for (Eigen::Index i = 1; i < s.field.num_proxies(); ++i) {
      if ((x - proxies.position[static_cast<std::size_t>(i)]).norm() <
          (x - proxies.position[static_cast<std::size_t>(nearest)]).norm()) {
        nearest = i;
      }
    }
    EXPECT_EQ(state.nearest_proxy(x), nearest);
    const Eigen::VectorXd start = Eigen::VectorXd::LinSpaced(6, -1.0, 1.0);
    Eigen::VectorXd reduced = start;
    state.add_reduced_force(x, force, reduced);
    Eigen::VectorXd at_proxy = start;
    state.add_proxy_reduced_force(nearest, force, at_proxy);
    EXPECT_EQ(at_proxy, reduced);
    const reduced::PointModes modes =
        s.embedding.modes(s.embedding.locate(s.field.rest_position(nearest)), s.basis);
    const Eigen::VectorXd expected = start + modes.displacement.transpose() * force;
    EXPECT_LT((reduced - expected).norm(), 1e-14 * (1.0 + expected.norm()));
  }
  // Non-finite x: no proxy, nothing added.
  Eigen::VectorXd reduced = Eigen::VectorXd::Zero(6);
  const Eigen::Vector3d nowhere(std::nan(""), 0.0, 0.0);
  state.add_reduced_force(nowhere, Eigen::Vector3d::Ones(), reduced);
  state.add_proxy_reduced_force(-1, Eigen::Vector3d::Ones(), reduced);
  EXPECT_EQ(reduced, Eigen::VectorXd::Zero(6));
  EXPECT_EQ(state.nearest_proxy(nowhere), -1);
  EXPECT_TRUE(std::isnan(state.distance(nowhere)));
}

TEST(DeformedDistanceField, UpdateRefusesBadCoordinatesAndKeepsTheState) {
  const Beam& s = beam();
  // One column F = I − q I: det F = (1 − q)³.
  const DeformedDistanceField collapsing(
      {s.field.field(0)}, proxy_sets(s.field), s.embedding,
      affine_basis(s.cantilever.model.mesh(), Eigen::Vector3d(0.5, 0.1, 0.1),
                   {-Eigen::Matrix3d::Identity()}));
  DeformedFieldState state(collapsing);
  ASSERT_TRUE(state.update(Eigen::VectorXd::Constant(1, 0.5)));
  const Eigen::Vector3d x(0.3, 0.12, 0.08);
  const double before = state.distance(x);
  const Eigen::Vector3d position = state.position(3);
  const Eigen::Matrix3d inverse = state.inverse_gradient(3);
  EXPECT_NEAR(inverse(0, 0), 2.0, 1e-12);
  const auto refused = [&](const Eigen::VectorXd& q) {
    const bool accepted = state.update(q);
    return !accepted && state.distance(x) == before && state.position(3) == position &&
           state.inverse_gradient(3) == inverse && state.coordinates()[0] == 0.5;
  };
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(2, 0.1)));  // wrong size
  EXPECT_TRUE(refused(Eigen::VectorXd()));
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, std::nan(""))));
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, 1.0)));         // F = 0
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, 1.5)));         // inverted
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, 0.905)));       // det 8.6e-4 < 1e-3
  EXPECT_TRUE(refused(Eigen::VectorXd::Constant(1, 1e200)));       // det overflows
  EXPECT_TRUE(state.update(Eigen::VectorXd::Constant(1, 0.895)));  // det 1.16e-3
  EXPECT_NE(state.distance(x), before);
}

TEST(DeformedDistanceField, DisplacementBoundCoversEverySurfacePoint) {
  // Temporal coherence relies on it: no surface point moves more than bound · ‖Δq‖.
  const Beam& s = beam();
  const double bound = s.field.displacement_bound();
  double largest_block = 0.0;
  for (Eigen::Index v = 0; 3 * v < s.basis.rows(); ++v) {
    largest_block = std::max(largest_block, s.basis.middleRows(3 * v, 3).norm());
  }
  // The same formula, compiled here and in the library (which may fuse differently).
  EXPECT_NEAR(bound, largest_block, 1e-14 * largest_block);
  std::mt19937 random(4);
  std::normal_distribution<double> gauss;
  double tightest = 0.0;  // largest ratio of a surface point's motion to bound · ‖Δq‖
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd dq(s.basis.cols());
    for (Eigen::Index j = 0; j < dq.size(); ++j) dq[j] = gauss(random);
    const Eigen::VectorXd u = s.basis * dq;
    for (const reduced::EmbeddedPoint& point : s.surface_points) {
      tightest = std::max(tightest, s.embedding.interpolate(point, u).norm() / (bound * dq.norm()));
    }
  }
  EXPECT_LE(tightest, 1.0);
  EXPECT_GT(tightest, 0.2);  // and not vacuously loose
  DeformedFieldState state(s.field);
  EXPECT_EQ(state.coordinates(), Eigen::VectorXd::Zero(s.basis.cols()));
  ASSERT_TRUE(state.update(0.01 * s.mixed_direction()));
  EXPECT_EQ(state.coordinates(), 0.01 * s.mixed_direction());
  EXPECT_EQ(state.displacement_bound(), bound);
}

TEST(DeformedDistanceField, RejectsBadInput) {
  const Beam& s = beam();
  const DistanceGrid& grid = s.field.field(0);
  const auto options_error = [](auto change, const char* message) {
    DeformedFieldOptions options;
    change(options);
    return test::throws_with_message<Error>([&] { options.validate(); }, message);
  };
  EXPECT_TRUE(options_error([](auto& o) { o.neighbours = 1; }, "neighbours 1 is not in [2, 16]"));
  EXPECT_TRUE(options_error([](auto& o) { o.neighbours = 17; }, "neighbours 17"));
  EXPECT_TRUE(options_error([](auto& o) { o.proxies = 4; }, "proxies 4 is below neighbours (5)"));
  DeformedFieldOptions few;
  few.proxies = 3;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { DeformedDistanceField({grid}, s.embedding, s.basis, few); }, "proxies 3"));

  const Eigen::Index rows = s.basis.rows();
  const auto build = [&](std::vector<DistanceGrid> fields, const Eigen::MatrixXd& basis) {
    DeformedDistanceField(std::move(fields), s.embedding, basis);
  };
  EXPECT_TRUE(test::throws_with_message<Error>([&] { build({grid}, s.basis.topRows(rows - 3)); },
                                               "expected " + std::to_string(rows) + " rows"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { build({grid}, Eigen::MatrixXd(rows, 0)); },
                                               "at least one column"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { build({}, s.basis); }, "no domain fields"));
  const std::vector<float> values(grid.values().begin(), grid.values().end());
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] {
        build({grid, DistanceGrid(grid.geometry(), values, false)}, s.basis);
      },
      "domain 1: the field is unsigned"));
  const std::vector<float> outside(values.size(), 1.0F);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { build({DistanceGrid(grid.geometry(), outside, true)}, s.basis); },
      "domain 0: the field's zero level set does not cross its grid"));

  std::vector<PointMatrix> proxies = proxy_sets(s.field);
  const auto given = [&](std::vector<DistanceGrid> fields, const std::vector<PointMatrix>& sets) {
    DeformedDistanceField(std::move(fields), sets, s.embedding, s.basis);
  };
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] {
        given({grid, grid}, proxies);
      },
      "1 proxy sets for 2 fields"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { given({grid}, {proxies[0].topRows(4)}); },
                                               "domain 0: 4 proxies, fewer than neighbours (5)"));
  proxies[0](7, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(test::throws_with_message<Error>([&] { given({grid}, proxies); },
                                               "domain 0: proxy 7 is not finite"));
}

TEST(DeformedDistanceField, QueriesAndUpdatesAllocateNothing) {
  const Beam& s = beam();
  const Legs& l = legs();
  DeformedFieldState state(s.field), split(l.split);
  const Eigen::VectorXd q = 0.2 * s.direction;
  const Eigen::VectorXd apart = Eigen::VectorXd::Constant(1, 0.3);
  Eigen::VectorXd reduced = Eigen::VectorXd::Zero(6), reduced_split = Eigen::VectorXd::Zero(1);
  const Eigen::Vector3d x(0.5, 0.21, 0.1), y(0.1, 0.2, 0.5);
  Eigen::Vector3d gradient;
  double sum = 0.0;
  test::allocation_count = 0;
  const bool updated = state.update(q) && split.update(apart);
  for (int n = 0; n < 10; ++n) {
    sum += state.distance(x) + state.distance_and_gradient(x, gradient) + split.distance(y) +
           split.distance_and_gradient(y, gradient);
    state.add_reduced_force(x, gradient, reduced);
    split.add_reduced_force(y, gradient, reduced_split);
  }
  const std::size_t allocations = test::allocation_count.load();
  EXPECT_TRUE(updated);
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_EQ(allocations, 0U);
}

}  // namespace
}  // namespace khz::contact
