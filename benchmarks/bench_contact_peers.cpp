// Kilohertz's contact query side by side with FCL and Bullet on the same meshes and poses: per
// query time (median, p99) and its ratio to Kilohertz, contacts found, agreement of the force's
// direction and of the deepest penetration with Kilohertz's, and the force's largest jump along a
// fine slide.
//
//   bench_contact_peers [--poses 400] [--repeats 3] [--slide-steps 2000] [--slide-step-um 1]
//                       [--cpu N]
//
// The scene has examples/scenes/dragon_on_dino.json's sizes: dino.off scaled to 0.2 m, fixed at the
// identity, and ChineseDragon-10kv.off scaled to 0.1 m with its holes filled, moving; both centred
// on their bounding boxes. Every library gets these two meshes.
// - Kilohertz: the dragon as a rigid PointTree of a 262,229-point, 5-level repulsion pointshell
//   against the dino's 256³ signed DistanceGrid; query_contact with one ContactWorkspace: k_C =
//   1000 N/m, L = 10, gradient normal_direction (as the bundled scenes), degradation none (full
//   traversal), no temporal coherence, the force taken on the pointshell (the dragon).
// - FCL: BVHModel<OBBRSS<double>> of both meshes; fcl::collide with enable_contact and
//   num_max_contacts 10⁶, so every intersecting triangle pair reports its contacts.
// - Bullet: btGImpactMeshShape of both meshes with margin 0 (so only penetrating triangle pairs
//   touch; the default 1 cm margin is a fifth of the dino), btCollisionWorld::contactPairTest
//   collecting every contact point.
// A peer's force on the dragon is Σ k_C · depth · n over its contacts with depth > 0, n the
// contact normal pointing out of the dino (no L/ℓ scaling). Kilohertz's force is its own: eq. 3.1
// over the points in contact, scaled by L/ℓ.
//
// Poses: bench_contact_query's flank trajectory scaled to these sizes: approach the dino's +x
// flank, slide 40 mm along z with the height swinging ±6 mm, turn 40° about the approach axis
// while rocking ±12° about z, slide back and leave. In contact the deepest pointshell point is up
// to 0.9 voxel deep (0.6 median), as Kilohertz measures it. After one unmeasured pass each pose
// runs Kilohertz, FCL and Bullet in turn, --repeats times. Times are over the poses Kilohertz finds
// in contact (and, apart, over the rest). The slide starts from the trajectory's pose at t = 0.3
// pressed 0.5 voxel deep and moves --slide-steps steps of --slide-step-um along z, the three
// libraries again in turn at every step.
//
// The field and pointshell are cached in KHZ_CONTACT_CACHE_DIR (first run: about two minutes on a
// busy machine; later runs: seconds). For a p99 without preemptions run it at SCHED_FIFO on one
// core, e.g. `chrt -f 20 taskset -c 1 bench_contact_peers --cpu 1`.
#include "contact_scenes.hpp"

#include <khz/contact/query/contact_query.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>

#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletCollisionCommon.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <omp.h>
#include <sched.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

namespace kc = khz::contact;
namespace kr = khz::reduced;
using khz::bench::Clock;
using khz::bench::degrees;
using khz::bench::quantile;
using khz::bench::ramp;
using khz::bench::rotation_about;
using khz::bench::TrajectoryScript;

constexpr double dino_size = 0.2;    // m
constexpr double dragon_size = 0.1;  // m

/// What one library reports for one pose.
struct Outcome {
  long contacts = 0;     // Kilohertz: points in contact; the peers: contact points with depth > 0
  double deepest = 0.0;  // m
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, on the dragon
  bool in_contact() const { return contacts > 0; }
};

// ---------------------------------------------------------------------------------------------
// The three queries.

class KilohertzQuery {
 public:
  KilohertzQuery(const kc::PointTree& tree, const kc::DistanceGrid& field,
                 const kc::ContactOptions& options)
      : m_tree(tree), m_field(field), m_workspace(tree, options) {}

