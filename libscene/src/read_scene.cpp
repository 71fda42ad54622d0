#include <khz/scene/read_scene.hpp>

#include "json_reader.hpp"
#include "names.hpp"
#include "option_tables.hpp"
#include "read_common.hpp"
#include "read_device.hpp"
#include "read_object.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string_view>
#include <system_error>
#include <vector>

namespace khz::scene {
namespace {

using detail::in_quotes;
using detail::Json;
using detail::KeyList;
using detail::Location;
using detail::ObjectReader;
using detail::option_table;
using detail::read_options;
using detail::ReadContext;

std::string role_name(contact::HapticObject role) {
  return in_quotes(detail::name_of(role, detail::role_names));
}

contact::HapticObject other_role(contact::HapticObject role) {
  return role == contact::HapticObject::pointshell ? contact::HapticObject::distance_field
                                                   : contact::HapticObject::pointshell;
}

bool has_role(const ObjectDescription& object, contact::HapticObject role) {
  return role == contact::HapticObject::pointshell ? object.roles.pointshell
                                                   : object.roles.distance_field;
}

std::string roles_text(const ObjectDescription& object) {
  if (object.roles.pointshell && object.roles.distance_field) {
    return "\"pointshell\" and \"distance_field\"";
  }
  return object.roles.pointshell ? "\"pointshell\"" : "\"distance_field\"";
}

void read_loop(const ObjectReader& root, SceneDescription& scene) {
  // "duration" is the scene's: how long khz runs, not how the loop runs.
  const auto loop = root.object("loop", KeyList(option_table<haptic::LoopOptions>(), "duration"),
                                {{"rate", "rate_hz"}, {"frequency", "rate_hz"}});
  if (!loop) return;
  read_options(*loop, scene.loop);
  scene.duration = loop->number("duration", scene.duration, detail::at_least(0.0));
}

void read_objects(const ObjectReader& root, const ReadContext& context, SceneDescription& scene) {
  const Json& objects = root.required("objects", "the scene's objects");
  const Location at = root.at("objects");
  if (!objects.is_array() || objects.empty()) {
    at.expected("a non-empty array of objects [{...}]", objects);
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    scene.objects.push_back(detail::read_object(objects[i], at.element(i), context));
    for (std::size_t j = 0; j < i; ++j) {
      if (scene.objects[j].name == scene.objects[i].name) {
        at.element(i).child("name").fail("duplicate object name " +
                                         in_quotes(scene.objects[i].name) + " (objects[" +
                                         std::to_string(j) + "] has it too)");
      }
    }
  }
}

/// The index of the object named `name`, or a failure at `at` that lists or suggests names.
int object_named(const std::string& name, const SceneDescription& scene, const Location& at) {
  std::vector<std::string_view> names;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    names.push_back(scene.objects[i].name);
    if (scene.objects[i].name == name) return static_cast<int>(i);
  }
  std::string message = "no object is named " + in_quotes(name);
  if (const auto match = detail::closest_match(name, names)) {
    message += "; did you mean " + in_quotes(*match) + "?";
  } else {
    message += " (the objects are";
    for (std::size_t i = 0; i < names.size(); ++i) {
      message += (i > 0 ? ", " : " ") + in_quotes(names[i]);
    }
    message += ")";
  }
  at.fail(message);
}

/// One hand: the held object, its role and grasp point, and (in a list) its device.
HapticDescription read_hand(const Json& value, const Location& at, bool in_list,
                            const ReadContext& context, const SceneDescription& scene) {
  std::initializer_list<std::string_view> keys = {"object", "role", "grasp_point", "grasp_button"};
  std::initializer_list<std::string_view> list_keys = {"object", "role", "grasp_point",
                                                       "grasp_button", "device"};
  const ObjectReader haptic(
      value, at, in_list ? list_keys : keys,
      {{"name", "object"}, {"grasp", "grasp_point"}, {"button", "grasp_button"}});
  HapticDescription result;
  result.object = haptic.required_string("object", "the name of the object the user holds");
  result.object_index = object_named(result.object, scene, haptic.at("object"));
  const ObjectDescription& held = scene.objects[static_cast<std::size_t>(result.object_index)];
  if (held.is_dynamic()) {
    haptic.fail("object", "object " + in_quotes(held.name) + " (objects[" +
                              std::to_string(result.object_index) +
                              "]) is a free body (it has \"dynamics\"): a hand holds an object "
                              "without dynamics, and picks a free one up with its grasp_button");
  }
  result.grasp_button = haptic.integer(
      "grasp_button", result.grasp_button,
      detail::with_text(detail::closed(-1, 31), "-1 (none) or a button index in [0, 31]"));
  result.role = held.roles.distance_field ? contact::HapticObject::distance_field
                                          : contact::HapticObject::pointshell;
  if (haptic.has("role")) {
    result.role = detail::to_choice(haptic.value("role"), haptic.at("role"), detail::role_names);
    if (!has_role(held, result.role)) {
      haptic.fail("role", "object " + in_quotes(held.name) + " (objects[" +
                              std::to_string(result.object_index) + "]) has no " +
                              role_name(result.role) + " role (its roles: " + roles_text(held) +
                              ")");
    }
  }
  if (haptic.has("grasp_point")) {
    const Json& grasp = haptic.value("grasp_point");
    if (grasp.is_string()) {
      const std::array<std::string_view, 1> centre{"centre"};
      if (grasp.get_ref<const std::string&>() != "centre") {
        detail::fail_choice(grasp, haptic.at("grasp_point"), centre);
      }
    } else {
      if (!grasp.is_array()) {
        haptic.at("grasp_point").expected("\"centre\" or a body-frame point [x, y, z] in m", grasp);
      }
      result.grasp_at_centre = false;
      result.grasp_point = detail::to_vector3(grasp, haptic.at("grasp_point"));
    }
  }
  if (in_list) {
    result.device = detail::read_device(haptic.has("device") ? &haptic.value("device") : nullptr,
                                        haptic.at("device"), context);
  }
  return result;
}

/// A hand's grasp button must differ from its device's indexing button (both act on a press).
void check_grasp_button(const HapticDescription& hand, const Location& at) {
  if (hand.grasp_button >= 0 && hand.grasp_button == hand.device.safety.index_button) {
    at.fail("button " + std::to_string(hand.grasp_button) +
            " is the device's safety.index_button already; choose another");
  }
}

/// Per object, whether it moves: a hand holds it, or it is a free body.
std::vector<bool> moving_objects(const SceneDescription& scene) {
  std::vector<bool> moving(scene.objects.size(), false);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) moving[i] = scene.objects[i].is_dynamic();
  for (const HapticDescription& hand : scene.haptic) {
    moving[static_cast<std::size_t>(hand.object_index)] = true;
  }
  return moving;
}

