// _glint, the compiled part of the Python package glint (docs/python.md).
#include "bindings.h"

PYBIND11_MODULE(_glint, m) {
    m.doc() = "Glint's libraries from Python: images, rendering, denoising and metrics.";
    glint::python::bindErrors(m);
    glint::python::bindImage(m);
    glint::python::bindRender(m);
    glint::python::bindDenoise(m);
    glint::python::bindMetrics(m);
}