  Outcome operator()(const Eigen::Isometry3d& pose) {
    kc::ContactFrames frames;
    frames.pointshell = pose;
    frames.grasp_point = pose.translation();
    if (!kc::query_contact(m_tree, m_field, frames, m_workspace)) {
      throw kc::Error("Kilohertz refused a query");
    }
    const kc::ContactResult& result = m_workspace.result();
    return {static_cast<long>(result.statistics.points_in_contact),
            result.statistics.deepest_penetration, result.force};
  }

 private:
  const kc::PointTree& m_tree;
  const kc::DistanceGrid& m_field;
  kc::ContactWorkspace m_workspace;
};

using FclModel = fcl::BVHModel<fcl::OBBRSSd>;

std::shared_ptr<FclModel> fcl_model(const kc::TriangleMesh& mesh) {
  std::vector<fcl::Vector3d> vertices;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    vertices.emplace_back(mesh.vertices.row(v).transpose());
  }
  std::vector<fcl::Triangle> triangles;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    triangles.emplace_back(mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2));
  }
  auto model = std::make_shared<FclModel>();
  model->beginModel();
  model->addSubModel(vertices, triangles);
  model->endModel();
  return model;
}

class FclQuery {
 public:
  FclQuery(const kc::TriangleMesh& dragon, const kc::TriangleMesh& dino, double stiffness)
      : m_dragon(fcl_model(dragon)), m_dino(fcl_model(dino)), m_stiffness(stiffness) {
    m_request.enable_contact = true;
    m_request.num_max_contacts = 1'000'000;
  }

  // Geometries and transforms rather than CollisionObjects: Kilohertz builds with Eigen's 64-byte
  // alignment, and a CollisionObject's Transform3d member would be laid out unlike in libfcl.
  Outcome operator()(const Eigen::Isometry3d& pose) {
    m_result.clear();
    fcl::collide(m_dragon.get(), pose, m_dino.get(), fcl::Transform3d::Identity(), m_request,
                 m_result);
    Outcome outcome;
    for (std::size_t c = 0; c < m_result.numContacts(); ++c) {
      const fcl::Contactd& contact = m_result.getContact(c);
      if (contact.penetration_depth <= 0.0) continue;
      // FCL's normal points from the first object (the dragon) to the second.
      outcome.force -= m_stiffness * contact.penetration_depth * contact.normal;
      outcome.deepest = std::max(outcome.deepest, contact.penetration_depth);
      ++outcome.contacts;
    }
    return outcome;
  }

 private:
  std::shared_ptr<FclModel> m_dragon, m_dino;
  double m_stiffness;
  fcl::CollisionRequestd m_request;
  fcl::CollisionResultd m_result;
};

/// A mesh as a GImpact shape; Bullet keeps pointers into the arrays.
struct BulletMesh {
  std::vector<int> indices;
  std::vector<btScalar> coordinates;
  std::unique_ptr<btTriangleIndexVertexArray> array;
  std::unique_ptr<btGImpactMeshShape> shape;

  explicit BulletMesh(const kc::TriangleMesh& mesh) {
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      for (int k = 0; k < 3; ++k) indices.push_back(mesh.triangles(t, k));
    }
    for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
      for (int k = 0; k < 3; ++k) coordinates.push_back(static_cast<btScalar>(mesh.vertices(v, k)));
    }
    array = std::make_unique<btTriangleIndexVertexArray>(
        static_cast<int>(mesh.triangles.rows()), indices.data(), 3 * static_cast<int>(sizeof(int)),
        static_cast<int>(mesh.vertices.rows()), coordinates.data(),
        3 * static_cast<int>(sizeof(btScalar)));
    shape = std::make_unique<btGImpactMeshShape>(array.get());
    shape->setMargin(0.0);
    shape->updateBound();
  }
};

/// Sums a contactPairTest's points into an Outcome.
struct BulletContacts final : btCollisionWorld::ContactResultCallback {
  const btCollisionObject* dragon = nullptr;
  double stiffness = 0.0;
  Outcome outcome;

  btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper* first, int, int,
                           const btCollisionObjectWrapper*, int, int) override {
    const double depth = -point.getDistance();
    if (depth <= 0.0) return 0;
    // m_normalWorldOnB points from the second object to the first.
    btVector3 normal = point.m_normalWorldOnB;
    if (first->getCollisionObject() != dragon) normal = -normal;
    outcome.force += stiffness * depth * Eigen::Vector3d(normal.x(), normal.y(), normal.z());
    outcome.deepest = std::max(outcome.deepest, depth);
    ++outcome.contacts;
    return 0;
  }
};

class BulletQuery {
 public:
  BulletQuery(const kc::TriangleMesh& dragon, const kc::TriangleMesh& dino, double stiffness)
      : m_dragon_mesh(dragon), m_dino_mesh(dino) {
    btGImpactCollisionAlgorithm::registerAlgorithm(&m_dispatcher);
    // contactPairTest asks for the closest-point algorithm, which registerAlgorithm() leaves
    // unset for GImpact pairs.
    m_dispatcher.registerClosestPointsCreateFunc(GIMPACT_SHAPE_PROXYTYPE, GIMPACT_SHAPE_PROXYTYPE,
                                                 &m_closest_points);
    m_dragon.setCollisionShape(m_dragon_mesh.shape.get());
    m_dino.setCollisionShape(m_dino_mesh.shape.get());
    m_world.addCollisionObject(&m_dragon);
    m_world.addCollisionObject(&m_dino);
    m_contacts.dragon = &m_dragon;
    m_contacts.stiffness = stiffness;
  }

  Outcome operator()(const Eigen::Isometry3d& pose) {
    const Eigen::Matrix3d& r = pose.linear();
    const Eigen::Vector3d& t = pose.translation();
    m_dragon.setWorldTransform(
        btTransform(btMatrix3x3(static_cast<btScalar>(r(0, 0)), static_cast<btScalar>(r(0, 1)),
                                static_cast<btScalar>(r(0, 2)), static_cast<btScalar>(r(1, 0)),
                                static_cast<btScalar>(r(1, 1)), static_cast<btScalar>(r(1, 2)),
                                static_cast<btScalar>(r(2, 0)), static_cast<btScalar>(r(2, 1)),
                                static_cast<btScalar>(r(2, 2))),
                    btVector3(static_cast<btScalar>(t.x()), static_cast<btScalar>(t.y()),
                              static_cast<btScalar>(t.z()))));
    m_contacts.outcome = Outcome{};
    m_world.contactPairTest(&m_dragon, &m_dino, m_contacts);
    return m_contacts.outcome;
  }

 private:
  btDefaultCollisionConfiguration m_configuration;
  btCollisionDispatcher m_dispatcher{&m_configuration};
  btDbvtBroadphase m_broadphase;
  btGImpactCollisionAlgorithm::CreateFunc m_closest_points;
  BulletMesh m_dragon_mesh, m_dino_mesh;
  btCollisionObject m_dragon, m_dino;
  // Last, so it is destroyed first: its destructor still reads the objects.
  btCollisionWorld m_world{&m_dispatcher, &m_broadphase, &m_configuration};
  BulletContacts m_contacts;
};

// ---------------------------------------------------------------------------------------------
// Poses.

/// bench_contact_query's flank script (its scene B: dragon 0.5 m on the dino 1 m) scaled by 0.2 to
/// these sizes; h is the dino field's voxel.
TrajectoryScript flank_script(double h) {
  constexpr double scale = dino_size / 1.0;
  TrajectoryScript script;
  script.start = scale * 1.0;  // as the 1 m dino's search starts 1 m out
  script.rotation = [](double t) {
    return Eigen::Matrix3d(
        rotation_about(Eigen::Vector3d::UnitX(), 40.0 * degrees * ramp(t, 0.45, 0.75)) *
        rotation_about(Eigen::Vector3d::UnitZ(),
                       12.0 * degrees * std::sin(3.0 * std::numbers::pi * t)));
  };
  script.lateral = [](double t) {
    return Eigen::Vector3d(0.0, scale * 0.03 * std::sin(2.0 * std::numbers::pi * t),
                           scale * 0.2 * (-0.5 + ramp(t, 0.15, 0.45) - 0.4 * ramp(t, 0.6, 0.9)));
  };
  script.clearance = [h](double t) {
    return scale * 0.03 * (1.0 - ramp(t, 0.0, 0.12)) + scale * 0.03 * ramp(t, 0.85, 1.0) -
           h * (0.6 + 0.3 * std::sin(6.0 * std::numbers::pi * t)) *
               (ramp(t, 0.08, 0.15) - ramp(t, 0.8, 0.87));
  };
  return script;
}