/// Whether objects a and b can touch: one's pointshell against the other's field.
bool can_touch(const ObjectDescription& a, const ObjectDescription& b) {
  return (a.roles.pointshell && b.roles.distance_field) ||
         (a.roles.distance_field && b.roles.pointshell);
}

/// The hands ("haptic": one object with the top-level "device", or a list from version 2, each
/// with its device), and that every object touches some moving one.
void read_haptic(const ObjectReader& root, const ReadContext& context, SceneDescription& scene) {
  const Json& haptic = root.required("haptic", "the held object and its grasp point");
  const Location at = root.at("haptic");
  if (haptic.is_array()) {
    if (scene.version < 2) {
      at.fail(
          "a list of held objects needs \"version\": 2 (version 1 holds one object: "
          "\"haptic\": {\"object\": ...})");
    }
    if (haptic.empty()) at.expected("at least one held object [{\"object\": ...}, ...]", haptic);
    if (root.has("device")) {
      root.at("device").fail(
          "with \"haptic\" as a list, each hand names its own device: move this block into "
          "haptic[i].device");
    }
    for (std::size_t i = 0; i < haptic.size(); ++i) {
      scene.haptic.push_back(read_hand(haptic[i], at.element(i), true, context, scene));
      check_grasp_button(scene.haptic.back(), at.element(i).child("grasp_button"));
      for (std::size_t j = 0; j < i; ++j) {
        if (scene.haptic[j].object_index == scene.haptic[i].object_index) {
          at.element(i).child("object").fail("object " + in_quotes(scene.haptic[i].object) +
                                             " is held by haptic[" + std::to_string(j) +
                                             "] already; a hand holds an object of its own");
        }
      }
    }
  } else {
    scene.haptic.push_back(read_hand(haptic, at, false, context, scene));
    scene.haptic.front().device = detail::read_device(
        root.has("device") ? &root.value("device") : nullptr, root.at("device"), context);
    check_grasp_button(scene.haptic.front(), at.child("grasp_button"));
  }
  // Every object touches some other through a complementary role, one of the two moving (held
  // or free): first the fixed objects (the usual mistake: a role missing), then the held ones. A
  // free object always does: it meets the held object or the held object's partner.
  const std::vector<bool> moving = moving_objects(scene);
  const auto touches = [&](std::size_t i) {
    for (std::size_t j = 0; j < scene.objects.size(); ++j) {
      if (j != i && (moving[i] || moving[j]) && can_touch(scene.objects[i], scene.objects[j])) {
        return true;
      }
    }
    return false;
  };
  const HapticDescription& first = scene.haptic.front();
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (moving[i] || touches(i)) continue;
    root.at("objects").element(i).child("roles").fail(
        "object " + in_quotes(scene.objects[i].name) + " touches nothing: the held object " +
        in_quotes(first.object) + " plays " + role_name(first.role) +
        ", so the other objects need the " + role_name(other_role(first.role)) + " role");
  }
  for (std::size_t h = 0; h < scene.haptic.size(); ++h) {
    const HapticDescription& hand = scene.haptic[h];
    if (touches(static_cast<std::size_t>(hand.object_index))) continue;
    const Location object_at =
        haptic.is_array() ? at.element(h).child("object") : at.child("object");
    object_at.fail("the held object " + in_quotes(hand.object) + " (objects[" +
                   std::to_string(hand.object_index) + "]) plays " + role_name(hand.role) +
                   ", but there is no other object with the " + role_name(other_role(hand.role)) +
                   " role for it to touch");
  }
}

