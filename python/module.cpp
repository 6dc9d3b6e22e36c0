// The Python module msmcl (docs/python.md): the C++ library and msmcl_io behind numpy arrays.
// Inputs are copied once into the library's host containers (converted to float32 on the way
// where they are of another real type); results are moved into numpy arrays without a copy;
// a Texture's or table's arrays are views of its words. Every device call runs with the GIL
// released; library exceptions become msmcl.Error / InputError / DeviceError.
#include "cli/commands.hpp"
#include "cli/info_command.hpp"
#include "cli/texture_files.hpp"
#include "io/dds.hpp"
#include "io/exr_io.hpp"
#include "io/gpu_image.hpp"
#include "io/ktx2.hpp"
#include "io/scene_json.hpp"

#include <msmcl/device_math.hpp>
#include <msmcl/msmcl.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace pybind11::literals;

namespace msmcl::python {
namespace {

// ---- Exceptions: one Python class per kind of library error (docs/python.md, Errors).

PyObject* error_type = nullptr;
PyObject* input_error_type = nullptr;
PyObject* device_error_type = nullptr;

/// Raises `type(message)` with the OpenCL details as attributes (None where there are none).
void raise(PyObject* type, const char* message, py::object cl_error = py::none(), py::object code = py::none(),
           py::object build_log = py::none()) {
    py::object exception = py::reinterpret_borrow<py::object>(type)(message);
    exception.attr("cl_error") = std::move(cl_error);
    exception.attr("code") = std::move(code);
    exception.attr("build_log") = std::move(build_log);
    PyErr_SetObject(type, exception.ptr());
}

void translate(std::exception_ptr pointer) {
    try {
        if (pointer) std::rethrow_exception(pointer);
    } catch (const build_error& e) {
        raise(device_error_type, e.what(), py::str(e.name()), py::int_(e.code()), py::str(e.log()));
    } catch (const opencl_error& e) {
        raise(device_error_type, e.what(), py::str(e.name()), py::int_(e.code()));
    } catch (const device_error& e) {
        raise(device_error_type, e.what());
    } catch (const input_error& e) {
        raise(input_error_type, e.what());
    } catch (const cli::usage_error& e) {
        raise(input_error_type, e.what());
    } catch (const error& e) {
        raise(error_type, e.what());
    }
}

PyObject* new_exception(py::module_& m, const char* name, const char* doc, py::tuple bases) {
    py::dict attributes("cl_error"_a = py::none(), "code"_a = py::none(), "build_log"_a = py::none());
    const std::string qualified = std::string("msmcl.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), attributes.ptr());
    if (!type) throw py::error_already_set();
    m.attr(name) = py::reinterpret_borrow<py::object>(type);
    return type;
}

// ---- Arrays in: checked, converted once.

std::string shape_text(const py::array& array) {
    std::string text = "(";
    for (py::ssize_t i = 0; i < array.ndim(); ++i) text += (i ? ", " : "") + std::to_string(array.shape(i));
    return text + (array.ndim() == 1 ? ",)" : ")");
}

/// `object` as a numpy array of real numbers with one of `dimensions` axes, else input_error
/// naming what was expected (`expected`, e.g. "float32 array of shape (H, W) or (H, W, S)")
/// and what came.
py::array real_array(const py::handle& object, const char* name, const char* expected,
                     std::initializer_list<int> dimensions) {
    py::array array = py::module_::import("numpy").attr("asarray")(object);
    const char kind = array.dtype().kind();
    bool dimensions_ok = false;
    for (int d : dimensions) dimensions_ok = dimensions_ok || array.ndim() == d;
    if ((kind != 'f' && kind != 'i' && kind != 'u') || !dimensions_ok)
        throw input_error(std::string(name) + " must be a " + expected + ", got " +
                          py::str(array.dtype()).cast<std::string>() + " of shape " + shape_text(array));
    return array;
}

/// The values of `array` as float32 in C order, in a vector of their own: one pass that
/// converts and copies (numpy.copyto into a view of the vector).
std::vector<float> float_values(const py::array& array) {
    std::vector<float> values(static_cast<std::size_t>(array.size()));
    std::vector<py::ssize_t> shape(array.shape(), array.shape() + array.ndim());
    // A view of the vector's memory: the capsule keeps numpy from owning (or copying) it.
    py::array_t<float> view(shape, values.data(), py::capsule(values.data(), [](void*) {}));
    py::module_::import("numpy").attr("copyto")(view, array, "casting"_a = "unsafe");
    return values;
}

/// A result vector moved into a numpy array of `shape` (no copy): the array owns it.
template <typename T>
py::array_t<T> to_numpy(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    py::capsule owner(owned, [](void* pointer) { delete static_cast<std::vector<T>*>(pointer); });
    return py::array_t<T>(shape, owned->data(), owner);
}

DepthRange depth_range_of(const py::handle& object) {
    // (0, 1), (-1, 1), "0,1" or "-1,1".
    std::string text;
    if (py::isinstance<py::str>(object)) {
        text = object.cast<std::string>();
    } else {
        const py::tuple pair = py::tuple(py::module_::import("builtins").attr("tuple")(object));
        if (pair.size() == 2) text = py::str("{:g},{:g}").format(pair[0], pair[1]).cast<std::string>();
    }
    const std::optional<DepthRange> range = parse_depth_range(text);
    if (!range) throw input_error("depth_range must be (0, 1) or (-1, 1), got " + py::repr(object).cast<std::string>());
    return *range;
}

py::tuple depth_range_tuple(DepthRange range) {
    return range == DepthRange::zero_one ? py::make_tuple(0, 1) : py::make_tuple(-1, 1);
}

template <typename Enum>
Enum parse_name(const std::string& text, std::optional<Enum> (*parse)(std::string_view), const char* what,
                const char* expected) {
    const std::optional<Enum> value = parse(text);
    if (!value) throw input_error(std::string("unknown ") + what + " '" + text + "' (expected " + expected + ")");
    return *value;
}

const char* depth_expected = "float32 array of shape (H, W) or (H, W, S) (S samples per texel: 1, 2, 4, 8 or 16)";

/// A depth map (H, W) or (H, W, S).
DepthImage depth_image(const py::handle& object, const char* name = "depth") {
    const py::array array = real_array(object, name, depth_expected, {2, 3});
    DepthImage depth;
    depth.height = static_cast<int>(array.shape(0));
    depth.width = static_cast<int>(array.shape(1));
    depth.samples = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
    depth.depth = float_values(array);
    return depth;
}

/// A texture array's maps: an array (L, H, W) or (L, H, W, S), or a sequence of (H, W[, S]) maps.
DepthImage depth_stack(const py::handle& object) {
    if (!py::isinstance<py::array>(object) && py::isinstance<py::sequence>(object) && !py::isinstance<py::str>(object)) {
        const py::sequence maps = py::reinterpret_borrow<py::sequence>(object);
        if (maps.size() == 0) throw input_error("depths: an empty sequence of maps");
        DepthImage stack = depth_image(maps[0], "depths[0]");
        for (std::size_t i = 1; i < maps.size(); ++i) {
            const std::string name = "depths[" + std::to_string(i) + "]";
            const DepthImage map = depth_image(maps[i], name.c_str());
            if (map.width != stack.width || map.height != stack.height || map.samples != stack.samples)
                throw input_error(name + " is " + std::to_string(map.width) + "x" + std::to_string(map.height) + " with " +
                                  std::to_string(map.samples) + " samples, depths[0] " + std::to_string(stack.width) +
                                  "x" + std::to_string(stack.height) + " with " + std::to_string(stack.samples));
            stack.depth.insert(stack.depth.end(), map.depth.begin(), map.depth.end());
        }
        stack.layers = static_cast<int>(maps.size());
        return stack;
    }
    const py::array array =
        real_array(object, "depths", "float32 array of shape (L, H, W) or (L, H, W, S), or a sequence of (H, W[, S]) maps",
                   {3, 4});
    DepthImage stack;
    stack.layers = static_cast<int>(array.shape(0));
    stack.height = static_cast<int>(array.shape(1));
    stack.width = static_cast<int>(array.shape(2));
    stack.samples = array.ndim() == 4 ? static_cast<int>(array.shape(3)) : 1;
    stack.depth = float_values(array);
    return stack;
}

/// Translucent layers: a sequence of (depth, opacity) pairs shaped like the depth map.
std::vector<TranslucentLayer> translucent_layers(const py::handle& object, const DepthImage& depth) {
    std::vector<TranslucentLayer> layers;
    if (object.is_none()) return layers;
    std::size_t k = 0;
    for (const py::handle pair : object) {
        const py::tuple items = py::tuple(py::module_::import("builtins").attr("tuple")(pair));
        const std::string name = "layers[" + std::to_string(k++) + "]";
        if (items.size() != 2) throw input_error(name + " must be a pair (depth, opacity)");
        const DepthImage z = depth_image(items[0], (name + " depth").c_str());
        const DepthImage a = depth_image(items[1], (name + " opacity").c_str());
        for (const DepthImage* part : {&z, &a})
            if (part->width != depth.width || part->height != depth.height || part->samples != depth.samples)
                throw input_error(name + " must have the depth map's shape (" + std::to_string(depth.height) + ", " +
                                  std::to_string(depth.width) +
                                  (depth.samples > 1 ? ", " + std::to_string(depth.samples) : std::string()) + ")");
        layers.push_back({std::move(z.depth), std::move(a.depth)});
    }
    return layers;
}

/// Receivers (N, 3) or (H, W, 3) of u, v (texels) and depth; the image width for dither
/// (0 for a flat list), and the shape of one value per receiver.
struct ReceiverArray {
    Receivers points;
    std::uint32_t screen_width = 0;
    std::vector<py::ssize_t> shape;
};

ReceiverArray receiver_array(const py::handle& object) {
    const py::array array = real_array(object, "receivers", "float32 array of shape (N, 3) or (H, W, 3) of u, v, depth",
                                       {2, 3});
    if (array.shape(array.ndim() - 1) != 3)
        throw input_error("receivers must be a float32 array of shape (N, 3) or (H, W, 3) of u, v, depth, got shape " +
                          shape_text(array));
    ReceiverArray receivers;
    receivers.shape.assign(array.shape(), array.shape() + array.ndim() - 1);
    if (array.ndim() == 3) receivers.screen_width = static_cast<std::uint32_t>(array.shape(1));
    const std::vector<float> uvz = float_values(array);
    const std::size_t count = uvz.size() / 3;
    for (std::vector<float>* plane : {&receivers.points.u, &receivers.points.v, &receivers.points.z})
        plane->resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        receivers.points.u[i] = uvz[3 * i];
        receivers.points.v[i] = uvz[3 * i + 1];
        receivers.points.z[i] = uvz[3 * i + 2];
    }
    return receivers;
}

// ---- The classes that hold results: a texture or table and what a file records of it.

struct TextureObject {
    Texture texture;
    io::TextureInfo info;
};

struct SatObject {
    SatTable table;
    io::SatInfo info;
};

/// A view of `words` as `dtype` with `shape` (C order), kept alive by `owner`.
py::array words_view(py::object owner, const py::dtype& dtype, std::vector<py::ssize_t> shape, void* data) {
    return py::array(dtype, shape, data, owner);
}

/// Leading axes of a (possibly layered) image: (H, W) or (L, H, W).
std::vector<py::ssize_t> image_axes(int layers, int height, int width, bool array) {
    if (array) return {layers, height, width};
    return {height, width};
}

bool is_array(const Texture& texture) { return texture.layers != 1; }

py::array texture_array(py::object self) {
    TextureObject& object = self.cast<TextureObject&>();
    Texture& t = object.texture;
    std::vector<py::ssize_t> shape = image_axes(t.layers, t.height, t.width, is_array(t));
    // The texel's channels in their storage type (docs/formats.md); nlq32's packed word whole.
    const auto channels = [&](py::dtype type, py::ssize_t count) {
        shape.push_back(count);
        return words_view(self, type, shape, t.words.data());
    };
    switch (t.format) {
    case Format::moments128:
    case Format::evsm4_128: return channels(py::dtype::of<float>(), 4);
    case Format::vsm64: return channels(py::dtype::of<float>(), 2);
    case Format::esm32: return words_view(self, py::dtype::of<float>(), shape, t.words.data());
    case Format::msm64:
    case Format::nlq64: return channels(py::dtype::of<std::uint16_t>(), 4);
    case Format::vsm32: return channels(py::dtype::of<std::uint16_t>(), 2);
    case Format::evsm2_32: return channels(py::dtype("float16"), 2);
    case Format::evsm4_64: return channels(py::dtype("float16"), 4);
    case Format::nlq32: break;
    }
    return words_view(self, py::dtype::of<std::uint32_t>(), shape, t.words.data());
}

py::array texture_words(py::object self) {
    Texture& t = self.cast<TextureObject&>().texture;
    std::vector<py::ssize_t> shape = image_axes(t.layers, t.height, t.width, is_array(t));
    shape.push_back(static_cast<py::ssize_t>(texel_words(t.format)));
    return words_view(self, py::dtype::of<std::uint32_t>(), shape, t.words.data());
}

/// Per texel its decoded quantities as msmcl info decodes them (b1..b4 for moments128 and msm64,
/// y1, y2, v2, xi4 for nlq64 and nlq32, ...; decoded_quantities), 0 beyond a format's count.
py::array_t<double> texture_decode(const TextureObject& object) {
    const Texture& t = object.texture;
    const std::size_t texels = static_cast<std::size_t>(t.width) * t.height * t.layers;
    std::vector<double> values(4 * texels);
    float texel[4];
    for (std::size_t i = 0; i < texels; ++i) {
        texel[0] = texel[1] = texel[2] = texel[3] = 0.0f;
        decode_texel(t, i, texel);
        for (int c = 0; c < 4; ++c) values[4 * i + c] = texel[c];
    }
    std::vector<py::ssize_t> shape = image_axes(t.layers, t.height, t.width, is_array(t));
    shape.push_back(4);
    return to_numpy(std::move(values), shape);
}

py::array sat_array(py::object self) {
    SatTable& t = self.cast<SatObject&>().table;
    std::vector<py::ssize_t> shape = image_axes(t.layers, t.height, t.width, t.layers != 1);
    shape.push_back(4);
    return words_view(self, py::dtype::of<std::uint32_t>(), shape, t.words.data());
}

// ---- Devices.

py::dict device_dict(const DeviceInfo& d) {
    return py::dict("index"_a = std::to_string(d.platform_index) + ":" + std::to_string(d.device_index),
                    "name"_a = d.name, "type"_a = d.is_gpu ? "gpu" : d.is_cpu ? "cpu" : "other",
                    "platform"_a = d.platform_name, "vendor"_a = d.vendor, "driver_version"_a = d.driver_version,
                    "opencl_version"_a = d.opencl_version, "compute_units"_a = d.compute_units,
                    "global_mem_bytes"_a = d.global_mem_bytes, "local_mem_bytes"_a = d.local_mem_bytes,
                    "max_work_group_size"_a = d.max_work_group_size,
                    "host_unified_memory"_a = d.host_unified_memory);
}

std::unique_ptr<Context> make_context(const py::object& device, const py::object& platform) {
    DeviceSelection selection;
    if (!device.is_none()) selection.device = py::str(device).cast<std::string>();
    if (!platform.is_none()) selection.platform = py::str(platform).cast<std::string>();
    // A device that is named and matches nothing is an error, as for msmcl --device.
    selection.strict = !device.is_none() || !platform.is_none();
    py::gil_scoped_release released;
    return std::make_unique<Context>(selection);
}

// ---- Operations.

TextureObject run_filter(Context& context, DepthImage depth, const std::vector<TranslucentLayer>& layers,
                         const std::string& format, float sigma, const py::object& depth_range,
                         const std::string& kernel) {
    FilterOptions options;
    options.format = parse_name<Format>(format, parse_format, "format", "moments128, msm64, nlq64 or nlq32");
    options.sigma = sigma;
    options.depth_range = depth_range_of(depth_range);
    options.kernel = parse_name<FilterKernel>(kernel, parse_filter_kernel, "kernel",
                                              "automatic, fused_paper, fused_cpu or three_pass");
    TextureObject result;
    result.info = io::TextureInfo{sigma, depth.samples, options.depth_range};
    py::gil_scoped_release released;
    result.texture = filter(context, depth, layers, options);
    return result;
}

SatObject run_build_sat(Context& context, const DepthImage& depth, const std::vector<TranslucentLayer>& layers,
                        std::uint32_t max_kernel, const py::object& depth_range, const std::string& kernel) {
    SatOptions options;
    options.max_kernel_texels = max_kernel;
    options.depth_range = depth_range_of(depth_range);
    options.kernel = parse_name<SatKernel>(kernel, parse_sat_kernel, "kernel",
                                           "automatic, tiled_gpu, tiled_cpu or row_per_thread");
    SatObject result;
    result.info = io::SatInfo{options.depth_range, depth.samples};
    py::gil_scoped_release released;
    result.table = build_sat(context, depth, layers, options);
    return result;
}

py::array_t<float> run_shade(Context& context, const TextureObject& map, const py::handle& receivers_object,
                             const std::string& lookup, float depth_bias, const py::object& depth_range,
                             std::uint32_t frame) {
    if (map.texture.layers != 1)
        throw input_error("shade takes one map: this texture array has " + std::to_string(map.texture.layers) +
                          " layers (shade texture.layer(i))");
    ShadeOptions options;
    options.lookup = parse_name<Lookup>(lookup, parse_lookup, "lookup", "nearest, bilinear or dither");
    options.depth_bias = depth_bias;
    options.depth_range = depth_range.is_none() ? map.info.depth_range : depth_range_of(depth_range);
    options.frame = frame;
    ReceiverArray receivers = receiver_array(receivers_object);
    options.screen_width = receivers.screen_width;
    std::vector<float> intensity;
    {
        py::gil_scoped_release released;
        intensity = shade(context, map.texture, receivers.points, options);
    }
    return to_numpy(std::move(intensity), receivers.shape);
}

py::array_t<float> run_soft_shade(Context& context, const SatObject& table, const py::handle& receivers_object,
                                  float light_size, int search_size, float min_filter_size, float depth_bias,
                                  const py::object& depth_range, float receiver_weight, int filter_parts,
                                  bool published) {
    if (table.table.layers != 1) throw input_error("soft_shade takes one table: this one has " +
                                                   std::to_string(table.table.layers) + " layers (table.layer(i))");
    SoftShadowOptions options;
    options.light_size = light_size;
    options.search_size = search_size;
    options.min_filter_size = min_filter_size;
    options.depth_bias = depth_bias;
    options.depth_range = depth_range.is_none() ? table.info.depth_range : depth_range_of(depth_range);
    options.receiver_blocker_weight = published ? 0.0f : receiver_weight;
    options.filter_parts = published ? 1 : filter_parts;
    ReceiverArray receivers = receiver_array(receivers_object);
    std::vector<float> intensity;
    {
        py::gil_scoped_release released;
        intensity = soft_shade(context, table.table, receivers.points, options);
    }
    return to_numpy(std::move(intensity), receivers.shape);
}

ScatterScene scene_of(const py::handle& scene) {
    if (py::isinstance<py::dict>(scene))
        return parse_scatter_scene(py::module_::import("json").attr("dumps")(scene).cast<std::string>());
    if (py::isinstance<py::str>(scene) || py::hasattr(scene, "__fspath__"))
        return load_scatter_scene(py::module_::import("os").attr("fspath")(scene).cast<std::string>());
    throw input_error("scene must be a dict with the keys of a scene file (light, camera, medium, rectified) or a "
                      "path to one");
}

py::array_t<float> run_scatter(Context& context, const py::handle& scene_object, const py::handle& shadow_map_object,
                               const py::handle& camera_depth_object, int moments, bool filtered, float sigma,
                               const py::object& beta, const std::string& kernel, const std::string& filter_kernel,
                               int ray_march, std::uint32_t jitter) {
    const ScatterScene scene = scene_of(scene_object);
    ScatterOptions options;
    if (moments != 4 && moments != 6) throw input_error("moments must be 4 or 6, got " + std::to_string(moments));
    options.moments = moments;
    options.filtered = filtered;
    if (!(sigma >= 0.0f)) throw input_error("sigma must be >= 0");
    options.filter_sigma = sigma;
    if (py::isinstance<py::str>(beta) && beta.cast<std::string>() == "adaptive") {
        options.beta = -1.0f;
    } else {
        options.beta = beta.cast<float>();
        if (!(options.beta >= 0.0f && options.beta <= 1.0f)) throw input_error("beta must be 'adaptive' or in [0, 1]");
    }
    options.kernel = parse_name<ScatterKernel>(kernel, parse_scatter_kernel, "kernel", "automatic, rows_gpu or rows_cpu");
    options.filter_kernel = parse_name<FilterKernel>(filter_kernel, parse_filter_kernel, "filter_kernel",
                                                     "automatic, fused_paper, fused_cpu or three_pass");
    if (ray_march < 0) throw input_error("ray_march must be >= 0 (0: the prefiltered method)");
    const DepthImage shadow_map = depth_image(shadow_map_object, "shadow_map");
    const py::array camera = real_array(camera_depth_object, "camera_depth",
                                        "float32 array of shape (H, W), the camera's size", {2});
    if (camera.shape(0) != scene.camera.height || camera.shape(1) != scene.camera.width)
        throw input_error("camera_depth is " + shape_text(camera) + ", the scene's camera (" +
                          std::to_string(scene.camera.height) + ", " + std::to_string(scene.camera.width) + ")");
    const std::vector<float> camera_depth = float_values(camera);
    std::vector<float> radiance;
    {
        py::gil_scoped_release released;
        validate_scatter_inputs(scene, shadow_map, camera_depth);
        radiance = ray_march > 0 ? scatter_ray_march(context, scene, shadow_map, camera_depth, ray_march, jitter)
                                 : scatter(context, scene, shadow_map, camera_depth, options);
    }
    return to_numpy(std::move(radiance), {scene.camera.height, scene.camera.width});
}

// ---- Files.

std::string path_of(const py::handle& path) {
    return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

py::object read_depth(const py::handle& path_object, const py::object& depth_range, bool translucent) {
    const std::string path = path_of(path_object);
    const DepthRange range = depth_range_of(depth_range);
    io::TranslucentDepth layered;
    {
        py::gil_scoped_release released;
        layered = io::read_translucent_depth_exr(path, range);
    }
    DepthImage& d = layered.depth;
    std::vector<py::ssize_t> shape{d.height, d.width};
    if (d.samples > 1) shape.push_back(d.samples);
    py::array depth = to_numpy(std::move(d.depth), shape);
    if (!translucent) return depth;
    py::list layers;
    for (TranslucentLayer& layer : layered.layers)
        layers.append(py::make_tuple(to_numpy(std::move(layer.depth), shape), to_numpy(std::move(layer.opacity), shape)));
    return py::make_tuple(depth, layers);
}

void write_depth(const py::handle& path_object, const py::handle& depth_object, const py::object& layers, bool half) {
    const std::string path = path_of(path_object);
    io::TranslucentDepth layered;
    layered.depth = depth_image(depth_object);
    layered.layers = translucent_layers(layers, layered.depth);
    py::gil_scoped_release released;
    io::write_translucent_depth_exr(path, layered, half ? io::SampleType::half : io::SampleType::float32);
}

py::array_t<float> read_receivers(const py::handle& path_object) {
    const std::string path = path_of(path_object);
    io::ReceiverGrid grid;
    {
        py::gil_scoped_release released;
        grid = io::read_receivers_exr(path);
    }
    const std::size_t count = grid.points.size();
    std::vector<float> uvz(3 * count);
    for (std::size_t i = 0; i < count; ++i) {
        uvz[3 * i] = grid.points.u[i];
        uvz[3 * i + 1] = grid.points.v[i];
        uvz[3 * i + 2] = grid.points.z[i];
    }
    return to_numpy(std::move(uvz), {grid.height, grid.width, 3});
}

void write_receivers(const py::handle& path_object, const py::handle& receivers_object) {
    const std::string path = path_of(path_object);
    const py::array array = real_array(receivers_object, "receivers", "float32 array of shape (H, W, 3) of u, v, depth",
                                       {3});
    if (array.shape(2) != 3)
        throw input_error("receivers must be a float32 array of shape (H, W, 3) of u, v, depth, got shape " +
                          shape_text(array));
    io::ReceiverGrid grid;
    grid.height = static_cast<int>(array.shape(0));
    grid.width = static_cast<int>(array.shape(1));
    grid.points = receiver_array(array).points;
    py::gil_scoped_release released;
    io::write_receivers_exr(path, grid);
}

/// Every channel of an EXR file as a float32 (HALF, FLOAT) or uint32 (UINT) array of the
/// image's shape.
py::dict read_image(const py::handle& path_object) {
    const std::string path = path_of(path_object);
    io::ExrImage image;
    {
        py::gil_scoped_release released;
        image = io::read_exr(path);
    }
    py::dict channels;
    for (io::ExrChannel& channel : image.channels) {
        const std::vector<py::ssize_t> shape{image.height / channel.y_sampling, image.width / channel.x_sampling};
        if (channel.type == io::SampleType::uint32) channels[channel.name.c_str()] = to_numpy(std::move(channel.codes), shape);
        else channels[channel.name.c_str()] = to_numpy(std::move(channel.values), shape);
    }
    return channels;
}

/// Whether an EXR, KTX2 or DDS file holds a summed-area table (else a filtered map).
bool holds_table(const std::string& path, cli::Container container) {
    if (container == cli::Container::exr) {
        const io::ExrImage image = io::read_exr(path);
        const io::ExrAttribute* format = image.find_attribute("msmcl:format");
        return format && std::holds_alternative<std::string>(format->value) &&
               std::get<std::string>(format->value) == "sat";
    }
    const io::GpuImage image = container == cli::Container::ktx2 ? io::read_ktx2(path) : io::read_dds(path);
    return image.format == io::GpuFormat::r32g32b32a32_uint;
}

py::object read_texture(const py::handle& path_object, const py::object& format_object,
                        const py::object& max_kernel_object) {
    const std::string path = path_of(path_object);
    std::optional<Format> format;
    if (!format_object.is_none())
        format = parse_name<Format>(format_object.cast<std::string>(), parse_format, "format",
                                    "moments128, msm64, nlq64 or nlq32");
    std::optional<std::uint32_t> max_kernel;
    if (!max_kernel_object.is_none()) max_kernel = max_kernel_object.cast<std::uint32_t>();
    py::gil_scoped_release released;
    const cli::Container container = cli::sniff_container(path);
    if (holds_table(path, container)) {
        io::SatFile file = cli::read_sat_file(path, max_kernel);
        py::gil_scoped_acquire acquired;
        return py::cast(SatObject{std::move(file.table), file.info});
    }
    io::TextureFile file = cli::read_texture_file(path, format);
    py::gil_scoped_acquire acquired;
    return py::cast(TextureObject{std::move(file.texture), file.info});
}

void write_texture(const py::handle& path_object, const py::handle& texture, const py::object& container_object,
                   bool array) {
    const std::string path = path_of(path_object);
    const std::string option = container_object.is_none() ? "" : container_object.cast<std::string>();
    const cli::Container container = cli::output_container(option, path);
    if (py::isinstance<TextureObject>(texture)) {
        const TextureObject& object = texture.cast<const TextureObject&>();
        py::gil_scoped_release released;
        cli::write_texture_file(path, container, object.texture, object.info, array);
    } else if (py::isinstance<SatObject>(texture)) {
        const SatObject& object = texture.cast<const SatObject&>();
        py::gil_scoped_release released;
        cli::write_sat_file(path, container, object.table, object.info, array);
    } else {
        throw input_error("write_texture writes a msmcl.Texture or msmcl.SatTable, got " +
                          py::str(py::type::of(texture)).cast<std::string>());
    }
}

py::object info(const py::handle& path_object, const py::object& depth_range) {
    const std::string path = path_of(path_object);
    const DepthRange range = depth_range_of(depth_range);
    std::string text;
    {
        py::gil_scoped_release released;
        text = cli::describe_json(path, range);
    }
    return py::module_::import("json").attr("loads")(text);
}

} // namespace
} // namespace msmcl::python

PYBIND11_MODULE(_msmcl, m) {
    using namespace msmcl;
    using namespace msmcl::python;
    m.doc() = "Moment shadow maps on OpenCL: filter depth maps into moment shadow maps and shade receivers, "
              "numpy arrays in and out (docs/python.md).";
    m.attr("__version__") = msmcl::version_string;
    // Classes and signatures name the package (msmcl.Texture), not its compiled part.
    m.attr("__name__") = "msmcl";

    error_type = new_exception(m, "Error", "Base of every error msmcl raises. Attributes: cl_error (the OpenCL "
                               "error name, e.g. 'CL_OUT_OF_RESOURCES', or None), code (the OpenCL error code or "
                               "None), build_log (a failed program build's log or None).",
                               py::make_tuple(py::handle(PyExc_Exception)));
    input_error_type = new_exception(m, "InputError", "Unusable input: a bad array dtype or shape, an unknown "
                                     "format or option, a file that is missing or not what it should be. Also a "
                                     "ValueError.",
                                     py::make_tuple(py::handle(error_type), py::handle(PyExc_ValueError)));
    device_error_type = new_exception(m, "DeviceError", "An OpenCL call or program build failed (cl_error, code, "
                                      "build_log say which), or no device matches the request.",
                                      py::make_tuple(py::handle(error_type)));
    py::register_exception_translator(translate);

    m.def("devices", [] {
        py::list list;
        for (const DeviceInfo& d : list_devices()) list.append(device_dict(d));
        return list;
    }, "Every OpenCL device of every platform, one dict each (index 'P:D', name, type 'gpu'|'cpu'|'other', "
       "platform, vendor, driver_version, opencl_version, compute_units, global_mem_bytes, local_mem_bytes, "
       "max_work_group_size, host_unified_memory). Empty without an OpenCL platform.");

    py::class_<TextureObject>(m, "Texture",
        "A filtered moment shadow map in host memory (or a texture array of `layers` maps): the bytes the "
        "device wrote, and what a file records of it (sigma, samples, depth_range). Independent of the "
        "Context that made it.")
        .def_property_readonly("format", [](const TextureObject& t) { return format_name(t.texture.format); },
                               "'moments128', 'msm64', 'nlq64' or 'nlq32'.")
        .def_property_readonly("width", [](const TextureObject& t) { return t.texture.width; })
        .def_property_readonly("height", [](const TextureObject& t) { return t.texture.height; })
        .def_property_readonly("layers", [](const TextureObject& t) { return t.texture.layers; },
                               "Array layers (1: a plain 2D map).")
        .def_property_readonly("sigma", [](const TextureObject& t) { return t.info.sigma; })
        .def_property_readonly("samples", [](const TextureObject& t) { return t.info.samples; })
        .def_property_readonly("depth_range", [](const TextureObject& t) { return depth_range_tuple(t.info.depth_range); })
        .def_property_readonly("array", &texture_array,
            "The texels, a writable view of the texture's memory (no copy; it keeps the texture alive): "
            "moments128 float32 (H, W, 4) b1..b4; msm64 and nlq64 uint16 (H, W, 4) codes; nlq32 uint32 (H, W); "
            "vsm32 uint16 (H, W, 2); vsm64 float32 (H, W, 2); evsm2_32 and evsm4_64 float16 (H, W, 2 or 4); "
            "evsm4_128 float32 (H, W, 4); esm32 float32 (H, W). "
            "A texture array has a leading axis L.")
        .def_property_readonly("words", &texture_words,
            "The texel words as the device and the files store them, a uint32 view (H, W, words per texel) of "
            "the same memory as .array.")
        .def("decode", &texture_decode,
            "A new float64 array (H, W, 4): per texel b1..b4 (moments128, msm64) or y1, y2, v2, xi4 of "
            "Algorithm 2 (nlq64, nlq32), as `msmcl info` decodes them.")
        .def("layer", [](const TextureObject& t, int index) {
            if (index < 0 || index >= t.texture.layers)
                throw input_error("layer " + std::to_string(index) + " of a texture of " +
                                  std::to_string(t.texture.layers) + " layers");
            return TextureObject{t.texture.layer(index), t.info};
        }, "index"_a, "Array layer `index` as a texture of its own (a copy).")
        .def("__repr__", [](const TextureObject& t) {
            return "<msmcl.Texture " + std::string(format_name(t.texture.format)) + " " + std::to_string(t.texture.width) +
                   "x" + std::to_string(t.texture.height) +
                   (t.texture.layers != 1 ? ", " + std::to_string(t.texture.layers) + " layers" : std::string()) + ">";
        });

    py::class_<SatObject>(m, "SatTable",
        "An integer modular summed-area table of moments (build_sat), or a texture array of `layers` tables. "
        "Independent of the Context that made it.")
        .def_property_readonly("width", [](const SatObject& t) { return t.table.width; })
        .def_property_readonly("height", [](const SatObject& t) { return t.table.height; })
        .def_property_readonly("layers", [](const SatObject& t) { return t.table.layers; })
        .def_property_readonly("max_kernel", [](const SatObject& t) { return t.table.max_kernel_texels; },
                               "N: texels of the largest rectangle the table may be queried for.")
        .def_property_readonly("scale", [](const SatObject& t) { return t.table.scale; })
        .def_property_readonly("samples", [](const SatObject& t) { return t.info.samples; })
        .def_property_readonly("depth_range", [](const SatObject& t) { return depth_range_tuple(t.info.depth_range); })
        .def_property_readonly("array", &sat_array,
            "The table words, a writable uint32 view (H, W, 4) of the table's memory (no copy; a texture array "
            "has a leading axis L).")
        .def("layer", [](const SatObject& t, int index) {
            if (index < 0 || index >= t.table.layers)
                throw input_error("layer " + std::to_string(index) + " of a table of " +
                                  std::to_string(t.table.layers) + " layers");
            return SatObject{t.table.layer(index), t.info};
        }, "index"_a, "Array layer `index` as a table of its own (a copy).")
        .def("__repr__", [](const SatObject& t) {
            return "<msmcl.SatTable " + std::to_string(t.table.width) + "x" + std::to_string(t.table.height) +
                   ", N " + std::to_string(t.table.max_kernel_texels) +
                   (t.table.layers != 1 ? ", " + std::to_string(t.table.layers) + " layers" : std::string()) + ">";
        });

    py::class_<Context>(m, "Context",
        "An OpenCL device with its queue and program cache. Python threads may share one: every call releases "
        "the GIL while the device works, and gives the same result as alone.")
        .def(py::init(&make_context), "device"_a = py::none(), "platform"_a = py::none(),
            "device: None (MSMCL_DEVICE, else the first GPU, else the first CPU), 'gpu', 'cpu', an index "
            "(int or 'P:D') or a substring of the device name; platform: None or a platform index or name "
            "substring. A device or platform that matches nothing raises DeviceError.")
        .def_property_readonly("device", [](const Context& c) { return device_dict(c.device()); },
                               "The device, as a dict of msmcl.devices().")
        .def_property_readonly("programs_built", &Context::programs_built,
                               "Programs built (not found in a cache) since the Context was made.")
        .def("set_binary_cache_dir", &Context::set_binary_cache_dir, "directory"_a,
             "Keep program binaries in `directory` (created when missing), as MSMCL_CACHE_DIR does.")
        .def("finish", &Context::finish, py::call_guard<py::gil_scoped_release>())
        .def("filter",
            [](Context& c, const py::handle& depth, const std::string& format, float sigma, const py::object& range,
               const std::string& kernel, const py::object& layers) {
                DepthImage image = depth_image(depth);
                const std::vector<TranslucentLayer> translucent = translucent_layers(layers, image);
                return run_filter(c, std::move(image), translucent, format, sigma, range, kernel);
            },
            "depth"_a, "format"_a = "nlq64", "sigma"_a = 2.4, "depth_range"_a = py::make_tuple(0, 1),
            "kernel"_a = "automatic", "layers"_a = py::none(),
            "Filters a depth map into a moment shadow map, as `msmcl filter` (same bytes).\n\n"
            "depth: float32 (H, W) or (H, W, S), S = 1, 2, 4, 8 or 16 samples per texel, in depth_range.\n"
            "format: 'moments128', 'msm64', 'nlq64' or 'nlq32'. sigma: Gaussian blur in texels (0: none).\n"
            "depth_range: (0, 1) or (-1, 1). kernel: 'automatic', 'fused_paper', 'fused_cpu' or 'three_pass'.\n"
            "layers: translucent occluders, a list of (depth, opacity) arrays shaped like depth.\n"
            "Returns a Texture. Other real dtypes and strides are converted once; anything else raises InputError.")
        .def("filter_array",
            [](Context& c, const py::handle& depths, const std::string& format, float sigma, const py::object& range,
               const std::string& kernel) {
                return run_filter(c, depth_stack(depths), {}, format, sigma, range, kernel);
            },
            "depths"_a, "format"_a = "nlq64", "sigma"_a = 2.4, "depth_range"_a = py::make_tuple(0, 1),
            "kernel"_a = "automatic",
            "Filters L maps of one size into a texture array (one launch for all), as `msmcl filter ... --array`: "
            "depths is (L, H, W[, S]) or a sequence of (H, W[, S]) maps; layer i holds the bytes of filter(depths[i]).")
        .def("shade", &run_shade, "texture"_a, "receivers"_a, "lookup"_a = "bilinear", "depth_bias"_a = 1e-3,
            "depth_range"_a = py::none(), "frame"_a = 0u,
            "Shadow intensity (0 lit, 1 shadowed) of each receiver, as `msmcl shade`.\n\n"
            "receivers: (N, 3) or (H, W, 3) of u, v (texel units, texel centres at i + 0.5) and depth as "
            "rendered, the channels U, V, Z of a receivers EXR. lookup: 'nearest', 'bilinear' or 'dither' "
            "(blue noise of the receiver's pixel: its (row, column) in an (H, W, 3) grid; frame picks the noise).\n"
            "depth_bias: subtracted from the internal depth. depth_range: None (the texture's), (0, 1) or (-1, 1).\n"
            "Returns float32 of shape receivers.shape[:-1].")
        .def("build_sat",
            [](Context& c, const py::handle& depth, std::uint32_t max_kernel, const py::object& range,
               const std::string& kernel, const py::object& layers) {
                DepthImage image = depth_image(depth);
                const std::vector<TranslucentLayer> translucent = translucent_layers(layers, image);
                return run_build_sat(c, image, translucent, max_kernel, range, kernel);
            },
            "depth"_a, "max_kernel"_a = 729u, "depth_range"_a = py::make_tuple(0, 1), "kernel"_a = "automatic",
            "layers"_a = py::none(),
            "Summed-area table of a depth map's moments, as `msmcl sat` (same bytes).\n\n"
            "max_kernel: N, texels of the largest rectangle ever queried (default 27 x 27). kernel: 'automatic', "
            "'tiled_gpu', 'tiled_cpu' or 'row_per_thread'. depth and layers as for filter. Returns a SatTable.")
        .def("build_sat_array",
            [](Context& c, const py::handle& depths, std::uint32_t max_kernel, const py::object& range,
               const std::string& kernel) { return run_build_sat(c, depth_stack(depths), {}, max_kernel, range, kernel); },
            "depths"_a, "max_kernel"_a = 729u, "depth_range"_a = py::make_tuple(0, 1), "kernel"_a = "automatic",
            "Tables of L maps of one size as one texture array, as `msmcl sat ... --array`.")
        .def("soft_shade", &run_soft_shade, "table"_a, "receivers"_a, "light_size"_a, "search_size"_a = 0,
            "min_filter_size"_a = 1.0, "depth_bias"_a = 1e-3, "depth_range"_a = py::none(),
            "receiver_weight"_a = 0.1, "filter_parts"_a = 2, "published"_a = false,
            "Moment soft shadows of a directional light from a SatTable, as `msmcl soft` (same options).\n\n"
            "light_size: penumbra width in texels per unit of internal depth between receiver and blocker. "
            "search_size: blocker search square side (0: floor(sqrt(N))). published: the method as published "
            "(receiver_weight 0, filter_parts 1). receivers as for shade; returns float32 of their shape.")
        .def("scatter", &run_scatter, "scene"_a, "shadow_map"_a, "camera_depth"_a, "moments"_a = 6,
            "filtered"_a = true, "sigma"_a = 1.0, "beta"_a = "adaptive", "kernel"_a = "automatic",
            "filter_kernel"_a = "automatic", "ray_march"_a = 0, "jitter"_a = 0u,
            "Single-scattered radiance per camera pixel, as `msmcl scatter`.\n\n"
            "scene: a dict with the keys of a scene file (light, camera, medium, rectified; see "
            "data/scatter/README.md) or a path to one. shadow_map: the light's depth map (H, W[, S]) in the "
            "light's depth_range; camera_depth: (camera height, camera width) in the camera's convention.\n"
            "moments 4 or 6; filtered False: one depth sample per texel (--no-filter); beta 'adaptive' or in "
            "[0, 1]; ray_march N > 0: ray marching with N steps instead (ground truth), jitter its seed.\n"
            "Returns float32 (camera height, camera width).")
        .def("__repr__", [](const Context& c) { return "<msmcl.Context " + c.device().name + ">"; });

    m.def("read_depth", &read_depth, "path"_a, "depth_range"_a = py::make_tuple(0, 1), "translucent"_a = false,
          "A depth map EXR as `msmcl filter` reads it (channel Z or sample<s>.Z; every depth checked against "
          "depth_range): float32 (H, W), or (H, W, S) for S > 1 samples. translucent=True returns (depth, layers) "
          "with the translucent layers as a list of (depth, opacity) arrays.");
    m.def("write_depth", &write_depth, "path"_a, "depth"_a, "layers"_a = py::none(), "half"_a = false,
          "Writes a depth map (H, W) or (H, W, S), with translucent layers (a list of (depth, opacity) "
          "arrays shaped like depth) if given, as an EXR that `msmcl filter` reads (FLOAT, or HALF).");
    m.def("read_receivers", &read_receivers, "path"_a,
          "A receivers EXR (channels U, V, Z) as float32 (H, W, 3) of u, v, depth.");
    m.def("write_receivers", &write_receivers, "path"_a, "receivers"_a,
          "Writes (H, W, 3) receivers of u, v, depth as an EXR that `msmcl shade` reads.");
    m.def("read_image", &read_image, "path"_a,
          "Every channel of an EXR file (a shade, soft or scatter result's Y, ...) as a dict of arrays of the "
          "image's shape: float32 for HALF and FLOAT channels, uint32 for UINT ones.");
    m.def("read_texture", &read_texture, "path"_a, "format"_a = py::none(), "max_kernel"_a = py::none(),
          "A filtered map (Texture) or summed-area table (SatTable) from EXR, KTX2 or DDS, as the CLI reads it "
          "(the container from the file's first bytes). format: needed for DDS maps of msm64/nlq64 texels; "
          "max_kernel: needed for DDS tables; both checked against what the file records.");
    m.def("write_texture", &write_texture, "path"_a, "texture"_a, "container"_a = py::none(), "array"_a = false,
          "Writes a Texture or SatTable as `msmcl filter` / `msmcl sat` write it (the same bytes): container "
          "'exr', 'ktx2' or 'dds', else from the extension. array=True writes a texture array even of one "
          "layer (KTX2, DDS; a Texture of several layers always is one).");
    m.def("info", &info, "path"_a, "depth_range"_a = py::make_tuple(0, 1),
          "What `msmcl info --json` says of a file (kind, container, size, format, attributes, per channel "
          "ranges and NaN/Inf counts), as a dict.");
    m.attr("__name__") = "msmcl._msmcl";
}
