// Glint's own modules: shared objects that a library loads with dlopen at first need, so that a
// program that never needs them never loads what they link (OpenImageIO and its some 260
// libraries: docs/research/start-and-writing.md). The image formats other than OpenEXR
// (libglint_image_formats.so, image/src/other_formats.h) and the renderer's texture cache
// (libglint_textures.so, renderer/src/scene/texture_cache.h). Internal to Glint.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace glint::detail {

/// Where Glint's module `fileName` is looked for: only the file the environment variable
/// `variable` names when it is set; else, in order, lib/glint/ beside the folder of the running
/// program (an installed Glint, and the build tree, whose programs are in bin/), the build tree's
/// lib/glint/ and the install prefix's.
std::vector<std::filesystem::path> moduleCandidates(const std::string& fileName,
                                                    const char* variable);

/// A module's entry point, or why it could not be had.
struct ModuleEntry {
    void* entry = nullptr;
    std::string failure;  ///< empty when `entry` is set
};

/// Loads the first of moduleCandidates(fileName, variable) that is a file (its symbols kept to
/// itself) and looks up its extern "C" function `entry`. Never throws: a failure names every
/// place tried, or the loader's reason.
ModuleEntry loadModule(const std::string& fileName, const char* variable, const char* entry);

}  // namespace glint::detail