/// `parent`'s "friction" block, if it has one (a coefficient's other names hinted).
std::optional<ObjectReader> friction_block(const ObjectReader& parent) {
  return parent.object("friction", option_table<contact::FrictionOptions>().keys(),
                       {{"static_coefficient", "static"},
                        {"kinetic_coefficient", "kinetic"},
                        {"mu_s", "static"},
                        {"mu_k", "kinetic"},
                        {"dynamic", "kinetic"}});
}

/// A "friction" block over `friction` (keys left out keep its values).
void read_friction(const ObjectReader& block, contact::FrictionOptions& friction) {
  option_table<contact::FrictionOptions>().read(block, friction);
  if (friction.kinetic_coefficient > friction.static_coefficient) {
    block.fail("kinetic",
               "expected at most static = " + detail::format_number(friction.static_coefficient) +
                   " (a sliding contact pulls no harder than a stuck one holds), got " +
                   detail::format_number(friction.kinetic_coefficient));
  }
}

/// "contact.pairs": each entry names two objects that touch, once, and their own friction.
void read_pairs(const ObjectReader& contact, SceneDescription& scene) {
  const Json* pairs = contact.array("pairs");
  if (pairs == nullptr) return;
  const std::vector<bool> moving = moving_objects(scene);
  for (std::size_t i = 0; i < pairs->size(); ++i) {
    const Location at = contact.at("pairs").element(i);
    const ObjectReader entry((*pairs)[i], at, {"objects", "friction"});
    const Json& names = entry.required("objects", "the two objects' names, [\"a\", \"b\"]");
    if (!names.is_array() || names.size() != 2 || !names[0].is_string() || !names[1].is_string()) {
      entry.at("objects").expected("two object names [\"a\", \"b\"]", names);
    }
    PairDescription pair;
    for (std::size_t k = 0; k < 2; ++k) {
      pair.objects[k] = names[k].get<std::string>();
      pair.object_indices[k] = object_named(pair.objects[k], scene, entry.at("objects").element(k));
    }
    const auto a = static_cast<std::size_t>(pair.object_indices[0]);
    const auto b = static_cast<std::size_t>(pair.object_indices[1]);
    if (a == b) entry.fail("objects", "names " + in_quotes(pair.objects[0]) + " twice");
    if (!(moving[a] || moving[b])) {
      entry.fail("objects", "neither " + in_quotes(pair.objects[0]) + " nor " +
                                in_quotes(pair.objects[1]) +
                                " moves (held or free), and fixed objects do not touch each other");
    }
    if (!can_touch(scene.objects[a], scene.objects[b])) {
      entry.fail("objects", in_quotes(pair.objects[0]) + " (" + roles_text(scene.objects[a]) +
                                ") and " + in_quotes(pair.objects[1]) + " (" +
                                roles_text(scene.objects[b]) +
                                ") never touch: one needs the pointshell role and the other the "
                                "distance_field role");
    }
    for (std::size_t j = 0; j < scene.pairs.size(); ++j) {
      const auto& other = scene.pairs[j].object_indices;
      if ((other[0] == pair.object_indices[0] && other[1] == pair.object_indices[1]) ||
          (other[0] == pair.object_indices[1] && other[1] == pair.object_indices[0])) {
        entry.fail("objects", "this pair is contact.pairs[" + std::to_string(j) +
                                  "] already; give each pair once");
      }
    }
    pair.friction = scene.contact.friction;
    if (const auto friction = friction_block(entry)) {
      read_friction(*friction, pair.friction);
    }
    scene.pairs.push_back(pair);
  }
}

