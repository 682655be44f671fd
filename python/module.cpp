// `import leanfade` (pybind11): the bake of `leanfade bake` for Python pipelines, NumPy arrays in
// and out (docs/pipelines.md). The settings are the bake's (BakeSettingsSpec below, one row per
// setting: its name, default and check); errors are leanfade.Error with the library's message.
// The GIL is released while a bake, a read or a write runs.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "leanfade/version.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace leanfade::python {
namespace {

// ---- Settings ---------------------------------------------------------------------------------

// The settings of one bake, as `leanfade bake`'s flags set them (tools/leanfade/cli_bake_plan.cpp:
// bake_settings): the same names without the dashes.
struct PyBakeSettings {
    BakeOptions options;
    BakeSource source = BakeSource::Auto;
    StoragePolicy storage;
    bool strength_given = false;
    io::ReadOptions read_options;
    io::WriteOptions write_options;
};

float finite_setting(const char* setting, double value) {
    if (!std::isfinite(value)) throw Error::setting(setting, "must be a finite number");
    return float(value);
}

// A setting's value as T, or leanfade::Error naming the setting.
template <typename T>
T value_of(const char* setting, py::handle value, const char* expected) {
    try {
        return py::cast<T>(value);
    } catch (const py::cast_error&) {
        throw Error::setting(setting,
                             std::string("expected ") + expected + ", got " +
                                 std::string(py::str(py::type::of(value).attr("__name__"))));
    }
}
std::string text_of(const char* setting, py::handle value) {
    if (!py::isinstance<py::str>(value))
        throw Error::setting(
            setting,
            "expected a string, got " + std::string(py::str(py::type::of(value).attr("__name__"))));
    return py::cast<std::string>(value);
}
double number_of(const char* setting, py::handle value) {
    return value_of<double>(setting, value, "a number");
}
// A name of `names` (a library's name table) as its value.
template <typename T>
T named(const char* setting, py::handle value, const std::vector<std::pair<std::string, T>>& names) {
    const std::string text = text_of(setting, value);
    std::string expected;
    for (const auto& [name, typed] : names) {
        if (name == text) return typed;
        expected += (expected.empty() ? "" : " or ") + name;
    }
    throw Error::setting(setting, "expected " + expected + ", got '" + text + "'");
}

// One row per bake setting: `leanfade bake`'s flag without the dashes ("from_" for --from), its
// default, and what it sets in PyBakeSettings, checked (in the table's order: `from_` before
// `strength`, which depends on it). BakeSettings(**settings), the module's BAKE_SETTINGS and
// leanfade.BAKE_SETTINGS (python/leanfade/__init__.py) read this table.
struct BakeSettingSpec {
    const char* name;
    py::object (*default_value)();
    void (*apply)(PyBakeSettings& settings, py::handle value);
};

const std::vector<BakeSettingSpec>& bake_setting_specs() {
    static const std::vector<BakeSettingSpec> specs{
        {"from_", [] { return py::object(py::str("auto")); },
         [](PyBakeSettings& s, py::handle v) {
             s.source = parse_bake_source(text_of("from", v), "from");
         }},
        {"strength", [] { return py::object(py::none()); },
         [](PyBakeSettings& s, py::handle v) {
             if (v.is_none()) return;  // not given: 1, and no error for normal maps
             s.options.strength = finite_setting("strength", number_of("strength", v));
             if (s.options.strength == 0.0f)
                 throw Error::setting("strength",
                                      "must not be 0 (a negative strength inverts the heights)");
             if (s.source == BakeSource::Normal)
                 throw Error::setting("strength",
                                      "applies to height maps; from='normal' bakes normal maps");
             s.strength_given = true;
         }},
        {"strength_unit", [] { return py::object(py::str("texel")); },
         [](PyBakeSettings& s, py::handle v) {
             s.options.strength_unit = named("strength_unit", v, strength_unit_names());
         }},
        {"sc", [] { return py::object(py::str("auto")); },
         [](PyBakeSettings& s, py::handle v) {
             s.options.scale_excludes_outliers =
                 named<bool>("sc", v, {{"auto", true}, {"max", false}});
         }},
        {"directx", [] { return py::object(py::bool_(false)); },
         [](PyBakeSettings& s, py::handle v) {
             s.options.convention = value_of<bool>("directx", v, "a bool")
                                        ? NormalConvention::DirectX
                                        : NormalConvention::OpenGL;
         }},
        {"strict_normals", [] { return py::object(py::bool_(false)); },
         [](PyBakeSettings& s, py::handle v) {
             s.options.strict_normals = value_of<bool>("strict_normals", v, "a bool");
         }},
        {"bits", [] { return py::object(py::str("auto")); },
         [](PyBakeSettings& s, py::handle v) {
             s.storage = parse_storage_policy(text_of("bits", v), "bits");
         }},
        {"bake_roughness", [] { return py::object(py::float_(0.0)); },
         [](PyBakeSettings& s, py::handle v) {
             const double shininess = number_of("bake_roughness", v);
             if (!(shininess >= 0.0) || !std::isfinite(shininess))
                 throw Error::setting("bake_roughness", "must be a positive shininess (0: none)");
             s.options.bake_roughness_shininess = float(shininess);
         }},
        {"plateau_epsilon", [] { return py::object(py::float_(double(kDefaultPlateauEpsilon))); },
         [](PyBakeSettings& s, py::handle v) {
             const double epsilon = number_of("plateau_epsilon", v);
             if (!(epsilon >= 0.0) || !std::isfinite(epsilon))
                 throw Error::setting("plateau_epsilon",
                                      "must be a finite number >= 0 (0: no plateau layer)");
             s.options.plateau_epsilon = float(epsilon);
         }},
        {"spike", [] { return py::object(py::str(to_string(SpikeFit::Auto))); },
         [](PyBakeSettings& s, py::handle v) {
             s.options.spike_fit = parse_spike_fit(text_of("spike", v), "spike");
         }},
        {"wrap", [] { return py::object(py::str("repeat")); },
         [](PyBakeSettings& s, py::handle v) { s.options.wrap = named("wrap", v, wrap_names()); }},
        {"threads", [] { return py::object(py::int_(0)); },
         [](PyBakeSettings& s, py::handle v) {
             const int threads = value_of<int>("threads", v, "an integer");
             if (threads < 0 || threads > 256)
                 throw Error::setting("threads", "must be in [0, 256] (0 = all cores)");
             s.options.threads = threads;
             s.write_options.threads = threads;
         }},
        {"max_size", [] { return py::object(py::int_(kDefaultMaxImageDimension)); },
         [](PyBakeSettings& s, py::handle v) {
             const int max_size = value_of<int>("max_size", v, "an integer");
             if (max_size < 1 || max_size > (1 << 20))
                 throw Error::setting("max_size", "must be in [1, 1048576]");
             s.read_options.max_dimension = max_size;
         }},
        // The KTX2 file's supercompression (save, to_bytes), as `bake --supercompression`.
        {"supercompression", [] { return py::object(py::str("zstd")); },
         [](PyBakeSettings& s, py::handle v) {
             s.write_options.supercompression =
                 named("supercompression", v, io::supercompression_names());
         }},
        {"zstd_level", [] { return py::object(py::int_(3)); },
         [](PyBakeSettings& s, py::handle v) {
             const int level = value_of<int>("zstd_level", v, "an integer");
             if (level < 1 || level > 19) throw Error::setting("zstd_level", "must be in [1, 19]");
             s.write_options.zstd_level = level;
         }},
    };
    return specs;
}

// The settings of `given` (keyword -> value), every other at its default. Throws
// leanfade::Error naming an unknown or bad setting.
PyBakeSettings make_settings(const py::kwargs& given) {
    std::string names;
    for (const BakeSettingSpec& spec : bake_setting_specs())
        names += std::string(names.empty() ? "" : ", ") + spec.name;
    for (const auto& [key, value] : given) {
        const std::string name = py::cast<std::string>(key);
        bool known = false;
        for (const BakeSettingSpec& spec : bake_setting_specs()) known = known || name == spec.name;
        if (!known) throw Error(name, "not a bake setting (expected one of " + names + ")");
    }
    PyBakeSettings settings;
    settings.read_options.drop_alpha = true;  // normal maps use RGB only, as the CLI reads them
    for (const BakeSettingSpec& spec : bake_setting_specs()) {
        const py::object value = given.contains(spec.name) ? py::object(given[spec.name])
                                                           : spec.default_value();
        spec.apply(settings, value);
    }
    return settings;
}

// ---- Inputs -----------------------------------------------------------------------------------

bool is_path(const py::handle& object) {
    return py::isinstance<py::str>(object) ||
           py::isinstance(object, py::module_::import("os").attr("PathLike"));
}

std::string path_text(const py::handle& object) {
    return py::str(py::module_::import("os").attr("fspath")(object)).cast<std::string>();
}

// A NumPy array as the bake's input: (H, W) or (H, W, C), C in 1-4; uint8 and uint16 as the
// integer samples of an 8- or 16-bit file, float32/float64 as floats. RGBA keeps RGB (what
// reading a file with an alpha channel gives the bake).
std::variant<Image, UnormImage> image_from_array(const py::array& array, const std::string& name,
                                                 int max_size) {
    if (array.ndim() != 2 && array.ndim() != 3)
        throw Error(name, "expected an array of shape (height, width) or (height, width, "
                          "channels), got " + std::to_string(array.ndim()) + " dimensions");
    const py::ssize_t height = array.shape(0), width = array.shape(1);
    const py::ssize_t channels = array.ndim() == 3 ? array.shape(2) : 1;
    if (width < 1 || height < 1) throw Error(name, "the array is empty");
    if (width > max_size || height > max_size)
        throw Error(name, std::to_string(width) + "x" + std::to_string(height) +
                              " is larger than max_size " + std::to_string(max_size));
    if (channels < 1 || channels > 4)
        throw Error(name, "expected 1-4 channels, got " + std::to_string(channels));
    const int kept = channels == 4 ? 3 : int(channels);
    const py::dtype dtype = array.dtype();
    const auto copy = [&](auto* out, auto tag) {
        using T = decltype(tag);
        const py::array_t<T, py::array::c_style | py::array::forcecast> dense(array);
        const T* in = dense.data();
        const std::size_t texels = std::size_t(width) * std::size_t(height);
        for (std::size_t i = 0; i < texels; ++i)
            for (int c = 0; c < kept; ++c) out[i * kept + c] = in[i * channels + c];
    };
    if (dtype.is(py::dtype::of<std::uint8_t>()) || dtype.is(py::dtype::of<std::uint16_t>())) {
        const bool eight = dtype.is(py::dtype::of<std::uint8_t>());
        UnormImage image(int(width), int(height), kept, eight ? 255 : 65535);
        if (eight)
            copy(image.samples.data(), std::uint8_t{});
        else
            copy(image.samples.data(), std::uint16_t{});
        return image;
    }
    if (dtype.kind() == 'f') {
        Image image(int(width), int(height), kept);
        copy(image.pixels.data(), float{});
        return image;
    }
    throw Error(name, "expected a uint8, uint16 or floating-point array, got dtype " +
                          dtype.attr("name").cast<std::string>());
}

std::vector<std::uint8_t> bytes_of(const py::bytes& bytes) {
    const std::string text = bytes;
    return {text.begin(), text.end()};
}

struct Source {
    std::variant<Image, UnormImage> image;
    std::string name;  // the file, or the caller's name for an array
    std::string file;  // the input file, when read from one
};

Source read_source(const py::object& source, const std::string& name, const PyBakeSettings& settings) {
    Source result;
    if (is_path(source)) {
        result.file = result.name = path_text(source);
        py::gil_scoped_release unlocked;
        result.image = io::read_image_compact(result.file, settings.read_options);
        return result;
    }
    if (py::isinstance<py::bytes>(source)) {
        // An image file's bytes (what a batch hashed), decoded as the file would be.
        const std::vector<std::uint8_t> bytes = bytes_of(source.cast<py::bytes>());
        result.name = name.empty() ? "bytes" : name;
        py::gil_scoped_release unlocked;
        result.image = io::read_image_compact_from_memory(bytes, result.name, settings.read_options);
        return result;
    }
    result.name = name.empty() ? "array" : name;
    result.image = image_from_array(py::array::ensure(source), result.name,
                                    settings.read_options.max_dimension);
    return result;
}

// ---- Results ----------------------------------------------------------------------------------

// How save() and to_bytes() write a loaded map: `leanfade bake`'s defaults (Zstandard at
// WriteOptions' level, 3).
io::WriteOptions default_file_options() {
    io::WriteOptions options;
    options.supercompression = io::Supercompression::Zstandard;
    return options;
}

// A baked or loaded LEAN map, shared with the arrays that view its levels. A baked map is
// written with its bake's write options (supercompression, level, threads).
struct LeanMapObject {
    PackedBakeResult baked;
    std::string input_file;  // the file it was baked from: never an output
    bool has_summary = false;
    io::WriteOptions file_options = default_file_options();
};

py::dtype storage_dtype(Storage storage) {
    switch (storage) {
        case Storage::Unorm8: return py::dtype("uint8");
        case Storage::Unorm16: return py::dtype("uint16");
        case Storage::Float16: return py::dtype("float16");
        case Storage::Float32: return py::dtype("float32");
    }
    return py::dtype("uint8");
}

// A read-only (height, width, 4) view of one slice's bytes, keeping `owner` alive.
py::object level_view(const std::vector<std::uint8_t>& bytes, const PackedLevel& level,
                      Storage storage, py::handle owner) {
    if (bytes.empty()) return py::none();
    const py::ssize_t texel = bytes_per_texel(storage), channel = texel / 4;
    py::array view(storage_dtype(storage), {py::ssize_t(level.height), py::ssize_t(level.width), py::ssize_t(4)},
                   {py::ssize_t(level.width) * texel, texel, channel}, bytes.data(), owner);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return std::move(view);
}

py::dict summary_dict(const LeanMapSummary& s) {
    py::dict d;
    d["width"] = s.width;
    d["height"] = s.height;
    d["levels"] = s.levels;
    d["scale"] = s.scale;
    d["mean_slope"] = s.mean_slope;
    d["max_slope"] = s.max_slope;
    d["coarsest_covariance"] = py::make_tuple(s.coarsest_covariance.x, s.coarsest_covariance.y,
                                              s.coarsest_covariance.z);
    d["coarsest_anisotropy"] = s.coarsest_anisotropy;
    d["plateau_fraction"] = s.plateau_fraction;
    d["flat_fraction"] = s.flat_fraction;
    d["spike_window"] =
        s.spike_window.shape == SpikeWindowShape::None
            ? py::object(py::none())
            : py::object(py::dict(py::arg("shape") = to_string(s.spike_window.shape),
                                  py::arg("radius") = s.spike_window.radius,
                                  py::arg("with_plateaus") = s.spike_window.with_plateaus));
    return d;
}

bool same_file(const std::string& a, const std::string& b) {
    std::error_code error;
    return !a.empty() && !b.empty() && fs::equivalent(a, b, error) && !error;
}

// save(): NAME.ktx2 (every level), or NAME.png for the PNG pair NAME.lean1.png + NAME.lean2.png
// (+ NAME.plateau.png), as `leanfade bake -o` names them.
void save_map(const LeanMapObject& map, const std::string& path, bool fsync) {
    io::WriteOptions options = map.file_options;
    options.durability = fsync ? io::Durability::Flush : io::Durability::Rename;
    const PackedLeanMap& packed = map.baked.packed;
    std::vector<std::string> outputs;
    const bool png = io::has_extension(path, ".png");
    if (png) {
        const std::string base = fs::path(path).replace_extension().string();
        outputs = {base + io::kLeanPngSuffixes[0], base + io::kLeanPngSuffixes[1]};
        if (packed.has_plateau()) outputs.push_back(base + io::kPlateauPngSuffix);
    } else if (io::has_extension(path, ".ktx2")) {
        outputs = {path};
    } else {
        throw Error(path, "expected a .ktx2 or .png output");
    }
    for (const std::string& output : outputs)
        if (same_file(output, map.input_file))
            throw Error(output, "is the map's input; an output may not replace an input");
    py::gil_scoped_release unlocked;
    if (png)
        io::write_lean_png_pair(outputs[0], outputs[1], packed, options,
                                outputs.size() > 2 ? outputs[2] : "");
    else
        io::write_ktx2(path, packed, options);
}

std::shared_ptr<LeanMapObject> bake(const py::object& source, const std::string& name,
                                    const PyBakeSettings& settings) {
    Source input = read_source(source, name, settings);
    auto map = std::make_shared<LeanMapObject>();
    map->input_file = input.file;
    map->file_options = settings.write_options;
    map->has_summary = true;
    {
        py::gil_scoped_release unlocked;
        map->baked = leanfade::bake(BakeInput(input.image, settings.source, input.name),
                                    {settings.options, settings.storage, LEANFADE_GENERATOR});
    }
    if (settings.strength_given && map->baked.source == BakeSource::Normal)
        throw Error(input.name, "is a normal map: strength applies to height maps only");
    return map;
}

// ---- Engine textures --------------------------------------------------------------------------

py::array rgba8_array(Rgba8Image&& image) {
    auto owner = std::make_unique<std::vector<std::uint8_t>>(std::move(image.texels));
    std::uint8_t* data = owner->data();
    py::capsule free_owner(owner.release(), [](void* p) {
        delete static_cast<std::vector<std::uint8_t>*>(p);
    });
    return py::array_t<std::uint8_t>({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(4)},
                                     data, free_owner);
}

py::list rgba8_levels(std::vector<Rgba8Image>& levels) {
    py::list list;
    for (Rgba8Image& level : levels) list.append(rgba8_array(std::move(level)));
    return list;
}


}  // namespace
}  // namespace leanfade::python

