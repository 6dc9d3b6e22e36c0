// Scene files of `msmcl scatter` (format: data/scatter/README.md), parsed with nlohmann-json
// (the validation of a ScatterScene is the library's: validate_scatter_scene).
#include "io/scene_json.hpp"
#include "io/atomic_file.hpp"

#include <msmcl/errors.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

namespace msmcl {

namespace {

using nlohmann::json;

/// Deepest nesting of arrays and objects a scene file may have (the format needs 3).
constexpr int max_json_depth = 64;
/// Largest scene file read (a scene is a few hundred bytes).
constexpr std::uint64_t max_scene_bytes = 16 << 20;

/// A value for an error message: scalars as written, containers by kind and size only
/// (printing a container would recurse through all of it).
std::string describe(const json& value) {
    if (value.is_object()) return "an object of " + std::to_string(value.size()) + " keys";
    if (value.is_array()) return "an array of " + std::to_string(value.size()) + " elements";
    std::string text = value.dump();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

/// Rejects keys outside `known` (catches typos such as "extinciton").
void check_keys(const json& object, const std::string& where, std::initializer_list<const char*> known) {
    for (auto it = object.begin(); it != object.end(); ++it) {
        bool found = false;
        for (const char* key : known) found = found || it.key() == key;
        if (!found) {
            std::string list;
            for (const char* key : known) list += (list.empty() ? "" : ", ") + std::string(key);
            throw input_error(where + ": unknown key \"" + it.key() + "\" (expected " + list + ")");
        }
    }
}

const json& member(const json& object, const std::string& where, const char* key) {
    const auto it = object.find(key);
    if (it == object.end()) throw input_error(where + ": missing key \"" + key + "\"");
    return *it;
}

const json& object_member(const json& object, const char* key) {
    const json& value = member(object, "scene", key);
    if (!value.is_object()) throw input_error(std::string(key) + ": expected an object, got " + describe(value));
    return value;
}

double number(const json& value, const std::string& name) {
    if (!value.is_number()) throw input_error(name + ": expected a number, got " + describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) throw input_error(name + ": not finite");
    return x;
}

double number_member(const json& object, const std::string& where, const char* key) {
    return number(member(object, where, key), where + "." + key);
}

double optional_number(const json& object, const std::string& where, const char* key, double fallback) {
    return object.contains(key) ? number(object.at(key), where + "." + key) : fallback;
}

int integer_member(const json& object, const std::string& where, const char* key) {
    const json& value = member(object, where, key);
    const std::string name = where + "." + key;
    if (!value.is_number_integer()) throw input_error(name + ": expected an integer, got " + describe(value));
    const long long x = value.get<long long>();
    if (x < 1 || x > 65536) throw input_error(name + ": " + std::to_string(x) + " is outside [1, 65536]");
    return static_cast<int>(x);
}

Vector3 vector_of(const json& value, const std::string& name) {
    if (!value.is_array() || value.size() != 3)
        throw input_error(name + ": expected an array of 3 numbers, got " + describe(value));
    Vector3 v{};
    for (std::size_t i = 0; i < 3; ++i) v[i] = number(value[i], name + "[" + std::to_string(i) + "]");
    return v;
}

Vector3 vector_member(const json& object, const std::string& where, const char* key) {
    return vector_of(member(object, where, key), where + "." + key);
}

std::string string_member(const json& object, const std::string& where, const char* key, const std::string& fallback) {
    if (!object.contains(key)) return fallback;
    const json& value = object.at(key);
    if (!value.is_string()) throw input_error(where + "." + key + ": expected a string, got " + describe(value));
    return value.get<std::string>();
}

double length(const Vector3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// Sine of the angle between two non-zero vectors.
double sine_between(const Vector3& a, const Vector3& b) {
    const Vector3 c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return length(c) / (length(a) * length(b));
}

ScatterLight parse_light(const json& object) {
    const std::string where = "light";
    check_keys(object, where, {"direction", "up", "center", "width", "height", "near", "far", "depth_range"});
    ScatterLight light;
    light.direction = vector_member(object, where, "direction");
    if (object.contains("up")) {
        light.up = vector_member(object, where, "up");
    } else {
        // World up, unless the light is (nearly) vertical.
        light.up = {0, 1, 0};
        if (length(light.direction) > 0 && sine_between(light.direction, light.up) < 0.1) light.up = {0, 0, -1};
    }
    light.center = vector_member(object, where, "center");
    light.width = number_member(object, where, "width");
    light.height = number_member(object, where, "height");
    light.near = number_member(object, where, "near");
    light.far = number_member(object, where, "far");
    const std::string range = string_member(object, where, "depth_range", "0,1");
    const std::optional<DepthRange> parsed = parse_depth_range(range);
    if (!parsed) throw input_error("light.depth_range: expected \"0,1\" or \"-1,1\", got \"" + range + "\"");
    light.depth_range = *parsed;
    return light;
}

ScatterCamera parse_camera(const json& object) {
    const std::string where = "camera";
    check_keys(object, where,
               {"position", "target", "forward", "up", "fov_y_degrees", "near", "far", "width", "height", "depth"});
    ScatterCamera camera;
    camera.position = vector_member(object, where, "position");
    const bool has_target = object.contains("target"), has_forward = object.contains("forward");
    if (has_target == has_forward) throw input_error("camera: give exactly one of \"target\" and \"forward\"");
    if (has_target) {
        const Vector3 target = vector_member(object, where, "target");
        camera.forward = {target[0] - camera.position[0], target[1] - camera.position[1], target[2] - camera.position[2]};
        if (length(camera.forward) == 0) throw input_error("camera.target: equals camera.position");
    } else {
        camera.forward = vector_member(object, where, "forward");
    }
    if (object.contains("up")) camera.up = vector_member(object, where, "up");
    camera.vertical_fov_degrees = number_member(object, where, "fov_y_degrees");
    camera.near = number_member(object, where, "near");
    camera.far = number_member(object, where, "far");
    camera.width = integer_member(object, where, "width");
    camera.height = integer_member(object, where, "height");
    const std::string depth = string_member(object, where, "depth", "0,1");
    if (depth == "0,1") camera.depth = CameraDepth::zero_one;
    else if (depth == "-1,1") camera.depth = CameraDepth::minus_one_one;
    else if (depth == "linear") camera.depth = CameraDepth::linear;
    else throw input_error("camera.depth: expected \"0,1\", \"-1,1\" or \"linear\", got \"" + depth + "\"");
    return camera;
}

ScatterMedium parse_medium(const json& object) {
    const std::string where = "medium";
    check_keys(object, where, {"extinction", "phase_g", "irradiance"});
    ScatterMedium medium;
    medium.extinction = number_member(object, where, "extinction");
    medium.phase_g = optional_number(object, where, "phase_g", 0.0);
    medium.irradiance = optional_number(object, where, "irradiance", 1.0);
    return medium;
}

/// nlohmann's "[json.exception.parse_error.101] parse error at line 2, column 3: ..." without
/// the bracketed id.
std::string parse_error_text(const std::string& what) {
    const std::size_t bracket = what.find("] ");
    return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

} // namespace

ScatterScene parse_scatter_scene(const std::string& json_text) {
    json document;
    try {
        // Refuse deep nesting while parsing, before it costs memory or recursion later.
        const json::parser_callback_t limit_depth = [](int depth, json::parse_event_t event, json&) {
            if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
                depth >= max_json_depth)
                throw input_error("malformed JSON: nested deeper than " + std::to_string(max_json_depth) + " levels");
            return true;
        };
        document = json::parse(json_text, limit_depth);
    } catch (const json::exception& e) { // syntax errors, and numbers out of range (1e400)
        throw input_error("malformed JSON: " + parse_error_text(e.what()));
    }
    if (!document.is_object()) throw input_error("scene: expected a JSON object at the top level");
    // "geometry" is for the sample-data generator (msmcl-scatter-scene); msmcl ignores it.
    check_keys(document, "scene", {"description", "light", "camera", "medium", "rectified", "geometry"});

    ScatterScene scene;
    try {
        scene.light = parse_light(object_member(document, "light"));
        scene.camera = parse_camera(object_member(document, "camera"));
        scene.medium = parse_medium(object_member(document, "medium"));
        const json& rectified = object_member(document, "rectified");
        check_keys(rectified, "rectified", {"width", "height", "guard_band"});
        scene.rectified_width = integer_member(rectified, "rectified", "width");
        scene.rectified_height = integer_member(rectified, "rectified", "height");
        scene.guard_band = optional_number(rectified, "rectified", "guard_band", 0.05);
    } catch (const json::exception& e) {
        throw input_error("scene: " + parse_error_text(e.what()));
    }
    validate_scatter_scene(scene);
    return scene;
}

ScatterScene load_scatter_scene(const std::string& path) {
    // A scene is a few hundred bytes; refuse anything absurdly large before reading it (and
    // anything but a regular file or standard input, which could make the read wait).
    const std::string text = io::read_input_file(path, {max_scene_bytes, "fixed for scene files", "", ""});
    try {
        return parse_scatter_scene(text);
    } catch (const input_error& e) {
        throw input_error(path + ": " + e.what());
    } catch (const json::exception& e) { // any JSON error the parsing above did not translate
        throw input_error(path + ": " + parse_error_text(e.what()));
    }
}

} // namespace msmcl
