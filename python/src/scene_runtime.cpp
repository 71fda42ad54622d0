// kilohertz.scene: scene files, their preparation through the product cache, and running them:
// SceneRuntime with the scene's devices or ones written in Python.

#include <khz/scene/cache_directory.hpp>
#include <khz/scene/make_device.hpp>
#include <khz/scene/prepare_error.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_error.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "haptic_devices.hpp"
#include "progress.hpp"
#include "scene_figures.hpp"

// A PreparedScene holds unique_ptrs in a vector, which std::is_copy_constructible cannot see
// through: tell pybind11 it moves only.
template <>
struct pybind11::detail::is_copy_constructible<khz::scene::PreparedScene> : std::false_type {};

namespace khz::python {

namespace {

using scene::PreparedScene;
using scene::SceneDescription;

/// Scene text from a str (JSON) or a dict (dumped with Python's json module).
std::string scene_text(const py::handle& scene) {
  if (py::isinstance<py::str>(scene)) return scene.cast<std::string>();
  if (py::isinstance<py::dict>(scene)) {
    return py::module_::import("json").attr("dumps")(scene).cast<std::string>();
  }
  throw py::type_error("expected the scene as JSON text (str) or a dict");
}

scene::SceneReadOptions read_options(const py::object& base_directory,
                                     const py::object& cgal_mesh_dir, bool check_files) {
  scene::SceneReadOptions options;
  if (!base_directory.is_none())
    options.base_directory = base_directory.cast<std::filesystem::path>();
  if (!cgal_mesh_dir.is_none()) options.cgal_mesh_dir = cgal_mesh_dir.cast<std::filesystem::path>();
  options.check_files = check_files;
  return options;
}

void bind_description(py::module_& module) {
  py::class_<SceneDescription>(module, "SceneDescription", R"(A scene file read and validated
(khz::scene::SceneDescription); prepare it with prepare_scene().)")
      .def_readonly("source", &SceneDescription::source, "Where it was read from.")
      .def_readonly("description", &SceneDescription::description)
      .def_property_readonly("object_names",
                             [](const SceneDescription& s) {
                               std::vector<std::string> names;
                               for (const auto& object : s.objects) names.push_back(object.name);
                               return names;
                             })
      .def_property_readonly(
          "hand_count", [](const SceneDescription& s) { return static_cast<int>(s.haptic.size()); })
      .def_property_readonly(
          "rate_hz", [](const SceneDescription& s) { return s.loop.rate_hz; },
          "The haptic loop's rate (Hz).")
      .def_readonly("duration", &SceneDescription::duration,
                    "loop.duration (s); 0 when the devices' recordings decide.")
      .def("__repr__", [](const SceneDescription& s) {
        return "SceneDescription('" + s.source + "', " + std::to_string(s.objects.size()) +
               " objects, " + std::to_string(s.haptic.size()) + " hands)";
      });
  module.def(
      "read_scene",
      [](const std::filesystem::path& file, const py::object& cgal_mesh_dir, bool check_files) {
        const auto options = read_options(py::none(), cgal_mesh_dir, check_files);
        const py::gil_scoped_release unlocked;
        return scene::read_scene(file, options);
      },
      py::arg("file"), py::arg("cgal_mesh_dir") = py::none(), py::arg("check_files") = true,
      R"(Reads and validates a scene file (docs/SCENES.md); relative paths resolve against its
directory, "cgal:NAME" meshes against cgal_mesh_dir (default: $KHZ_CGAL_MESH_DIR or the
build's). Raises IoError, or SceneError naming the file, line or key path and what was expected.)");
  module.def(
      "default_cgal_mesh_dir",
      []() -> py::object {
        const std::filesystem::path directory = scene::default_cgal_mesh_dir();
        if (directory.empty()) return py::none();
        return py::cast(directory);
      },
      "Where \"cgal:NAME\" meshes are: $KHZ_CGAL_MESH_DIR, else the directory this build "
      "extracted CGAL's demo meshes to; None when neither is known.");
  module.def(
      "parse_scene",
      [](const py::handle& scene, const std::string& source, const py::object& base_directory,
         const py::object& cgal_mesh_dir, bool check_files) {
        const std::string text = scene_text(scene);
        const auto options = read_options(base_directory, cgal_mesh_dir, check_files);
        const py::gil_scoped_release unlocked;
        return scene::parse_scene(text, source, options);
      },
      py::arg("scene"), py::arg("source") = "<python>", py::arg("base_directory") = py::none(),
      py::arg("cgal_mesh_dir") = py::none(), py::arg("check_files") = true,
      "A scene given as a dict or JSON text, validated as read_scene() does; `source` names it "
      "in messages, relative paths resolve against base_directory (default: the current one).");
}

py::dict prepare_record(const scene::PrepareRecord& record) {
  py::dict row;
  row["object"] = record.object;
  row["step"] = std::string(scene::step_name(record.step));
  row["origin"] = std::string(scene::origin_name(record.origin));
  row["seconds"] = record.seconds;
  row["file"] = record.file;
  row["note"] = record.note;
  return row;
}

void bind_preparation(py::module_& module) {
  py::class_<PreparedScene>(module, "PreparedScene", R"(Everything a scene needs to run,
computed or read from the cache (khz::scene::PreparedScene); run it with SceneRuntime.)")
      .def_readonly("description", &PreparedScene::description)
      .def_property_readonly(
          "records",
          [](const PreparedScene& p) {
            py::list rows;
            for (const auto& record : p.records) rows.append(prepare_record(record));
            return rows;
          },
          "One dict per product: object, step, origin (computed, read, "
          "built), seconds, file, note.")
      .def_property_readonly(
          "warnings",
          [](const PreparedScene& p) {
            std::vector<std::pair<std::string, std::string>> warnings;
            for (const auto& w : p.warnings) warnings.emplace_back(w.object, w.message);
            return warnings;
          },
          "(object, message) pairs: sizes that look like the wrong unit, devices turned away "
          "from their object.")
      .def_property_readonly(
          "computed",
          [](const PreparedScene& p) { return p.count(scene::PrepareRecord::Origin::computed); })
      .def_property_readonly("total_seconds", &PreparedScene::total_seconds);
  module.def(
      "default_cache_directory",
      []() -> py::object {
        const std::filesystem::path directory = scene::default_cache_directory();
        if (directory.empty()) return py::none();
        return py::cast(directory);
      },
      "Where products are cached: $XDG_CACHE_HOME/kilohertz, else ~/.cache/kilohertz "
      "(None when neither variable is an absolute path).");
  module.def(
      "prepare_scene",
      [](const SceneDescription& description, const py::object& cache_directory,
         const py::object& progress) {
        const std::filesystem::path directory = cache_directory.is_none()
                                                    ? scene::default_cache_directory()
                                                    : cache_directory.cast<std::filesystem::path>();
        if (directory.empty()) {
          throw py::value_error(
              "no cache directory: neither XDG_CACHE_HOME nor HOME is an absolute path, so give "
              "cache_directory=");
        }
        scene::ProductCache cache(directory);
        const reduced::ProgressCallback report = python_progress(progress);
        scene::PrepareOptions options;
        options.progress = [report](const std::string& object, scene::PrepareStep step,
                                    const reduced::Progress& p) {
          const std::string stage =
              object + ": " + std::string(scene::step_name(step)) + ": " + std::string(p.stage);
          return report(reduced::Progress{stage, p.done, p.total});
        };
        const py::gil_scoped_release unlocked;
        return scene::prepare_scene(description, cache, options);
      },
      py::arg("scene"), py::arg("cache_directory") = py::none(), py::arg("progress") = py::none(),
      R"(Prepares every object of the scene: reduced models, distance fields and pointshells, each
computed once and cached by the content of its inputs (default_cache_directory()), and the
point trees, built from them every time.
progress: None or a callable(stage, done, total) -> bool, stage reading "object: step: what";
False cancels (Cancelled, no partial file). Ctrl-C stops it. Runs without the GIL. Raises
PrepareError naming the object and step.)");
}

/// One hand's records of a run, column by column.
struct HandColumns {
  std::vector<double> time, cycle_us, manipulandum, simulation, contact, rendered, residual;
  std::vector<double> penetration_voxels, energy;
  std::vector<std::int64_t> points_in_contact;
  std::vector<std::uint8_t> saturated, device_valid;

  void reserve(std::size_t cycles) {
    for (auto* column : {&time, &cycle_us, &penetration_voxels, &energy}) column->reserve(cycles);
    for (auto* column : {&manipulandum, &simulation}) column->reserve(7 * cycles);
    for (auto* column : {&contact, &rendered, &residual}) column->reserve(6 * cycles);
    points_in_contact.reserve(cycles);
    saturated.reserve(cycles);
    device_valid.reserve(cycles);
  }

  void add(const haptic::CycleRecord& r, double us) {
    time.push_back(r.time);
    cycle_us.push_back(us);
    for (const haptic::Pose* pose : {&r.manipulandum, &r.simulation}) {
      auto& column = pose == &r.manipulandum ? manipulandum : simulation;
      column.insert(column.end(), pose->position.data(), pose->position.data() + 3);
      const auto& q = pose->orientation;
      column.insert(column.end(), {q.w(), q.x(), q.y(), q.z()});
    }
    const auto add_wrench = [](std::vector<double>& column, const Eigen::Vector3d& force,
                               const Eigen::Vector3d& torque) {
      column.insert(column.end(), force.data(), force.data() + 3);
      column.insert(column.end(), torque.data(), torque.data() + 3);
    };
    add_wrench(contact, r.contact.force, r.contact.torque);
    add_wrench(rendered, r.rendered.force, r.rendered.torque);
    add_wrench(residual, r.residual.force, r.residual.torque);
    penetration_voxels.push_back(r.penetration_voxels);
    energy.push_back(r.observed_energy);
    points_in_contact.push_back(r.contact.statistics.points_in_contact);
    saturated.push_back(r.coupling_saturated);
    device_valid.push_back(r.device_valid);
  }

  py::dict to_numpy() const {
    const auto n = static_cast<py::ssize_t>(time.size());
    const auto column = [n](const auto& values, py::ssize_t width, py::ssize_t from,
                            py::ssize_t count) {
      using T = typename std::decay_t<decltype(values)>::value_type;
      py::array_t<T> out(count == 1 ? std::vector<py::ssize_t>{n}
                                    : std::vector<py::ssize_t>{n, count});
      for (py::ssize_t i = 0; i < n; ++i) {
        for (py::ssize_t c = 0; c < count; ++c) {
          out.mutable_data()[i * count + c] =
              values[static_cast<std::size_t>(i * width + from + c)];
        }
      }
      return out;
    };
    py::dict d;
    d["time"] = column(time, 1, 0, 1);
    d["cycle_us"] = column(cycle_us, 1, 0, 1);
    d["manipulandum_position"] = column(manipulandum, 7, 0, 3);
    d["manipulandum_orientation"] = column(manipulandum, 7, 3, 4);
    d["simulation_position"] = column(simulation, 7, 0, 3);
    d["simulation_orientation"] = column(simulation, 7, 3, 4);
    d["contact_force"] = column(contact, 6, 0, 3);
    d["contact_torque"] = column(contact, 6, 3, 3);
    d["rendered_force"] = column(rendered, 6, 0, 3);
    d["rendered_torque"] = column(rendered, 6, 3, 3);
    d["residual_force"] = column(residual, 6, 0, 3);
    d["residual_torque"] = column(residual, 6, 3, 3);
    d["penetration_voxels"] = column(penetration_voxels, 1, 0, 1);
    d["observed_energy"] = column(energy, 1, 0, 1);
    d["points_in_contact"] = column(points_in_contact, 1, 0, 1);
    d["coupling_saturated"] = py::array(column(saturated, 1, 0, 1)).attr("astype")("bool");
    d["device_valid"] = py::array(column(device_valid, 1, 0, 1)).attr("astype")("bool");
    return d;
  }
};

/// A SceneRuntime with the Python objects it borrows: the prepared scene and the devices.
class Runtime {
 public:
  Runtime(const PreparedScene& prepared, const py::object& devices) {
    if (devices.is_none()) {
      m_runtime = std::make_unique<scene::SceneRuntime>(prepared);
      return;
    }
    std::vector<haptic::Device*> borrowed;
    for (const py::handle device : devices) {
      m_devices.push_back(py::reinterpret_borrow<py::object>(device));
      borrowed.push_back(device.is_none() ? nullptr : device.cast<haptic::Device*>());
      if (auto* python = dynamic_cast<PythonDevice*>(borrowed.back())) m_python.push_back(python);
    }
    m_runtime = std::make_unique<scene::SceneRuntime>(prepared, borrowed);
  }

  scene::SceneRuntime& runtime() noexcept { return *m_runtime; }

  std::vector<py::dict> run(const py::object& duration, const py::object& cycles_given) {
    const double rate = m_runtime->description().loop.rate_hz;
    std::size_t cycles = 0;
    if (!cycles_given.is_none()) {
      const auto n = cycles_given.cast<std::int64_t>();
      if (n < 1) throw py::value_error("cycles: expected at least 1, got " + std::to_string(n));
      cycles = static_cast<std::size_t>(n);
    } else {
      const double seconds =
          duration.is_none() ? m_runtime->natural_duration() : duration.cast<double>();
      if (!(seconds > 0.0) || !std::isfinite(seconds)) {
        throw py::value_error(
            "the run has no duration: the devices play no recording, so give duration= (s) or "
            "cycles=");
      }
      cycles = static_cast<std::size_t>(std::ceil(seconds * rate - 1e-9));
    }
    std::vector<HandColumns> hands(static_cast<std::size_t>(m_runtime->hand_count()));
    for (auto& hand : hands) hand.reserve(cycles);
    bool interrupted = false;
    m_runtime->open_devices();
    {
      const py::gil_scoped_release unlocked;
      haptic::World& world = m_runtime->world();
      world.reset_metrics();
      const double period = 1.0 / rate;
      using Clock = std::chrono::steady_clock;
      for (std::size_t i = 0; i < cycles; ++i) {
        const double now = static_cast<double>(i) * period;
        const auto start = Clock::now();
        const auto records = world.cycle(now, now + period, [now] { return now; });
        const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
        for (std::size_t h = 0; h < records.size(); ++h) hands[h].add(records[h], us);
        if (device_failed()) break;
        if (i % 256 == 255) {  // Ctrl-C: Python's handlers run in the main thread, with the GIL
          const py::gil_scoped_acquire gil;
          if (PyErr_CheckSignals() != 0) {
            interrupted = true;
            break;
          }
        }
      }
    }
    m_runtime->close_devices();
    if (interrupted) throw py::error_already_set();
    for (PythonDevice* device : m_python) device->raise_error();
    std::vector<py::dict> out;
    for (const auto& hand : hands) out.push_back(hand.to_numpy());
    return out;
  }

  std::vector<py::dict> cycle(double now, double period) {
    const auto records = m_runtime->world().cycle(now, now + period, [now] { return now; });
    std::vector<py::dict> hands;
    for (const auto& record : records) {
      HandColumns one;
      one.add(record, 0.0);
      hands.push_back(one.to_numpy());
    }
    for (PythonDevice* device : m_python) device->raise_error();
    return hands;
  }

 private:
  bool device_failed() const noexcept {
    for (const PythonDevice* device : m_python) {
      if (device->failed()) return true;
    }
    return false;
  }

  std::vector<py::object> m_devices;
  std::vector<PythonDevice*> m_python;
  std::unique_ptr<scene::SceneRuntime> m_runtime;
};

py::array pose_matrix(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> m = pose.matrix();
  return py::array_t<double>({4, 4}, m.data());
}

void check_object(Runtime& r, int object) {
  const auto count = static_cast<int>(r.runtime().description().objects.size());
  if (object < 0 || object >= count) {
    throw py::index_error("object " + std::to_string(object) + " out of range: the scene has " +
                          std::to_string(count));
  }
}

void bind_runtime(py::module_& module) {
  py::class_<Runtime>(module, "SceneRuntime", R"(A prepared scene made a running haptic World
(khz::scene::SceneRuntime): object i is the scene's object i, hand h its haptic[h].)")
      .def(py::init<const PreparedScene&, const py::object&>(), py::arg("prepared"),
           py::arg("devices") = py::none(), py::keep_alive<1, 2>(),
           R"(devices: None for the devices the scene describes, or one entry per hand: a
kilohertz.haptic.Device (a Python subclass runs in the cycle), or None to keep that hand's
scene device. Raises kilohertz.Error naming the problem (e.g. a device list of the wrong
length).)")
      .def_property_readonly("hand_count", [](Runtime& r) { return r.runtime().hand_count(); })
      .def_property_readonly(
          "natural_duration", [](Runtime& r) { return r.runtime().natural_duration(); },
          "How long the scene runs (s) when run() is given no duration.")
      .def("run", &Runtime::run, py::arg("duration") = py::none(), py::arg("cycles") = py::none(),
           R"(Opens the devices, runs the haptic loop in simulated time (1 / rate_hz per cycle)
for `cycles` cycles or `duration` seconds (default: natural_duration), and closes them. Runs
without the GIL except for Python devices' calls; Ctrl-C stops it (KeyboardInterrupt), and an
exception from a Python device stops it and is raised. Returns one dict per hand of per-cycle
arrays: time, cycle_us, manipulandum_/simulation_position (N, 3) and _orientation (N, 4) (w, x,
y, z), contact_/rendered_/residual_force and _torque (N, 3), penetration_voxels,
observed_energy, points_in_contact, coupling_saturated, device_valid.)")
      .def(
          "metrics",
          [](Runtime& r, int hand) {
            if (hand < 0 || hand >= r.runtime().hand_count()) {
              throw py::index_error("hand " + std::to_string(hand) + " out of range");
            }
            return metrics_out(r.runtime().world().metrics(hand));
          },
          py::arg("hand") = 0,
          "The last run's smoothness, jitter, residual, penetration and passivity figures for a "
          "hand (a dict; docs/HAPTICS.md explains each).")
      .def(
          "pose",
          [](Runtime& r, int object) {
            check_object(r, object);
            return pose_matrix(r.runtime().pose(object));
          },
          py::arg("object"), "Object i's pose, world ← body, as a 4×4 matrix (m).")
      .def(
          "coordinates",
          [](Runtime& r, int object) {
            check_object(r, object);
            const Eigen::VectorXd q = r.runtime().coordinates(object);
            return py::array_t<double>(q.size(), q.data());
          },
          py::arg("object"), "Object i's reduced coordinates q (r,); empty for rigid objects.")
      .def(
          "deformed_vertices",
          [](Runtime& r, int object) {
            check_object(r, object);
            return copy_of(r.runtime().deformed_vertices(object));
          },
          py::arg("object"), "Object i's surface vertices at its current q (V, 3), body frame.")
      .def_property_readonly(
          "body_names",
          [](Runtime& r) {
            std::vector<std::string> names;
            for (const auto& body : r.runtime().world().bodies()) names.push_back(body.name);
            return names;
          },
          "The World's bodies, the scene's objects in order.")
      .def_property_readonly(
          "pairs",
          [](Runtime& r) {
            std::vector<std::pair<int, int>> pairs;
            for (const auto& pair : r.runtime().world().pairs()) {
              pairs.emplace_back(pair.pointshell, pair.field);
            }
            return pairs;
          },
          "(pointshell body, field body) of every pair the World queries each cycle.")
      .def(
          "pair_result",
          [](Runtime& r, int pair) {
            const auto count = static_cast<int>(r.runtime().world().pairs().size());
            if (pair < 0 || pair >= count) {
              throw py::index_error("pair " + std::to_string(pair) +
                                    " out of range: the world "
                                    "queries " +
                                    std::to_string(count));
            }
            return r.runtime().world().pair_result(pair);
          },
          py::arg("pair"), "The last cycle's contact query of pair i (a ContactResult copy).")
      .def("cycle", &Runtime::cycle, py::arg("now"), py::arg("period") = 1e-3,
           R"(One haptic cycle of every hand at simulated time `now` (s) with deadline now +
period, for a loop driven from Python (open_devices() first, close_devices() after): one dict
per hand as run() gives, each array of one row. Runs with the GIL held; an exception from a
Python device is raised after the cycle.)")
      .def(
          "open_devices", [](Runtime& r) { r.runtime().open_devices(); },
          "Opens every hand's device (before cycle()).")
      .def(
          "close_devices", [](Runtime& r) { r.runtime().close_devices(); },
          "Closes every hand's device.")
      .def(
          "grasp", [](Runtime& r, int hand) { return r.runtime().world().grasp(hand); },
          py::arg("hand"),
          "Hand `hand` grasps the free dynamic body its body touches; returns its index or -1.")
      .def(
          "release", [](Runtime& r, int hand) { return r.runtime().world().release(hand); },
          py::arg("hand"), "Hand `hand` lets go of what it grasped; returns how many bodies.")
      .def(
          "surface",
          [](Runtime& r, int object) {
            check_object(r, object);
            return r.runtime().surface(object);
          },
          py::arg("object"), "Object i's surface mesh (body frame), a copy.");
}

void bind_make_device(py::module_& module) {
  module.def(
      "make_device",
      [](const py::handle& description, double rate_hz, const py::object& base_directory) {
        const auto options = read_options(base_directory, py::none(), true);
        return scene::make_device(
            scene::parse_device(scene_text(description), "<python device>", rate_hz, options));
      },
      py::arg("description"), py::arg("rate_hz") = 1000.0, py::arg("base_directory") = py::none(),
      R"(A device from a scene's "device" keys (docs/SCENES.md), as a dict or JSON text:
{"type": "operator", "keyframes": [...], ...} or {"type": "trajectory", "file": "path.csv"}.
Raises SceneError naming the key.)");
}

}  // namespace

void bind_scene(py::module_& module, const py::handle& error) {
  py::register_exception<scene::SceneError>(module, "SceneError", error).doc() =
      "A scene file is invalid; the message names the file and the line or key path.";
  py::register_exception<scene::PrepareError>(module, "PrepareError", error).doc() =
      "Preparing a scene failed; the message names the object, the step and the cause.";
  bind_description(module);
  bind_preparation(module);
  bind_runtime(module);
  bind_make_device(module);
}

}  // namespace khz::python