/// The script's pose at t moved along the approach axis until the deepest point is `depth` deep.
Eigen::Isometry3d pressed_pose(const TrajectoryScript& script, double t, double depth,
                               const kc::PointTree& tree, const kc::DistanceGrid& field) {
  const auto at = [&](double u) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = script.rotation(t);
    pose.translation() = script.lateral(t) + u * script.approach_axis;
    return pose;
  };
  const double h = field.geometry().spacing;
  const double u = khz::bench::solve_increasing(
      [&](double x) {
        return khz::bench::min_distance(khz::bench::RigidShape(tree), field, at(x)) + depth;
      },
      script.start, 0.25 * h, 1e-4 * h);
  return at(u);
}

// ---------------------------------------------------------------------------------------------
// Statistics.

double angle_degrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / degrees;
}

/// The largest change of the force from one slide step to the next, relative to its mean
/// magnitude over the slide.
double largest_jump(const std::vector<Eigen::Vector3d>& forces) {
  double jump = 0.0, sum = 0.0;
  for (std::size_t k = 0; k < forces.size(); ++k) {
    sum += forces[k].norm();
    if (k > 0) jump = std::max(jump, (forces[k] - forces[k - 1]).norm());
  }
  return sum > 0.0 ? jump / (sum / static_cast<double>(forces.size())) : std::nan("");
}

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

double load_average() {
  double load[1] = {0.0};
  return getloadavg(load, 1) == 1 ? load[0] : std::nan("");
}

struct Library {
  Library(std::string library_name, std::function<Outcome(const Eigen::Isometry3d&)> run)
      : name(std::move(library_name)), query(std::move(run)) {}

  std::string name;
  std::function<Outcome(const Eigen::Isometry3d&)> query;
  std::vector<Outcome> outcomes;             // per pose
  std::vector<double> us_contact, us_apart;  // per query
  std::vector<Eigen::Vector3d> slide;        // force per slide step
  long slide_contact_steps = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Kilohertz's contact query side by side with FCL and Bullet"};
  int poses = 400, repeats = 3, slide_steps = 2000, cpu = -1;
  double slide_step_um = 1.0;
  app.add_option("--poses", poses, "Poses along the flank trajectory")
      ->check(CLI::Range(16, 100000));
  app.add_option("--repeats", repeats, "Measured queries per pose and library")
      ->check(CLI::PositiveNumber);
  app.add_option("--slide-steps", slide_steps, "Steps of the fine slide")
      ->check(CLI::Range(2, 1000000));
  app.add_option("--slide-step-um", slide_step_um, "Length of a slide step (µm)")
      ->check(CLI::PositiveNumber);
  app.add_option("--cpu", cpu, "Pin the queries to this CPU (default: not pinned)")
      ->check(CLI::Range(0, static_cast<int>(std::thread::hardware_concurrency()) - 1));
  CLI11_PARSE(app, argc, argv);

