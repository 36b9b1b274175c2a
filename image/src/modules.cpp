// Finding and loading Glint's modules (glint/image/internal/modules.h).
#include "glint/image/internal/modules.h"

#include <dlfcn.h>

#include <cstdlib>
#include <system_error>

namespace glint::detail {

namespace fs = std::filesystem;

std::vector<fs::path> moduleCandidates(const std::string& fileName, const char* variable) {
    // A module the user names is the only one tried: a wrong path is an error, not a fallback.
    if (const char* named = std::getenv(variable); named && *named) return {fs::path(named)};
    std::vector<fs::path> out;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec)
        out.push_back((exe.parent_path() / ".." / "lib" / "glint" / fileName).lexically_normal());
    out.push_back(fs::path(GLINT_MODULE_BUILD_DIR) / fileName);
    out.push_back(fs::path(GLINT_MODULE_INSTALL_DIR) / fileName);
    return out;
}

ModuleEntry loadModule(const std::string& fileName, const char* variable, const char* entry) {
    std::string tried;
    for (const fs::path& candidate : moduleCandidates(fileName, variable)) {
        std::error_code ec;
        if (!fs::is_regular_file(candidate, ec)) {
            tried += (tried.empty() ? "" : ", ") + candidate.string();
            continue;
        }
        // RTLD_LOCAL: the module's symbols stay its own. A library it links that the process has
        // already loaded (OpenImageIO in a test that writes textures) is shared.
        void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = ::dlerror();
            return {nullptr, "cannot load " + candidate.string() + " (" +
                                 std::string(why ? why : "no reason given") + ")"};
        }
        void* function = ::dlsym(handle, entry);
        if (!function)
            return {nullptr, candidate.string() + " has no " + entry +
                                 " (a module of another Glint version)"};
        return {function, {}};
    }
    if (const char* named = std::getenv(variable); named && *named)
        return {nullptr, std::string(variable) + " names " + tried +
                             ", which is not a file (expected the path of " + fileName + ")"};
    return {nullptr, "the module " + fileName + " is in none of " + tried + "; set " + variable +
                         " to its path"};
}

}  // namespace glint::detail