void read_contact(const ObjectReader& root, SceneDescription& scene) {
  contact::ContactOptions& options = scene.contact;
  options.haptic_object = scene.haptic.front().role;
  const auto contact = root.object(
      "contact",
      KeyList(option_table<contact::ContactOptions>(), "degradation", "coherence", "friction",
              "pairs"),
      {{"haptic_object", "haptic.role"}, {"temporal_coherence", "coherence"}, {"pair", "pairs"}});
  if (!contact) return;
  read_options(*contact, options);
  // Which keys of these two blocks apply depends on their first setting, read first.
  const auto& degradation_settings = option_table<contact::DegradationOptions>();
  if (const auto degradation =
          contact->object("degradation", degradation_settings.keys(),
                          {{"budget", "budget_microseconds"}, {"threshold", "warm_threshold"}})) {
    contact::DegradationOptions& d = options.degradation;
    using Mode = contact::DegradationOptions::Mode;
    degradation_settings.read(*degradation, d, "mode");
    const std::string mode = in_quotes(detail::name_of(d.mode, detail::degradation_modes));
    if (d.mode != Mode::node_count) {
      degradation->refuse({"warm_threshold"}, "mode \"node_count\" (mode is " + mode + ")");
    }
    if (d.mode != Mode::time_budget) {
      degradation->refuse({"budget_microseconds"}, "mode \"time_budget\" (mode is " + mode + ")");
    }
    if (d.mode == Mode::none) {
      degradation->refuse({"cold_fraction", "contact_weight"},
                          "modes \"node_count\" and \"time_budget\" (mode is \"none\")");
    }
    degradation_settings.read(*degradation, d);
  }
  const auto& coherence_settings = option_table<contact::CoherenceOptions>();
  if (const auto coherence = contact->object("coherence", coherence_settings.keys())) {
    contact::CoherenceOptions& c = options.coherence;
    coherence_settings.read(*coherence, c, "enabled");
    if (!c.enabled) {
      coherence->refuse({"max_translation", "max_rotation", "max_deformation",
                         "max_field_deformation", "max_skip"},
                        "enabled temporal coherence (\"enabled\": true)");
    }
    coherence_settings.read(*coherence, c);
  }
  if (const auto friction = friction_block(*contact)) {
    read_friction(*friction, options.friction);
  }
  read_pairs(*contact, scene);
}

/// "dynamics": how the free objects move; only in a scene that has one.
void read_dynamics(const ObjectReader& root, SceneDescription& scene) {
  scene.dynamics.time_step = 1.0 / scene.loop.rate_hz;
  if (!root.has("dynamics")) return;
  if (!scene.has_free_objects()) {
    root.fail("dynamics",
              "settings for free bodies, but no object has \"dynamics\" (objects[i].dynamics "
              "makes one)");
  }
  detail::read_block(root, "dynamics", scene.dynamics,
                     {{"time_step", "loop.rate_hz"}, {"damping", "contact_damping"}});
}

void read_coupling(const ObjectReader& root, SceneDescription& scene) {
  haptic::CouplingOptions& options = scene.coupling;
  options.period = 1.0 / scene.loop.rate_hz;
  detail::read_block(root, "coupling", options,
                     {{"period", "loop.rate_hz"}, {"damping", "static_damping"}});
  if (options.stiffness > options.device_max_stiffness) {
    root.at("coupling")
        .child("stiffness")
        .fail("expected at most device_max_stiffness = " +
              detail::format_number(options.device_max_stiffness) +
              " N/m (k_VC bounds the stiffness the device renders, thesis §4.7), got " +
              detail::format_number(options.stiffness));
  }
}

/// The library's own checks of what the scene maps onto, after the reader's: a failure here
/// means the reader missed a rule, and still names the block.
template <typename Options>
void check_with_library(const Options& options, const Location& at) {
  try {
    options.validate();
  } catch (const reduced::Error& error) {
    at.fail(error.what());
  }
}

