// glint.Scene: load a scene, edit its look (LookProperty, described by ParamSpec), render it with
// a progress callback and Ctrl-C, the GIL released while the renderer works.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cctype>
#include <memory>

#include "bindings.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings_codec.h"

namespace glint::python {
namespace {

namespace fs = std::filesystem;
using render::Renderer;
using render::Settings;

/// A loaded scene and its ray-tracing structures, until close() (then "dead": every use raises).
struct SceneHandle {
    std::unique_ptr<Renderer> renderer;
    int rendering = 0;  ///< renders running (on other Python threads): no close or edit then

    Renderer& get() {
        if (!renderer)
            throw Error(ErrorKind::InvalidArgument,
                        "the scene was closed (Scene.close() or the end of its with block); load "
                        "it again");
        return *renderer;
    }
    Renderer& editable() {
        Renderer& r = get();
        if (rendering > 0)
            throw Error(ErrorKind::InvalidArgument,
                        "the scene is rendering on another thread; wait for the render to end");
        return r;
    }
};

/// "max_depth" → "maxDepth": Python's spelling of a setting's name.
std::string camelCase(const std::string& name) {
    std::string out;
    bool upper = false;
    for (char c : name) {
        if (c == '_') {
            upper = true;
            continue;
        }
        out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return out;
}

/// A setting's text value as Python's value (int, float, bool or str).
py::object settingValue(const Settings& settings, const render::SettingSpec& spec) {
    const std::string text = render::settingText(settings, spec);
    switch (spec.kind) {
        case render::SettingKind::Integer:
            return py::int_(std::stoll(text));
        case render::SettingKind::Real:
            return py::float_(std::stod(text));
        case render::SettingKind::Boolean:
            return py::bool_(text == "true");
        case render::SettingKind::Choice:
            break;
    }
    return py::str(text);
}

/// `settings` with the named settings of `values` (Python names, snake_case or camelCase) set
/// through the settings codec, with its ranges and messages.
Settings withSettings(Settings settings, const py::dict& values) {
    for (const auto& [key, value] : values) {
        const std::string given = py::str(key);
        const std::string name = camelCase(given);
        if (name == "threads") {
            settings.threads = value.cast<int>();
            continue;
        }
        if (name == "timeLimit") {
            settings.timeLimit = value.cast<double>();
            continue;
        }
        if (name == "positionLayer") {
            settings.positionLayer = value.cast<bool>();
            continue;
        }
        const render::SettingSpec* spec = render::findSetting(name);
        if (!spec) {
            std::string names = "threads, time_limit, position_layer";
            for (const render::SettingSpec& s : render::settingSpecs())
                names += std::string(", ") + s.name;
            throw Error(ErrorKind::InvalidArgument,
                        "unknown setting '" + given + "' (" + names + ")", {}, given);
        }
        std::string text;
        if (py::isinstance<py::bool_>(value))
            text = value.cast<bool>() ? "true" : "false";
        else if (py::isinstance<py::float_>(value))
            text = py::repr(value);
        else
            text = py::str(value);
        try {
            render::setSetting(settings, *spec, text, {}, given);
        } catch (const Error& e) {
            throw Error(ErrorKind::InvalidArgument, e.message(), e.file(), e.where());
        }
    }
    try {
        render::validate(settings);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidArgument, e.message(), e.file(), e.where());
    }
    return settings;
}

py::dict statsDict(const render::RenderStats& s) {
    py::dict d;
    d["seconds"] = s.seconds;
    d["samples"] = s.samples;
    d["rays"] = s.rays;
    d["non_finite_samples"] = s.nonFiniteSamples;
    d["passes"] = s.passes;
    d["completed_spp"] = s.completedSpp;
    d["cancelled"] = s.cancelled;
    return d;
}

py::list lookList(const render::Scene& scene) {
    py::list items;
    for (const render::LookItem& item : scene.look()) {
        py::dict d;
        d["name"] = item.name;
        d["kind"] = item.kind == render::LookItemKind::Material ? "material" : "environment";
        d["type"] = item.type;
        d["light"] = item.light;
        py::list properties;
        for (const render::LookProperty& p : item.properties) {
            py::dict pd = specDict(p);
            pd["value"] = p.isColour
                              ? py::object(py::make_tuple(p.value[0], p.value[1], p.value[2]))
                              : py::object(py::float_(p.value[0]));
            properties.append(pd);
        }
        d["properties"] = properties;
        items.append(d);
    }
    return items;
}

}  // namespace

void bindRender(py::module_& m) {
    py::class_<render::RenderResult>(m, "RenderResult", "A rendered frame and what it took.")
        .def_readonly("frame", &render::RenderResult::frame)
        .def_property_readonly("stats",
                               [](const render::RenderResult& r) { return statsDict(r.stats); });

    py::class_<SceneHandle>(m, "Scene",
                            "A loaded scene with its ray-tracing structures; render() it, edit "
                            "its look. close() (or a with block) frees it.")
        .def_property_readonly("width", [](SceneHandle& s) { return s.get().scene().width(); })
        .def_property_readonly("height", [](SceneHandle& s) { return s.get().scene().height(); })
        .def_property_readonly("path", [](SceneHandle& s) { return s.get().scene().path(); })
        .def_property_readonly("triangles",
                               [](SceneHandle& s) { return s.get().scene().triangleCount(); })
        .def_property_readonly("warnings",
                               [](SceneHandle& s) { return s.get().scene().warnings(); })
        .def_property_readonly(
            "settings",
            [](SceneHandle& s) {
                py::dict d;
                const Settings& settings = s.get().scene().settings();
                for (const render::SettingSpec& spec : render::settingSpecs())
                    d[spec.name] = settingValue(settings, spec);
                return d;
            },
            "The scene's render block (every named setting).")
        .def("look", [](SceneHandle& s) { return lookList(s.get().scene()); })
        .def(
            "set_look",
            [](SceneHandle& s, const std::string& item, const std::string& property,
               py::handle value) {
                render::Scene& scene = s.editable().scene();
                if (py::isinstance<py::sequence>(value) && !py::isinstance<py::str>(value)) {
                    const auto v = value.cast<std::vector<double>>();
                    if (v.size() != 3)
                        throw Error(ErrorKind::InvalidArgument,
                                    "a colour takes 3 values, got " + std::to_string(v.size()), {},
                                    property);
                    scene.setLook(item, property, std::array<double, 3>{v[0], v[1], v[2]});
                } else {
                    scene.setLook(item, property, value.cast<double>());
                }
            },
            py::arg("item"), py::arg("property"), py::arg("value"),
            "Sets one look property (a number, or 3 values for a colour).")
        .def(
            "save",
            [](SceneHandle& s, const fs::path& path) { render::saveScene(s.get().scene(), path); },
            py::arg("path"), "Writes the scene with its look edits as scene.json.")
        .def(
            "render",
            [](SceneHandle& s, py::object progress, py::kwargs kwargs) {
                Renderer& renderer = s.editable();
                const Settings settings = withSettings(renderer.scene().settings(), kwargs);
                Job job(std::move(progress));
                render::Callbacks callbacks;
                callbacks.progress = [&job](int, double fraction) { job.report(fraction); };
                callbacks.cancel = [&job] { return job.stopping(); };
                render::RenderResult result;
                ++s.rendering;
                try {
                    job.run([&] { result = renderer.render(settings, callbacks); });
                } catch (...) {
                    --s.rendering;
                    throw;
                }
                --s.rendering;
                return result;
            },
            py::arg("progress") = py::none(),
            "Renders with the scene's settings and those given by name (spp=, seed=, threads=, "
            "max_depth=, sampler=, half_buffers=...). progress(fraction) is called on this "
            "thread; returning False raises glint.Cancelled, Ctrl-C KeyboardInterrupt.")
        .def("close",
             [](SceneHandle& s) {
                 if (s.rendering > 0) s.editable();
                 s.renderer.reset();
             })
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__", [](SceneHandle& s, py::args) {
            if (s.rendering == 0) s.renderer.reset();
            return false;
        });

    m.def(
        "load_scene",
        [](const fs::path& path, std::uint64_t memoryLimit) {
            SceneHandle handle;
            py::gil_scoped_release release;
            render::Scene scene = render::loadScene(path, memoryLimit);
            Settings settings = scene.settings();
            settings.memoryLimit = memoryLimit;
            handle.renderer = std::make_unique<Renderer>(std::move(scene), settings);
            return handle;
        },
        py::arg("path"), py::arg("memory_limit") = 0,
        "Loads scene.json (or a bare glTF/OBJ asset) and builds its ray-tracing structures.");
}

}  // namespace glint::python
