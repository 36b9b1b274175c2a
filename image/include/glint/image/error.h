// glint::Error — the one exception type Glint's libraries throw, and the GLINT_CHECK macros.
#pragma once

#include <stdexcept>
#include <string>

namespace glint {

/// What went wrong, coarse enough for a CLI to choose an exit code and a GUI a message style.
enum class ErrorKind {
    Io,               ///< a file is missing, unreadable or unwritable
    Format,           ///< a file was read but its content is not what was expected
    InvalidArgument,  ///< a parameter or option is out of range or unknown
    Numeric,          ///< NaN/Inf or another numerical failure that cannot be handled
    Cancelled,        ///< the caller cancelled a long operation
    OutOfMemory,      ///< the work needs more memory than the machine or the caller allows
    Internal,         ///< a broken invariant (GLINT_CHECK)
};

/// Name of an error kind ("io", "format", ...).
const char* errorKindName(ErrorKind kind);

/// `text` on one line: control characters (a newline in a file name...) written as escapes
/// ("\n", "\x1b"), so that a message is always one line of a log.
std::string oneLine(const std::string& text);

/// A number for a message as %g writes it ("1e-07", "2.5", "1e+09", "nan"), not as
/// std::to_string's six fixed decimals, which write 1e-07 as "0.000000".
std::string numberText(double v);

/// A typed error with an optional file and place (line, channel, pixel...) it refers to.
class Error : public std::runtime_error {
  public:
    /// `file` and `where` may be empty; what() reads "file: where: message" on one line (control
    /// characters, e.g. a newline in a file name, are written as escapes: "\n", "\x1b").
    Error(ErrorKind kind, std::string message, std::string file = {}, std::string where = {});

    ErrorKind kind() const { return m_kind; }
    const std::string& message() const { return m_message; }
    const std::string& file() const { return m_file; }
    const std::string& where() const { return m_where; }

  private:
    ErrorKind m_kind;
    std::string m_message;
    std::string m_file;
    std::string m_where;
};

namespace detail {
[[noreturn]] void checkFailed(const char* expr, const char* file, int line, const std::string& msg);
}  // namespace detail

}  // namespace glint

/// Always-on invariant check: throws glint::Error(Internal) naming the expression and place.
#define GLINT_CHECK(cond, ...)                                                                \
    do {                                                                                      \
        if (!(cond)) ::glint::detail::checkFailed(#cond, __FILE__, __LINE__, "" __VA_ARGS__); \
    } while (0)

#ifdef NDEBUG
#define GLINT_DCHECK(cond, ...) \
    do {                        \
    } while (0)
#else
#define GLINT_DCHECK(cond, ...) GLINT_CHECK(cond, __VA_ARGS__)
#endif
