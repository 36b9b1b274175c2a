// glint.Image and glint.FrameBuffers (their pixels as numpy views, no copy), layered EXR reading
// and writing, PNG display values for Jupyter.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "bindings.h"
#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::python {
namespace {

namespace fs = std::filesystem;

/// The layer a user names ("color", "albedo", "depthVariance"...); KeyError otherwise.
Layer layerNamed(const std::string& name) {
    if (const auto layer = findLayer(name)) return *layer;
    std::string names;
    for (int i = 0; i < kLayerCount; ++i)
        names += (i ? ", " : "") + std::string(layerDisplayName(Layer(i)));
    throw py::key_error("no layer '" + name + "' (layers: " + names + ")");
}

/// An 8-bit PNG of `image`'s display values at `exposure` stops, as bytes.
py::bytes pngBytes(const Image& image, float exposure) {
    const fs::path file = fs::temp_directory_path() /
                          ("glint-repr-" + std::to_string(::getpid()) + "-" +
                           std::to_string(reinterpret_cast<std::uintptr_t>(&image)) + ".png");
    DisplayOptions options;
    options.exposure = exposure;
    writePng(image, file, options);
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::error_code ec;
    fs::remove(file, ec);
    return py::bytes(bytes);
}

ExrCompression parseCompression(const std::string& name) {
    if (name == "none") return ExrCompression::None;
    if (name == "zip") return ExrCompression::Zip;
    throw Error(ErrorKind::InvalidArgument, "unknown compression '" + name + "' (none, zip)", {},
                "compression");
}

/// The frame's metadata as a dict (spp, seed, integrator, scene, and every extra attribute).
py::dict metadataDict(const FrameMetadata& m) {
    py::dict d;
    d["spp"] = m.spp;
    d["seed"] = m.seed;
    d["integrator"] = m.integrator;
    d["scene"] = m.scene;
    d["non_finite_samples"] = m.nonFiniteSamples;
    d["source"] = m.source;
    for (const auto& [key, value] : m.extra) d[py::str(key)] = value;
    return d;
}

}  // namespace

