#include "glint/image/error.h"

#include <cstdio>

namespace glint {

const char* errorKindName(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::Io:
            return "io";
        case ErrorKind::Format:
            return "format";
        case ErrorKind::InvalidArgument:
            return "invalid-argument";
        case ErrorKind::Numeric:
            return "numeric";
        case ErrorKind::Cancelled:
            return "cancelled";
        case ErrorKind::OutOfMemory:
            return "out-of-memory";
        case ErrorKind::Internal:
            return "internal";
    }
    return "unknown";
}

std::string numberText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

std::string oneLine(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if (c >= 0x20 && c != 0x7f) {
            out += ch;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else {
            static const char hex[] = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

namespace {
std::string compose(const std::string& message, const std::string& file, const std::string& where) {
    std::string text;
    if (!file.empty()) text += file + ": ";
    if (!where.empty()) text += where + ": ";
    return oneLine(text + message);
}
}  // namespace

Error::Error(ErrorKind kind, std::string message, std::string file, std::string where)
    : std::runtime_error(compose(message, file, where)),
      m_kind(kind),
      m_message(std::move(message)),
      m_file(std::move(file)),
      m_where(std::move(where)) {}

namespace detail {
void checkFailed(const char* expr, const char* file, int line, const std::string& msg) {
    std::string text = std::string("check failed: ") + expr;
    if (!msg.empty()) text += " (" + msg + ")";
    throw Error(ErrorKind::Internal, text, file, "line " + std::to_string(line));
}
}  // namespace detail

}  // namespace glint