  // Precomputes on the machine's two cores; the queries on one thread.
  omp_set_num_threads(2);
  std::printf("Precomputes (cache: %s)\n", KHZ_CONTACT_CACHE_DIR);
  std::fflush(stdout);
  const kc::TriangleMesh dino = khz::bench::demo_mesh("dino.off", dino_size);
  kc::TriangleMesh dragon = khz::bench::demo_mesh("ChineseDragon-10kv.off", dragon_size);
  const kr::HoleFilling holes = kr::fill_holes(dragon);
  const kc::DistanceGrid field = khz::bench::cached_signed_field("dino_200mm", dino, 256);
  const kc::PointTree tree(
      khz::bench::cached_pointshell("dragon_100mm_filled", dragon, false, 256, 769, 5));
  const double h = field.geometry().spacing;
  for (const auto& p : khz::bench::precompute_log()) {
    std::printf("  %-40s %8.2f s %s\n", p.what.c_str(), p.seconds,
                p.from_cache ? "cache" : "built");
  }

  const TrajectoryScript script = flank_script(h);
  TrajectoryScript sized = script;
  sized.poses = poses;
  const khz::bench::Trajectory trajectory = khz::bench::record_trajectory(
      sized, [&](const Eigen::VectorXd&) { return khz::bench::RigidShape(tree); }, field, h);
  const Eigen::Isometry3d slide_start = pressed_pose(script, 0.3, 0.5 * h, tree, field);

  kc::ContactOptions options;
  options.haptic_object = kc::HapticObject::pointshell;
  options.gradient = kc::ContactGradient::normal_direction;
  KilohertzQuery kilohertz(tree, field, options);
  const Clock::time_point start = Clock::now();
  FclQuery fcl(dragon, dino, options.stiffness);
  BulletQuery bullet(dragon, dino, options.stiffness);
  const double peer_setup = khz::bench::seconds_since(start);
  std::array<Library, 3> libraries{Library("Kilohertz", std::ref(kilohertz)),
                                   Library("FCL OBBRSS", std::ref(fcl)),
                                   Library("Bullet GImpact", std::ref(bullet))};

  std::printf(
      "\nScene: dino.off %.1f m (%ld triangles, fixed), ChineseDragon-10kv.off %.1f m (%ld "
      "triangles, %ld holes filled, %ld left open), moving\n",
      dino_size, static_cast<long>(dino.triangles.rows()), dragon_size,
      static_cast<long>(dragon.triangles.rows()), static_cast<long>(holes.filled),
      static_cast<long>(holes.left_open));
  std::printf(
      "Kilohertz: %ld points in %d levels against a 256³ field (h = %.3f mm); k_C %.0f N/m, L "
      "%.0f, normal_direction gradient, degradation none, no coherence\n",
      static_cast<long>(tree.num_points()), tree.num_levels(), 1e3 * h, options.stiffness,
      options.scaling_count);
  std::printf(
      "FCL BVHModel<OBBRSS<double>> collide, all contacts; Bullet btGImpactMeshShape (margin 0) "
      "contactPairTest, all points (%s precision); peers' force Σ k_C·depth·n; peer setup %.2f "
      "s\n",
      sizeof(btScalar) == sizeof(double) ? "double" : "single", peer_setup);

