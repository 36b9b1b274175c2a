// Images as numpy arrays: views of Glint's images that share their memory (the owning Python
// object as the array's base), and checked copies of arrays into Glint's images.
#include <algorithm>
#include <cstring>

#include "bindings.h"
#include "glint/image/error.h"

namespace glint::python {

py::array imageView(const Image& image, py::handle owner, bool writable) {
    const auto h = py::ssize_t(image.height()), w = py::ssize_t(image.width()),
               c = py::ssize_t(image.channels());
    const auto f = py::ssize_t(sizeof(float));
    // The base keeps `owner`, and so the image's storage, alive as long as the view.
    py::array view(py::dtype::of<float>(), {h, w, c}, {w * c * f, c * f, f}, image.data().data(),
                   owner);
    if (!writable) view.attr("setflags")(py::arg("write") = false);
    return view;
}

namespace {

/// What is wrong with `array` as an image (empty when nothing).
std::string arrayProblem(const py::array& array) {
    if (!py::isinstance<py::array_t<float>>(array))
        return "is a " + std::string(py::str(array.dtype())) +
               " array; Glint's images are float32 (use array.astype(numpy.float32))";
    if (array.ndim() != 2 && array.ndim() != 3)
        return "has " + std::to_string(array.ndim()) +
               " dimensions; expected (height, width) or (height, width, channels)";
    if (!(array.flags() & py::array::c_style))
        return "is not C-contiguous (a slice or a transpose); use numpy.ascontiguousarray(array)";
    if (array.shape(0) > (1 << 30) || array.shape(1) > (1 << 30) ||
        (array.ndim() == 3 && (array.shape(2) < 1 || array.shape(2) > 64)))
        return "has a shape Glint's images cannot take (channels 1 to 64)";
    return {};
}

}  // namespace

void checkImageArray(py::handle object, const std::string& what) {
    if (py::isinstance<Image>(object)) return;
    if (!py::isinstance<py::array>(object))
        throw Error(ErrorKind::InvalidArgument,
                    std::string("is a ") + Py_TYPE(object.ptr())->tp_name +
                        "; expected a glint.Image or a numpy float32 array",
                    {}, what);
    const std::string problem = arrayProblem(py::reinterpret_borrow<py::array>(object));
    if (!problem.empty()) throw Error(ErrorKind::InvalidArgument, problem, {}, what);
}

Image imageFromObject(py::handle object, const std::string& what) {
    if (py::isinstance<Image>(object)) return object.cast<const Image&>();
    checkImageArray(object, what);
    const auto array = py::reinterpret_borrow<py::array>(object);
    const int channels = array.ndim() == 3 ? int(array.shape(2)) : 1;
    Image image(int(array.shape(1)), int(array.shape(0)), channels);
    if (!image.data().empty())
        std::memcpy(image.data().data(), array.data(), image.data().size_bytes());
    return image;
}

ImageArg::ImageArg(py::handle object, const std::string& what) {
    if (py::isinstance<Image>(object))
        m_image = &object.cast<const Image&>();
    else
        m_copy = imageFromObject(object, what);
}

py::object toPython(Image image) {
    return py::cast(std::move(image), py::return_value_policy::move);
}

}  // namespace glint::python
