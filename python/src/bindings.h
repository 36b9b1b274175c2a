// What the files of the Python module _glint share (docs/python.md): each binds one part of Glint
// (image, render, denoise, metrics) and uses these helpers to turn Glint's types into Python's and
// back, and to run long work with the GIL released.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/image/parameters.h"

namespace glint::python {

namespace py = pybind11;

/// Registers glint.Error and its subclasses (one per glint::ErrorKind) and the translator that
/// raises them for a glint::Error with Glint's one-line message (errors.cpp).
void bindErrors(py::module_& m);
void bindImage(py::module_& m);    ///< Image, FrameBuffers, EXR/PNG (image_bindings.cpp)
void bindRender(py::module_& m);   ///< Scene, render (render_bindings.cpp)
void bindDenoise(py::module_& m);  ///< filters, bank, auto, sessions (denoise_bindings.cpp)
void bindMetrics(py::module_& m);  ///< metrics, FLIP, mc comparison (metrics_bindings.cpp)

// ---- numpy arrays (arrays.cpp) ----

/// A numpy view of `image`, shape (height, width, channels), float32, sharing its memory (no
/// copy); `owner` (the Python object that owns the image) becomes the array's base and so lives
/// as long as the view. Read-only unless `writable`.
py::array imageView(const Image& image, py::handle owner, bool writable = true);
/// A copy of `object` as an Image: a glint.Image, or a numpy array of float32, C-contiguous,
/// shaped (height, width) or (height, width, channels). Throws glint::Error(InvalidArgument)
/// naming `what` and what was expected otherwise (a float64 array, a non-contiguous slice...).
Image imageFromObject(py::handle object, const std::string& what);
/// Checks that `array` can be read as an image without conversion (see imageFromObject).
void checkImageArray(py::handle object, const std::string& what);

/// An image argument: the glint.Image passed (not copied) or a copy of the array passed.
class ImageArg {
  public:
    ImageArg(py::handle object, const std::string& what);
    const Image& get() const { return m_image ? *m_image : m_copy; }

  private:
    const Image* m_image = nullptr;
    Image m_copy;
};

/// Moves `image` into a new glint.Image Python object.
py::object toPython(Image image);

// ---- parameters (params.cpp) ----

/// A ParamSpec as a dict: name, label, min, max, default, soft_min, soft_max, scale, integer,
/// choices, colour, strings, help.
py::dict specDict(const ParamSpec& spec);
/// A dict of values (numbers, a choice's option name, a list of strings) as values for `specs`:
/// numbers as they are, text through the spec's parser. Throws glint::Error(InvalidArgument)
/// naming `where` for an unknown name or a value of the wrong type.
std::map<std::string, double> numbersFromDict(
    const std::vector<ParamSpec>& specs, py::handle values, const std::string& where,
    std::map<std::string, std::vector<std::string>>* strings);
/// Values for `specs` as a dict: numbers, a choice's option name, a list of strings.
py::dict valuesDict(const std::vector<ParamSpec>& specs,
                    const std::map<std::string, double>& numbers,
                    const std::map<std::string, std::vector<std::string>>& strings);
/// A region given as (x0, y0, x1, y1), half-open; None: empty.
std::optional<Rect> regionFrom(py::handle region);
/// (x0, y0, x1, y1) of `rect`.
py::tuple regionTuple(const Rect& rect);

// ---- long work (job.cpp) ----

/// Runs long work on a worker thread with the GIL released while the calling thread wakes
/// every 50 ms to take the GIL back briefly: it calls the Python `progress(fraction)` (None or a
/// callable; False stops the work) and checks for signals (Ctrl-C), so that Python callbacks run
/// on the caller's thread and Ctrl-C stops the work.
class Job {
  public:
    explicit Job(py::object progress);
    /// Records the fraction done (any thread).
    void report(double fraction) { m_fraction.store(fraction, std::memory_order_relaxed); }
    /// True once the work should stop (Ctrl-C, an exception in the callback, or False from it).
    bool stopping() const { return m_stop.load(std::memory_order_relaxed); }
    /// A glint::denoise::ProgressFn-compatible function: reports and returns !stopping().
    std::function<bool(double)> progressFn();
    /// Runs `work` (called with the GIL held; it may not touch Python objects) and returns when
    /// it ends. Raises what stopped it: the callback's exception, KeyboardInterrupt for Ctrl-C,
    /// glint.Cancelled when the callback returned False, or the work's own glint::Error.
    void run(const std::function<void()>& work);

  private:
    py::object m_progress;
    std::atomic<double> m_fraction{0.0};
    std::atomic<bool> m_stop{false};
};

}  // namespace glint::python