SceneDescription parse(std::string_view text, const ReadContext& context) {
  const Json json = detail::parse_json(text, context.source);
  const ObjectReader root(json, Location{context.source, {}},
                          {"version", "description", "objects", "haptic", "contact", "coupling",
                           "device", "loop", "threads", "dynamics"},
                          {{"gravity", "dynamics"}});
  SceneDescription scene;
  scene.source = context.source;
  scene.base_directory = context.base_directory;
  if (root.has("version")) {
    const Json& version = root.value("version");
    if (!(version == 1) && !(version == 2)) {
      root.at("version").expected("1 or 2 (the scene format versions so far)", version);
    }
    scene.version = version.get<int>();
  }
  if (root.has("description")) {
    const Json& description = root.value("description");
    if (!description.is_string()) root.at("description").expected("a string", description);
    scene.description = description.get<std::string>();
  }
  scene.threads = root.integer("threads", scene.threads, detail::at_least(1));
  read_loop(root, scene);
  ReadContext derived = context;
  derived.rate_hz = scene.loop.rate_hz;
  read_objects(root, derived, scene);
  read_haptic(root, derived, scene);
  read_contact(root, scene);
  read_coupling(root, scene);
  read_dynamics(root, scene);
  check_with_library(scene.loop, root.at("loop"));
  check_with_library(scene.dynamics, root.at("dynamics"));
  check_with_library(scene.contact, root.at("contact"));
  check_with_library(scene.coupling, root.at("coupling"));
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].is_reduced()) {
      check_with_library(scene.objects[i].model.integrator,
                         root.at("objects").element(i).child("model").child("integrator"));
    }
  }
  return scene;
}

ReadContext make_context(const std::string& source, const std::filesystem::path& base,
                         const SceneReadOptions& options) {
  ReadContext context;
  context.source = source;
  context.base_directory = std::filesystem::absolute(base).lexically_normal();
  context.cgal_mesh_dir =
      options.cgal_mesh_dir.empty() ? default_cgal_mesh_dir() : options.cgal_mesh_dir;
  context.check_files = options.check_files;
  return context;
}

}  // namespace

std::filesystem::path default_cgal_mesh_dir() {
  if (const char* directory = std::getenv("KHZ_CGAL_MESH_DIR");
      directory != nullptr && *directory != '\0') {
    return directory;
  }
#ifdef KHZ_SCENE_CGAL_MESH_DIR
  return KHZ_SCENE_CGAL_MESH_DIR;
#else
  return {};
#endif
}

namespace {

/// The whole file as text. @throws reduced::IoError naming the file (`what`: "scene file").
std::string read_text_file(const std::filesystem::path& file, const std::string& what) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw reduced::IoError(
        "cannot read " + what + " " + file.string() +
        (std::filesystem::exists(file, error) ? ": not a regular file" : ": no such file"));
  }
  std::ifstream stream(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
  if (!stream && !stream.eof()) {
    throw reduced::IoError("cannot read " + what + " " + file.string());
  }
  return text;
}

std::filesystem::path base_of(const std::filesystem::path& file, const SceneReadOptions& options) {
  return options.base_directory.empty() ? std::filesystem::absolute(file).parent_path()
                                        : options.base_directory;
}

/// Where relative paths in text that comes from no file resolve.
std::filesystem::path text_base(const SceneReadOptions& options) {
  return options.base_directory.empty() ? std::filesystem::current_path() : options.base_directory;
}

DeviceDescription parse_device(std::string_view text, ReadContext context, double rate_hz) {
  context.rate_hz = rate_hz;
  const Json json = detail::parse_json(text, context.source);
  return detail::read_device(&json, Location{context.source, {}}, context);
}

}  // namespace

SceneDescription read_scene(const std::filesystem::path& file, const SceneReadOptions& options) {
  const std::string text = read_text_file(file, "scene file");
  return parse(text, make_context(file.string(), base_of(file, options), options));
}

DeviceDescription read_device_file(const std::filesystem::path& file, double rate_hz,
                                   const SceneReadOptions& options) {
  const std::string text = read_text_file(file, "device file");
  return parse_device(text, make_context(file.string(), base_of(file, options), options), rate_hz);
}

SceneDescription parse_scene(std::string_view text, const std::string& source,
                             const SceneReadOptions& options) {
  return parse(text, make_context(source, text_base(options), options));
}

DeviceDescription parse_device(std::string_view text, const std::string& source, double rate_hz,
                               const SceneReadOptions& options) {
  return parse_device(text, make_context(source, text_base(options), options), rate_hz);
}

}  // namespace khz::scene
