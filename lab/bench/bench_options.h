// Command-line options of the benchmarks in lab/bench: "--name value" pairs. One parser for
// what bench_bank, bench_auto and bench_denoise_a each parsed by hand: a lone last option
// without a value, a value that is not a whole integer, and an unknown option each end the run
// with one line naming the option (exit code 2), instead of being ignored or ending in an
// uncaught exception.
#pragma once

#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace glint::bench {

/// A bad option value; parseOptions prints its message and returns 2.
struct OptionError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The integer that is the whole of `text`, or OptionError naming `name`.
inline int intOption(const std::string& name, const std::string& text) {
    std::size_t used = 0;
    int value = 0;
    try {
        value = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size())
        throw OptionError(name + " needs an integer, not '" + text + "'");
    return value;
}

/// The number that is the whole of `text`, or OptionError naming `name`.
inline double numberOption(const std::string& name, const std::string& text) {
    std::size_t used = 0;
    double value = 0.0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size())
        throw OptionError(name + " needs a number, not '" + text + "'");
    return value;
}

/// The options bench_bank and bench_auto share: the cornell render they time on (--size, --spp),
/// the threads, the bank's --members, the --reps (at least 1) and --retain-freed.
struct RenderBankOptions {
    int size = 1024, spp = 4, threads = 2, members = 64, reps = 1, retainFreed = 1;
    /// Sets the option `name` names to `value`; false for any other name.
    bool take(const std::string& name, int value) {
        if (name == "--size")
            size = value;
        else if (name == "--spp")
            spp = value;
        else if (name == "--threads")
            threads = value;
        else if (name == "--members")
            members = value;
        else if (name == "--reps")
            reps = value < 1 ? 1 : value;
        else if (name == "--retain-freed")
            retainFreed = value;
        else
            return false;
        return true;
    }
};

/// Calls handle(name, value) for each "--name value" pair of argv[1 …]; `handle` returns false
/// for a name it does not know, and may throw OptionError for a bad value. Returns 0, or 2
/// after printing "program: …" on stderr for a lone last option, an unknown one or a bad value.
inline int parseOptions(const char* program, int argc, char** argv,
                        const std::function<bool(const std::string&, const std::string&)>& handle) {
    if (argc % 2 == 0) {  // options come in pairs: a lone last one has no value
        std::fprintf(stderr, "%s: option %s needs a value\n", program, argv[argc - 1]);
        return 2;
    }
    for (int i = 1; i + 1 < argc; i += 2) {
        try {
            if (!handle(argv[i], argv[i + 1])) {
                std::fprintf(stderr, "%s: unknown option %s\n", program, argv[i]);
                return 2;
            }
        } catch (const OptionError& e) {
            std::fprintf(stderr, "%s: %s\n", program, e.what());
            return 2;
        }
    }
    return 0;
}

/// The items of a comma-separated option value ("glossy,dof" → {"glossy", "dof"}).
inline std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (std::size_t comma; (comma = text.find(',', start)) != std::string::npos; start = comma + 1)
        out.push_back(text.substr(start, comma - start));
    if (start < text.size()) out.push_back(text.substr(start));
    return out;
}

/// Options bound to variables by name: `OptionTable t; t.bind("--seed", seed); …;
/// return t.parse("bench_x", argc, argv, first)` — each value read as its variable's type
/// (text, integer, 64-bit integer, number), a bad one or an unknown name ending the run with
/// one line (exit code 2, as parseOptions). `first` is argv's first option (after positionals).
class OptionTable {
  public:
    void bind(std::string name, std::string& to) {
        m_rows.push_back(
            {std::move(name), [&to](const std::string&, const std::string& v) { to = v; }});
    }
    void bind(std::string name, int& to) {
        m_rows.push_back({std::move(name), [&to](const std::string& n, const std::string& v) {
                              to = intOption(n, v);
                          }});
    }
    void bind(std::string name, unsigned long long& to) {
        m_rows.push_back(
            {std::move(name), [&to](const std::string& n, const std::string& v) {
                 to = number<unsigned long long>(
                     n, v, [](const std::string& t, std::size_t* u) { return std::stoull(t, u); });
             }});
    }
    void bind(std::string name, double& to) {
        m_rows.push_back({std::move(name), [&to](const std::string& n, const std::string& v) {
                              to = number<double>(n, v, [](const std::string& t, std::size_t* u) {
                                  return std::stod(t, u);
                              });
                          }});
    }

    /// Reads argv[first …] as "--name value" pairs; 0, or 2 after one line on stderr.
    int parse(const char* program, int argc, char** argv, int first = 1) const {
        if ((argc - first) % 2 != 0) {
            std::fprintf(stderr, "%s: option %s needs a value\n", program, argv[argc - 1]);
            return 2;
        }
        for (int i = first; i + 1 < argc; i += 2) {
            const std::string name = argv[i];
            const Row* row = nullptr;
            for (const Row& r : m_rows)
                if (r.name == name) row = &r;
            if (!row) {
                std::fprintf(stderr, "%s: unknown option %s\n", program, argv[i]);
                return 2;
            }
            try {
                row->set(name, argv[i + 1]);
            } catch (const OptionError& e) {
                std::fprintf(stderr, "%s: %s\n", program, e.what());
                return 2;
            }
        }
        return 0;
    }

  private:
    template <typename T, typename Read>
    static T number(const std::string& name, const std::string& text, Read read) {
        std::size_t used = 0;
        T value{};
        try {
            value = read(text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != text.size())
            throw OptionError(name + " needs a number, not '" + text + "'");
        return value;
    }

    struct Row {
        std::string name;
        std::function<void(const std::string&, const std::string&)> set;
    };
    std::vector<Row> m_rows;
};

}  // namespace glint::bench
