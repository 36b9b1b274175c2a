// Glint's own sources as text, for the tests that check what a kind's code may name (material
// kinds in the integrators, asset formats outside their own files).
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace glint::render::test {

/// The text of `file` with its comments (// to the end of the line, /* … */) blanked. (No
/// std::regex: GCC 12's <regex> trips -Werror=maybe-uninitialized in the sanitizer build.)
inline std::string codeOf(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    std::string code = text.str();
    for (std::size_t i = 0; i + 1 < code.size(); ++i) {
        if (code[i] != '/') continue;
        std::size_t end = std::string::npos;
        if (code[i + 1] == '/')
            end = code.find('\n', i);
        else if (code[i + 1] == '*')
            end = code.find("*/", i + 2) == std::string::npos ? std::string::npos
                                                              : code.find("*/", i + 2) + 2;
        else
            continue;
        if (end == std::string::npos) end = code.size();
        for (std::size_t j = i; j < end; ++j) code[j] = ' ';
        i = end - 1;
    }
    return code;
}

}  // namespace glint::render::test