  // One thread from here on, pinned if asked.
  omp_set_num_threads(1);
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof(set), &set) != 0) std::printf("(pinning refused)\n");
  }
  const double load_before = load_average();

  // One unmeasured pass (caches, allocations), then the measured ones, alternating per query.
  const auto n = trajectory.size();
  for (Library& library : libraries) {
    for (std::size_t i = 0; i < n; ++i)
      library.outcomes.push_back(library.query(trajectory.pointshell[i]));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const bool touching = libraries[0].outcomes[i].in_contact();
    for (int r = 0; r < repeats; ++r) {
      for (Library& library : libraries) {
        const Clock::time_point query_start = Clock::now();
        library.query(trajectory.pointshell[i]);
        const double us = 1e6 * khz::bench::seconds_since(query_start);
        (touching ? library.us_contact : library.us_apart).push_back(us);
      }
    }
  }
  for (int k = 0; k < slide_steps; ++k) {
    Eigen::Isometry3d pose = slide_start;
    pose.translation().z() += 1e-6 * slide_step_um * k;
    for (Library& library : libraries) {
      const Outcome outcome = library.query(pose);
      library.slide.push_back(outcome.force);
      if (outcome.in_contact()) ++library.slide_contact_steps;
    }
  }
  const double load_after = load_average();

  // Penetration of the poses in contact, as Kilohertz measures it.
  std::vector<double> depths;
  for (const Outcome& outcome : libraries[0].outcomes) {
    if (outcome.in_contact()) depths.push_back(outcome.deepest / h);
  }
  std::printf(
      "Poses: %zu on the flank trajectory, %zu in contact (deepest point %.2f–%.2f voxel, median "
      "%.2f), %zu apart; %d measured queries per pose and library\n",
      n, depths.size(), quantile(depths, 0.0), quantile(depths, 1.0), quantile(depths, 0.5),
      n - depths.size(), repeats);
  std::printf("Slide: %d steps of %.3g µm along z from a press 0.5 voxel deep\n", slide_steps,
              slide_step_um);
  const std::string pinned = cpu >= 0 ? ", pinned to CPU " + std::to_string(cpu) : "";
  // Whether it ran at SCHED_FIFO (e.g. under chrt): without, a busy machine's preemptions make
  // the p99.
  const bool fifo = sched_getscheduler(0) == SCHED_FIFO;
  std::printf(
      "Machine: %s, %u CPUs; queries on one thread (omp_set_num_threads(1))%s, %s; load "
      "average %.1f before, %.1f after\n",
      cpu_model().c_str(), std::thread::hardware_concurrency(), pinned.c_str(),
      fifo ? "SCHED_FIFO" : "normal priority", load_before, load_after);

  const double khz_median = quantile(libraries[0].us_contact, 0.5);
  std::printf("\n%-15s %9s %9s %9s %7s %9s %15s %13s %15s %11s\n", "library", "µs p50", "µs p99",
              "µs apart", "× KHZ", "contacts", "angle p50/p90°", "depth |Δ| mm", "contact differs",
              "slide jump");
  for (const Library& library : libraries) {
    std::vector<double> contacts, angles, depth_errors;
    long differs = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Outcome& mine = library.outcomes[i];
      const Outcome& reference = libraries[0].outcomes[i];
      if (mine.in_contact()) contacts.push_back(static_cast<double>(mine.contacts));
      if (mine.in_contact() != reference.in_contact()) ++differs;
      if (mine.in_contact() && reference.in_contact()) {
        angles.push_back(angle_degrees(mine.force, reference.force));
        depth_errors.push_back(1e3 * std::abs(mine.deepest - reference.deepest));
      }
    }
    const double median = quantile(library.us_contact, 0.5);
    std::printf("%-15s %9.1f %9.1f %9.1f %7.2f %9.0f %7.1f/%-7.1f %13.3f %14.1f%% %10.1f%%\n",
                library.name.c_str(), median, quantile(library.us_contact, 0.99),
                quantile(library.us_apart, 0.5), median / khz_median, quantile(contacts, 0.5),
                quantile(angles, 0.5), quantile(angles, 0.9), quantile(depth_errors, 0.5),
                100.0 * static_cast<double>(differs) / static_cast<double>(n),
                100.0 * largest_jump(library.slide));
  }
  std::printf(
      "\nµs: per query, median and p99 over the poses Kilohertz finds in contact, median apart; × "
      "KHZ: median over Kilohertz's median.\n"
      "contacts: median over the poses the library finds in contact (Kilohertz: pointshell "
      "points; the peers: contact points).\n"
      "angle: between the library's force and Kilohertz's, over poses where both find contact; "
      "depth |Δ|: median |deepest − Kilohertz's deepest| there.\n"
      "contact differs: share of all poses where one of the two finds contact and the other not.\n"
      "slide jump: largest step-to-step change of the force over its mean magnitude along the "
      "slide (steps in contact: ");
  for (const Library& library : libraries) {
    std::printf("%s %ld%s", library.name.c_str(), library.slide_contact_steps,
                &library == &libraries.back() ? ").\n" : ", ");
  }
  return 0;
}