void bindImage(py::module_& m) {
    py::class_<Image>(m, "Image", py::buffer_protocol(), py::dynamic_attr(),
                      "A float image, (height, width, channels) interleaved. np.asarray(image) "
                      "and image.array share its memory.")
        .def(py::init([](py::handle array) { return imageFromObject(array, "array"); }),
             py::arg("array"), "A copy of a float32 array shaped (h, w) or (h, w, c).")
        .def(py::init([](int width, int height, int channels, float fill) {
                 if (width < 0 || height < 0 || channels < 1 || channels > 64)
                     throw Error(ErrorKind::InvalidArgument,
                                 "expected width, height >= 0 and 1 to 64 channels");
                 return Image(width, height, channels, fill);
             }),
             py::arg("width"), py::arg("height"), py::arg("channels") = 3, py::arg("fill") = 0.0f)
        .def_property_readonly("width", &Image::width)
        .def_property_readonly("height", &Image::height)
        .def_property_readonly("channels", &Image::channels)
        .def_property_readonly(
            "shape",
            [](const Image& i) { return py::make_tuple(i.height(), i.width(), i.channels()); })
        .def_property_readonly(
            "array", [](py::object self) { return imageView(self.cast<Image&>(), self); },
            "A numpy view (no copy) of the pixels, (height, width, channels).")
        .def_buffer([](Image& i) {
            const auto f = py::ssize_t(sizeof(float));
            return py::buffer_info(
                i.data().data(), f, py::format_descriptor<float>::format(), 3,
                {py::ssize_t(i.height()), py::ssize_t(i.width()), py::ssize_t(i.channels())},
                {py::ssize_t(i.width()) * i.channels() * f, py::ssize_t(i.channels()) * f, f});
        })
        .def("copy", [](const Image& i) { return Image(i); })
        .def("_png", &pngBytes, py::arg("exposure") = 0.0f)
        .def("__repr__", [](const Image& i) {
            return "<glint.Image " + std::to_string(i.width()) + "x" + std::to_string(i.height()) +
                   "x" + std::to_string(i.channels()) + ">";
        });

    py::class_<FrameBuffers>(m, "FrameBuffers", py::dynamic_attr(),
                             "The named layers of a render. frame['albedo'] is a numpy view (no "
                             "copy) of a layer, (height, width, channels).")
        .def(py::init([](int width, int height) {
                 if (width < 1 || height < 1)
                     throw Error(ErrorKind::InvalidArgument, "expected a size of at least 1x1");
                 return FrameBuffers(width, height);
             }),
             py::arg("width"), py::arg("height"))
        .def_property_readonly("width", &FrameBuffers::width)
        .def_property_readonly("height", &FrameBuffers::height)
        .def_property_readonly("layers",
                               [](const FrameBuffers& f) {
                                   std::vector<std::string> names;
                                   for (int i = 0; i < kLayerCount; ++i)
                                       if (f.has(Layer(i)))
                                           names.emplace_back(layerDisplayName(Layer(i)));
                                   return names;
                               })
        .def("__contains__",
             [](const FrameBuffers& f, const std::string& name) {
                 const auto layer = findLayer(name);
                 return layer && f.has(*layer);
             })
        .def("__getitem__",
             [](py::object self, const std::string& name) {
                 FrameBuffers& f = self.cast<FrameBuffers&>();
                 const Layer layer = layerNamed(name);
                 if (!f.has(layer)) throw py::key_error("the frame has no layer '" + name + "'");
                 return imageView(f.layer(layer), self);
             })
        .def(
            "__setitem__",
            [](FrameBuffers& f, const std::string& name, py::handle array) {
                const Layer layer = layerNamed(name);
                Image image = imageFromObject(array, "frame['" + name + "']");
                const int channels = layerInfo(layer).channels;
                if (image.width() != f.width() || image.height() != f.height() ||
                    image.channels() != channels)
                    throw Error(ErrorKind::InvalidArgument,
                                "expected shape (" + std::to_string(f.height()) + ", " +
                                    std::to_string(f.width()) + ", " + std::to_string(channels) +
                                    "), got (" + std::to_string(image.height()) + ", " +
                                    std::to_string(image.width()) + ", " +
                                    std::to_string(image.channels()) + ")",
                                {}, "frame['" + name + "']");
                // Into the layer's own storage when it exists, so that views of it stay valid.
                if (Image* existing = f.find(layer))
                    std::copy(image.data().begin(), image.data().end(), existing->data().begin());
                else
                    f.set(layer, std::move(image));
            },
            "Sets a layer from a float32 array (copied into the frame).")
        .def_property_readonly("metadata",
                               [](const FrameBuffers& f) { return metadataDict(f.metadata()); })
        .def("copy", [](const FrameBuffers& f) { return FrameBuffers(f); })
        .def(
            "write_exr",
            [](const FrameBuffers& f, const fs::path& path, const std::string& compression) {
                ExrWriteOptions options;
                options.compression = parseCompression(compression);
                py::gil_scoped_release release;
                writeExr(f, path, options);
            },
            py::arg("path"), py::arg("compression") = "none",
            "Writes a layered float EXR (temporary name, then renamed).")
        .def(
            "_png",
            [](const FrameBuffers& f, float exposure) { return pngBytes(f.color(), exposure); },
            py::arg("exposure") = 0.0f)
        .def("__repr__", [](const FrameBuffers& f) {
            return "<glint.FrameBuffers " + std::to_string(f.width()) + "x" +
                   std::to_string(f.height()) + ">";
        });

    m.def(
        "read_exr",
        [](const fs::path& path) {
            py::gil_scoped_release release;
            return readExr(path);
        },
        py::arg("path"),
        "Reads a layered EXR (Glint's names, Cycles/pbrt/Mitsuba aliases) into FrameBuffers.");
    m.def(
        "read_image",
        [](const fs::path& path, bool linearize) {
            py::gil_scoped_release release;
            return readImage(path, linearize);
        },
        py::arg("path"), py::arg("linearize") = true,
        "Reads an EXR, PNG, JPEG or any image OpenImageIO reads as a float glint.Image (sRGB "
        "made linear).");
    m.def(
        "write_png",
        [](py::handle image, const fs::path& path, float exposure) {
            const ImageArg arg(image, "image");
            DisplayOptions options;
            options.exposure = exposure;
            writePng(arg.get(), path, options);
        },
        py::arg("image"), py::arg("path"), py::arg("exposure") = 0.0f,
        "Writes an 8-bit PNG of the display values (exposure in stops, sRGB).");
    m.def("layer_names", [] {
        std::vector<std::string> names;
        for (int i = 0; i < kLayerCount; ++i) names.emplace_back(layerDisplayName(Layer(i)));
        return names;
    });
}

}  // namespace glint::python
