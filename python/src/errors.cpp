// glint.Error and its subclasses: a glint::Error becomes the Python exception of its kind, with
// Glint's one-line message and the kind, file and place as attributes.
#include <Python.h>

#include <array>
#include <utility>

#include "bindings.h"
#include "glint/image/error.h"

namespace glint::python {
namespace {

/// One Python exception class per error kind: its name, the built-in class it also derives from
/// (so that `except ValueError` catches bad input as a Python programmer expects), its doc.
struct ErrorClass {
    ErrorKind kind;
    const char* name;
    PyObject* builtin;
    const char* doc;
};

/// The classes, indexed by ErrorKind (created once by bindErrors; they live as long as the
/// interpreter, as the module holds them).
std::array<PyObject*, 7> g_classes{};
PyObject* g_base = nullptr;

}  // namespace

void bindErrors(py::module_& m) {
    g_base = PyErr_NewExceptionWithDoc("glint.Error",
                                       "An error Glint reported: kind, message, file and place "
                                       "(where) as attributes; str() is Glint's one-line message.",
                                       PyExc_Exception, nullptr);
    m.add_object("Error", py::handle(g_base));
    const ErrorClass classes[] = {
        {ErrorKind::Io, "IoError", PyExc_OSError, "A file is missing, unreadable or unwritable."},
        {ErrorKind::Format, "FormatError", PyExc_ValueError,
         "A file was read but its content is not what was expected."},
        {ErrorKind::InvalidArgument, "InvalidArgument", PyExc_ValueError,
         "A parameter, option or array is out of range, unknown or of the wrong type."},
        {ErrorKind::Numeric, "NumericError", PyExc_ValueError,
         "NaN/Inf or another numerical failure."},
        {ErrorKind::Cancelled, "Cancelled", nullptr,
         "The work was stopped: its progress callback returned False."},
        {ErrorKind::OutOfMemory, "OutOfMemory", PyExc_MemoryError,
         "The work needs more memory than the machine or the caller allows."},
        {ErrorKind::Internal, "InternalError", PyExc_RuntimeError, "A broken invariant of Glint."},
    };
    for (const ErrorClass& c : classes) {
        py::tuple bases = c.builtin ? py::make_tuple(py::handle(g_base), py::handle(c.builtin))
                                    : py::make_tuple(py::handle(g_base));
        const std::string qualified = std::string("glint.") + c.name;
        PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), c.doc, bases.ptr(), nullptr);
        g_classes[std::size_t(c.kind)] = cls;
        m.add_object(c.name, py::handle(cls));
    }
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            PyObject* cls = g_classes[std::size_t(e.kind())];
            py::object instance =
                py::reinterpret_steal<py::object>(PyObject_CallFunction(cls, "s", e.what()));
            if (!instance) return;  // the call set its own error
            instance.attr("kind") = errorKindName(e.kind());
            instance.attr("message") = e.message();
            instance.attr("file") = e.file();
            instance.attr("where") = e.where();
            PyErr_SetObject(cls, instance.ptr());
        }
    });
}

}  // namespace glint::python
