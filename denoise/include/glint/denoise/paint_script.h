// Paint scripts (docs/painting.md): a JSON file listing filter layers and the edits (strokes,
// magic-wand fills, diffusion, constant weights) that `glint-denoise paint` replays on a render
// to build a painting session. Reading checks everything that does not need the image, so a bad
// script is refused before the render is read.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "glint/denoise/session.h"

namespace glint::denoise {

class PaintScript {
  public:
    /// Reads and checks a script file: JSON, every key known at every level, every value of the
    /// right type and in range (filters, parameters, layer indices, brushes). Throws
    /// glint::Error(Io) for a missing or unreadable file, a folder or a device, and
    /// glint::Error(Format) naming the file and the place: "line L, column C" for malformed JSON
    /// (a number JSON cannot hold, such as 1e400, included), else the JSON pointer.
    static PaintScript read(const std::filesystem::path& file);
    /// The same for script text; `file` names it in errors.
    static PaintScript parse(const std::string& text, const std::string& file);

    /// The layers, in order.
    const std::vector<LayerSpec>& layers() const;
    std::size_t editCount() const;

    /// Adds the layers on top of `session`'s and applies the edits in order (layer indices count
    /// from the first added layer). Throws glint::Error(Format) naming the script and the edit's
    /// JSON pointer for an edit that does not fit the image: a fill seed outside it, a diffusion
    /// of a layer with no painted pixel.
    void apply(Session& session) const;

  private:
    struct Impl;
    std::shared_ptr<const Impl> m_impl;
};

}  // namespace glint::denoise