PYBIND11_MODULE(_leanfade, m) {
    using namespace leanfade;
    using namespace leanfade::python;
    m.doc() = "leanfade: LEAN maps (filtered normal-map specular) baked for pipelines";
    m.attr("__version__") = LEANFADE_VERSION;

    static py::exception<Error> error_type(m, "Error", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const Error& e) {
            py::object instance = py::handle(error_type.ptr())(e.what());
            instance.attr("subject") = e.file();
            instance.attr("kind") = e.kind() == ErrorKind::Setting ? "setting" : "file";
            instance.attr("setting") = e.setting();
            instance.attr("mentioned_settings") = e.mentioned_settings();
            instance.attr("cause") = e.cause();
            PyErr_SetObject(error_type.ptr(), instance.ptr());
        }
    });

    py::class_<PyBakeSettings>(m, "BakeSettings",
                             "The settings of one bake: `leanfade bake`'s flags, checked.")
        .def(py::init([](const py::kwargs& settings) { return make_settings(settings); }));
    // Every setting with its default (bake_setting_specs).
    py::dict defaults;
    for (const BakeSettingSpec& spec : bake_setting_specs()) defaults[spec.name] = spec.default_value();
    m.attr("BAKE_SETTINGS") = defaults;

    py::class_<LeanMapObject, std::shared_ptr<LeanMapObject>>(
        m, "LeanMap",
        "A LEAN map: every MIP level's layers lean1, lean2 (and the plateau layer of two-lobe "
        "LEAN) as the GPU samples them (docs/math.md §3).")
        .def_property_readonly("width", [](const LeanMapObject& m) {
            return m.baked.packed.levels.empty() ? 0 : m.baked.packed.levels[0].width; })
        .def_property_readonly("height", [](const LeanMapObject& m) {
            return m.baked.packed.levels.empty() ? 0 : m.baked.packed.levels[0].height; })
        .def_property_readonly("storage", [](const LeanMapObject& m) {
            return std::string(to_string(m.baked.packed.storage)); })
        .def_property_readonly("encoding", [](const LeanMapObject& m) {
            return std::string(to_string(m.baked.packed.encoding)); })
        .def_property_readonly("scale", [](const LeanMapObject& m) { return m.baked.packed.scale; })
        .def_property_readonly("source", [](const LeanMapObject& m) {
            return std::string(to_string(m.baked.source)); })
        .def_property_readonly("generator", [](const LeanMapObject& m) {
            return m.baked.packed.generator; })
        .def_property_readonly("plateau_epsilon", [](const LeanMapObject& m) {
            return m.baked.packed.plateau_epsilon; })
        .def_property_readonly("has_plateau", [](const LeanMapObject& m) {
            return m.baked.packed.has_plateau(); })
        .def_property_readonly("summary", [](const LeanMapObject& m) {
            return summary_dict(m.baked.summary); })
        .def_property_readonly(
            "levels",
            [](py::object self) {
                const LeanMapObject& m = self.cast<const LeanMapObject&>();
                py::list levels;
                for (const PackedLevel& level : m.baked.packed.levels) {
                    py::dict d;
                    const Storage s = m.baked.packed.storage;
                    d["lean1"] = level_view(level.lean1, level, s, self);
                    d["lean2"] = level_view(level.lean2, level, s, self);
                    d["plateau"] = level_view(level.plateau, level, s, self);
                    levels.append(d);
                }
                return levels;
            },
            "One dict per MIP level (0 = finest): read-only (height, width, 4) views of lean1, "
            "lean2 and plateau (None without the layer), dtype as the storage.")
        .def("save", &save_map, py::arg("path"), py::arg("fsync") = false,
             "Writes PATH.ktx2 (every level) or the PNG pair PATH.lean1.png + PATH.lean2.png "
             "(+ .plateau.png) of 8- or 16-bit maps, atomically: the bytes `leanfade bake -o` "
             "writes.")
        .def("to_bytes", [](const LeanMapObject& m) {
            std::vector<std::uint8_t> bytes;
            {
                py::gil_scoped_release unlocked;
                bytes = io::write_ktx2_to_memory(m.baked.packed, "LeanMap", m.file_options);
            }
            return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        }, "The KTX2 file's bytes.");

    m.def(
        "bake",
        [](const py::object& source, const PyBakeSettings& settings, const std::string& name) {
            return bake(source, name, settings);
        },
        py::arg("source"), py::arg("settings"), py::arg("name") = "",
        "Bakes SOURCE (a path, a file's bytes or a NumPy array) with SETTINGS into a LeanMap, as "
        "`leanfade bake` does. leanfade.bake() is the keyword form.");

    m.def(
        "load",
        [](const py::object& path, int max_size) {
            const std::string file = path_text(path);
            auto map = std::make_shared<LeanMapObject>();
            py::gil_scoped_release unlocked;
            io::ReadOptions options;
            options.max_dimension = max_size;
            map->baked.packed = io::read_ktx2(file, options);
            map->baked.summary = summarize(unpack_lean_map(map->baked.packed));
            if (map->baked.packed.has_plateau())
                map->baked.summary.plateau_fraction = plateau_fraction(map->baked.packed);
            map->baked.source = BakeSource::Auto;
            map->input_file = file;
            return map;
        },
        py::arg("path"), py::arg("max_size") = kDefaultMaxImageDimension,
        "Reads a LEAN-map KTX2 file with every check of `leanfade info`.");

    m.def(
        "inspect",
        [](const py::object& path) {
            const std::string file = path_text(path);
            io::Ktx2Info info;
            {
                py::gil_scoped_release unlocked;
                info = io::inspect_ktx2(file);
            }
            py::dict d;
            d["path"] = info.path;
            d["file_size"] = info.file_size;
            d["vk_format"] = info.vk_format;
            d["width"] = info.pixel_width;
            d["height"] = info.pixel_height;
            d["layer_count"] = info.layer_count;
            d["level_count"] = info.level_count;
            d["supercompression_scheme"] = info.supercompression_scheme;
            py::list levels;
            for (const io::Ktx2Level& level : info.levels) {
                py::dict l;
                l["width"] = level.width;
                l["height"] = level.height;
                l["byte_offset"] = level.byte_offset;
                l["byte_length"] = level.byte_length;
                levels.append(l);
            }
            d["levels"] = levels;
            py::dict key_values;
            for (const auto& [key, value] : info.key_values)
                key_values[py::str(key)] = py::bytes(value);
            d["key_values"] = key_values;
            const std::string* layout = info.find(io::kLayoutKey);
            d["lean_map"] = layout != nullptr && io::is_lean_layout_name(*layout);
            return d;
        },
        py::arg("path"),
        "Any KTX2 file's header, levels and key/values (bytes), checked structurally; "
        "lean_map: whether it says it is a LEAN map.");

    m.def(
        "roughness_textures",
        [](const py::object& source, const PyBakeSettings& settings, double base_roughness,
           const std::string& name) {
            if (!(base_roughness >= 0.0 && base_roughness <= 1.0))
                throw Error::setting("base_roughness", "must be in [0, 1]");
            Source input = read_source(source, name, settings);
            RoughnessTexturesRgba8 textures;
            {
                py::gil_scoped_release unlocked;
                const Image floats = std::holds_alternative<Image>(input.image)
                                         ? std::get<Image>(input.image)
                                         : std::get<UnormImage>(input.image).to_float();
                const BakeResult baked =
                    bake_lean_map(floats, settings.source, settings.options, input.name);
                RoughnessOptions options;
                options.base_roughness = float(base_roughness);
                options.threads = settings.options.threads;
                textures = roughness_textures_rgba8(baked.map, options, nullptr);
            }
            py::dict d;
            d["metallic_roughness"] = rgba8_levels(textures.metallic_roughness);
            d["normal"] = rgba8_levels(textures.normal);
            d["anisotropy"] = rgba8_levels(textures.anisotropy);
            return d;
        },
        py::arg("source"), py::arg("settings"), py::arg("base_roughness") = 0.0,
        py::arg("name") = "",
        "The engine textures of `bake --roughness-out` (metallic_roughness, normal, anisotropy), "
        "every level as a (h, w, 4) uint8 array.");

    m.def(
        "write_image",
        [](const py::object& path, const py::array& array) {
            const std::string file = path_text(path);
            std::variant<Image, UnormImage> image = image_from_array(array, file, 1 << 20);
            py::gil_scoped_release unlocked;
            if (std::holds_alternative<UnormImage>(image)) {
                const UnormImage& samples = std::get<UnormImage>(image);
                io::write_png(file, samples.to_float(), samples.max_value == 255 ? 8 : 16);
            } else if (io::has_extension(file, ".exr")) {
                io::write_exr(file, std::get<Image>(image));
            } else {
                io::write_pfm(file, std::get<Image>(image));
            }
        },
        py::arg("path"), py::arg("array"),
        "Writes a (H, W[, C]) array: uint8/uint16 as 8/16-bit PNG, floats as OpenEXR (.exr) or "
        "PFM.");

    m.def(
        "cache_key",
        [](const std::vector<py::bytes>& sources, const std::string& settings) {
            std::vector<std::vector<std::uint8_t>> copies;
            for (const py::bytes& b : sources) copies.push_back(bytes_of(b));
            py::gil_scoped_release unlocked;
            std::vector<std::span<const std::uint8_t>> spans(copies.begin(), copies.end());
            return scene::lean_cache_key(spans, settings);
        },
        py::arg("sources"), py::arg("settings"),
        "SHA-256 (hex) over a format tag, leanfade's version, SETTINGS and each source's length "
        "and bytes: the key of leanfade's cache.");
    m.def(
        "sha256_file",
        [](const py::object& path) {
            const std::string file = path_text(path);
            py::gil_scoped_release unlocked;
            return scene::sha256_file_hex(file);
        },
        py::arg("path"), "SHA-256 (hex) of a file, read in pieces.");
    m.def("default_cache_folder", &scene::default_lean_cache_folder,
          "$XDG_CACHE_HOME/leanfade, else $HOME/.cache/leanfade; '' when neither is set.");

    py::class_<scene::LeanMapCache>(m, "Cache")
        .def(py::init([](const py::object& folder, std::uint64_t max_bytes) {
                 return scene::LeanMapCache(folder.is_none() ? std::string() : path_text(folder),
                                            max_bytes);
             }),
             py::arg("folder"), py::arg("max_bytes") = scene::kMaxLeanCacheBytes)
        .def_property_readonly("folder", &scene::LeanMapCache::folder)
        .def("entry_path",
             [](const scene::LeanMapCache& c, const std::string& key, const std::string& suffix) {
                 return c.folder() + "/" + key + suffix;
             })
        .def(
            "find_file",
            [](const scene::LeanMapCache& c, const std::string& key,
               const std::string& suffix) -> py::object {
                std::optional<std::vector<std::uint8_t>> bytes;
                {
                    py::gil_scoped_release unlocked;
                    bytes = c.find_file(key, suffix);
                }
                if (!bytes) return py::none();
                return py::bytes(reinterpret_cast<const char*>(bytes->data()), bytes->size());
            },
            py::arg("key"), py::arg("suffix"))
        .def(
            "store_file",
            [](const scene::LeanMapCache& c, const std::string& key, const std::string& suffix,
               const py::bytes& bytes) {
                std::vector<std::uint8_t> copy = bytes_of(bytes);
                py::gil_scoped_release unlocked;
                return c.store_file(key, suffix, copy);
            },
            py::arg("key"), py::arg("suffix"), py::arg("data"))
        .def(
            "store_file_copy",
            [](const scene::LeanMapCache& c, const std::string& key, const std::string& suffix,
               const py::object& source, std::uint64_t size) {
                const std::string file = path_text(source);
                py::gil_scoped_release unlocked;
                return c.store_file_copy(key, suffix, file, size);
            },
            py::arg("key"), py::arg("suffix"), py::arg("source"), py::arg("size"))
        .def(
            "store_file_link",
            [](const scene::LeanMapCache& c, const std::string& key, const std::string& suffix,
               const py::object& source, std::uint64_t size) {
                const std::string file = path_text(source);
                py::gil_scoped_release unlocked;
                return c.store_file_link(key, suffix, file, size);
            },
            py::arg("key"), py::arg("suffix"), py::arg("source"), py::arg("size"),
            "Stores SOURCE (SIZE bytes) as the entry KEY+SUFFIX, by a hard link where the file "
            "system allows, else a copy; returns '' or why it could not.")
        .def(
            "serve_file_to",
            [](const scene::LeanMapCache& c, const std::string& key, const std::string& suffix,
               std::uint64_t size, const std::string& sha256, const py::object& output) {
                const std::string file = path_text(output);
                py::gil_scoped_release unlocked;
                return c.serve_file_to(key, suffix, size, sha256, file);
            },
            py::arg("key"), py::arg("suffix"), py::arg("size"), py::arg("sha256"),
            py::arg("output"),
            "Puts the entry KEY+SUFFIX at OUTPUT (atomically; a hard link where the file system "
            "allows) when it holds SIZE bytes whose SHA-256 is SHA256; False (OUTPUT untouched) "
            "otherwise.");
}
