// The deformed distance field of a reduced deformable object (thesis §3.12) on dino.off (CGAL's
// demo data): its signed distance field at 128³ cells, a voxel hexahedral mesh of it with its 15
// lowest free-floating linear modes (r = 15, the thesis's setting), 40 proxies and k = 5.
// Per call: DeformedFieldState::distance() and distance_and_gradient() at points near the
// deformed surface (deformed dino vertices moved by up to two grid cells), and update(q).
// Prints the model's sizes once.
#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <random>
#include <span>
#include <vector>

namespace {

namespace kc = khz::contact;
namespace kr = khz::reduced;

constexpr int kModes = 15;

struct Model {
  kc::TriangleMesh surface =
      kr::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / "dino.off");
  kr::VolumeMesh volume = voxels();
  kr::MeshEmbedding embedding{volume};
  Eigen::MatrixXd basis = modes();
  kc::DeformedDistanceField field{{field_of_surface()}, embedding, basis};
  /// A pose with a largest vertex displacement of 5% of the model's size.
  Eigen::VectorXd q = pose();
  std::vector<Eigen::Vector3d> points = points_near_surface();

  kr::VolumeMesh voxels() const {
    kr::VoxelizeOptions options;
    options.resolution = 24;
    options.fill_interior = true;
    return kr::voxelize(surface, options);
  }
  kc::DistanceGrid field_of_surface() const {
    kc::DistanceFieldOptions options;
    options.cells = 128;
    return kc::signed_distance_field(surface, options);
  }
  Eigen::MatrixXd modes() const {
    const kr::FemModel model(volume, {kr::Material::stvk(1e6, 0.4, 1000.0)});
    kr::LinearModesOptions options;
    options.num_modes = kModes;
    return kr::compute_linear_modes(model, {}, options).modes;
  }
  double size() const {
    return (surface.vertices.colwise().maxCoeff() - surface.vertices.colwise().minCoeff()).norm();
  }
  Eigen::VectorXd pose() const {
    std::mt19937 random(1);
    std::normal_distribution<double> gauss;
    Eigen::VectorXd direction(kModes);
    for (Eigen::Index j = 0; j < kModes; ++j) direction[j] = gauss(random);
    const Eigen::VectorXd u = basis * direction;
    const double largest = u.reshaped(3, u.size() / 3).colwise().norm().maxCoeff();
    return 0.05 * size() / largest * direction;
  }
  std::vector<Eigen::Vector3d> points_near_surface() const {
    const Eigen::VectorXd u = basis * q;
    const double spacing = field.field(0).geometry().spacing;
    std::mt19937 random(2);
    std::uniform_real_distribution<double> offset(-2.0 * spacing, 2.0 * spacing);
    std::vector<Eigen::Vector3d> result;
    for (Eigen::Index v = 0; v < surface.num_vertices(); ++v) {
      const Eigen::Vector3d rest = surface.vertices.row(v).transpose();
      const Eigen::Vector3d deformed = rest + embedding.interpolate(embedding.locate(rest), u);
      result.push_back(deformed + Eigen::Vector3d(offset(random), offset(random), offset(random)));
    }
    return result;
  }
};

const Model& model() {
  static const Model instance = [] {
    Model m;
    std::printf(
        "dino.off: %lld triangles; volume mesh %lld hexahedra, %lld vertices; r = %lld; %lld "
        "proxies, k = %d; field %d³ cells (h = %.4g); %zu query points within 2h of the surface "
        "deformed by up to 5%% of the size\n",
        static_cast<long long>(m.surface.num_triangles()),
        static_cast<long long>(m.volume.num_elements()),
        static_cast<long long>(m.volume.num_vertices()),
        static_cast<long long>(m.field.dimension()), static_cast<long long>(m.field.num_proxies()),
        m.field.neighbours(), m.field.field(0).geometry().cells,
        m.field.field(0).geometry().spacing, m.points.size());
    return m;
  }();
  return instance;
}

void add_rate(benchmark::State& state, std::size_t calls, const char* name) {
  state.counters[name] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(calls),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// distance() or, with_gradient, distance_and_gradient() at every query point.
template <bool with_gradient>
void BM_Query(benchmark::State& state) {
  const Model& m = model();
  kc::DeformedFieldState field(m.field);
  if (!field.update(m.q)) state.SkipWithError("update refused the pose");
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  for (auto _ : state) {
    double sum = 0.0;
    for (const Eigen::Vector3d& x : m.points) {
      if constexpr (with_gradient) {
        sum += field.distance_and_gradient(x, gradient);
      } else {
        sum += field.distance(x);
      }
    }
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(gradient);
  }
  add_rate(state, m.points.size(), "s/query");
}
BENCHMARK_TEMPLATE(BM_Query, false)->Name("BM_Distance");

/// culling_distance() at every query point, at threshold 0 (a deepest-level point's radius:
/// about half the points are culled) and at −4h, below every query point's distance (all are).
void BM_CullingDistance(benchmark::State& state) {
  const Model& m = model();
  kc::DeformedFieldState field(m.field);
  if (!field.update(m.q)) state.SkipWithError("update refused the pose");
  const double threshold =
      static_cast<double>(state.range(0)) * m.field.field(0).geometry().spacing;
  for (auto _ : state) {
    double sum = 0.0;
    for (const Eigen::Vector3d& x : m.points) sum += field.culling_distance(x, threshold);
    benchmark::DoNotOptimize(sum);
  }
  add_rate(state, m.points.size(), "s/query");
}
BENCHMARK(BM_CullingDistance)->Arg(0)->Arg(-4)->ArgName("threshold_h");

/// culling_distances() over the same points, 16 at a time as the contact query asks.
void BM_CullingDistances(benchmark::State& state) {
  const Model& m = model();
  kc::DeformedFieldState field(m.field);
  if (!field.update(m.q)) state.SkipWithError("update refused the pose");
  const double threshold =
      static_cast<double>(state.range(0)) * m.field.field(0).geometry().spacing;
  constexpr std::size_t batch = 16;
  const std::vector<double> thresholds(batch, threshold);
  std::array<double, batch> out{};
  for (auto _ : state) {
    double sum = 0.0;
    for (std::size_t first = 0; first + batch <= m.points.size(); first += batch) {
      field.culling_distances(std::span(m.points).subspan(first, batch), thresholds, out);
      sum += out[0];
    }
    benchmark::DoNotOptimize(sum);
  }
  add_rate(state, m.points.size() / batch * batch, "s/query");
}
BENCHMARK(BM_CullingDistances)->Arg(0)->Arg(-4)->ArgName("threshold_h");
BENCHMARK_TEMPLATE(BM_Query, true)->Name("BM_DistanceAndGradient");

void BM_Update(benchmark::State& state) {
  const Model& m = model();
  kc::DeformedFieldState field(m.field);
  // Alternating poses, so no call can reuse the previous result.
  const Eigen::VectorXd poses[2] = {m.q, 0.5 * m.q};
  int which = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(field.update(poses[which]));
    which ^= 1;
  }
  add_rate(state, 1, "s/update");
}
BENCHMARK(BM_Update);

}  // namespace
