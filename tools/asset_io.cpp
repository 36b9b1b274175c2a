#include "asset_io.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>

#include "glint/image/error.h"

namespace glint::tools {
namespace {

/// Temporary path beside `path` that keeps its extension (OpenImageIO picks the format by it).
std::filesystem::path temporaryPath(const std::filesystem::path& path) {
    std::filesystem::path tmp = path;
    tmp.replace_filename("." + path.stem().string() + ".tmp" + path.extension().string());
    return tmp;
}

/// Renames `tmp` onto `path`, removing `tmp` and throwing on failure.
void commit(const std::filesystem::path& tmp, const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error(ErrorKind::Io, "cannot rename temporary file into place", path.string());
    }
}

/// Writes `pixels` (of `format`) through OpenImageIO with `spec` to a temporary file, then renames.
void writeOiio(const OIIO::ImageSpec& spec, OIIO::TypeDesc format, const void* pixels,
               const std::filesystem::path& path) {
    const std::filesystem::path tmp = temporaryPath(path);
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) {
        throw Error(ErrorKind::Io, "no image writer for this extension: " + OIIO::geterror(),
                    path.string());
    }
    const bool ok =
        out->open(tmp.string(), spec) && out->write_image(format, pixels) && out->close();
    if (!ok) {
        const std::string message = out->geterror();
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw Error(ErrorKind::Io, "cannot write image: " + message, path.string());
    }
    commit(tmp, path);
}

}  // namespace

void writeObj(const Mesh& mesh, const std::filesystem::path& path, const std::string& comment) {
    GLINT_CHECK(mesh.normals.size() == mesh.positions.size());
    GLINT_CHECK(mesh.uvs.empty() || mesh.uvs.size() == mesh.positions.size());
    const std::filesystem::path tmp = temporaryPath(path);
    {
        std::ofstream file(tmp);
        if (!file) throw Error(ErrorKind::Io, "cannot open for writing", tmp.string());
        char line[128];
        file << "# " << comment << "\n";
        // Six significant digits keep the files small and the geometry exact to ~1e-6.
        for (const Vec3& p : mesh.positions) {
            std::snprintf(line, sizeof line, "v %.6g %.6g %.6g\n", p[0], p[1], p[2]);
            file << line;
        }
        for (const Vec3& n : mesh.normals) {
            std::snprintf(line, sizeof line, "vn %.5g %.5g %.5g\n", n[0], n[1], n[2]);
            file << line;
        }
        for (const Vec2& t : mesh.uvs) {
            std::snprintf(line, sizeof line, "vt %.6g %.6g\n", t[0], t[1]);
            file << line;
        }
        // OBJ indices are 1-based: "v//vn" without texture coordinates, "v/vt/vn" with them.
        for (const auto& f : mesh.faces) {
            file << 'f';
            for (int i : f) {
                const int k = i + 1;
                if (mesh.uvs.empty()) {
                    std::snprintf(line, sizeof line, " %d//%d", k, k);
                } else {
                    std::snprintf(line, sizeof line, " %d/%d/%d", k, k, k);
                }
                file << line;
            }
            file << '\n';
        }
        if (!file.flush()) throw Error(ErrorKind::Io, "write failed", tmp.string());
    }
    commit(tmp, path);
}

void writeHalfExr(const std::vector<float>& rgb, int width, int height,
                  const std::filesystem::path& path) {
    GLINT_CHECK(rgb.size() == std::size_t(width) * std::size_t(height) * 3);
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::HALF);
    spec.attribute("compression", "zip");
    writeOiio(spec, OIIO::TypeDesc::FLOAT, rgb.data(), path);
}

void writeSrgbPng(const std::vector<unsigned char>& rgb, int width, int height,
                  const std::filesystem::path& path) {
    GLINT_CHECK(rgb.size() == std::size_t(width) * std::size_t(height) * 3);
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    writeOiio(spec, OIIO::TypeDesc::UINT8, rgb.data(), path);
}

}  // namespace glint::tools
