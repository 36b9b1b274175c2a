// Checks of the docs against the tree (issue 47, "Docs as a reference"): the source layout in
// docs/architecture.md names every folder of the six modules and no other; every relative link
// of README.md, docs/*.md and docs/lab/*.md reaches a file (and, with #anchor, a heading of it);
// every source path a reference page names exists; the newcomer's lists of where to add a filter, a
// material kind and an asset format hold at most three files each, every one of which exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = GLINT_SOURCE_DIR;

/// The modules whose folders the layout section lists.
const std::vector<std::string> kModules = {"image", "renderer", "denoise", "pipeline",
                                           "gui",   "lab",      "python"};

std::string readText(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<std::string> linesOf(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

/// The heading's level (number of leading '#') or 0 when `line` is not a heading.
int headingLevel(const std::string& line) {
    std::size_t n = 0;
    while (n < line.size() && line[n] == '#') ++n;
    return n > 0 && n <= 6 && n < line.size() && line[n] == ' ' ? int(n) : 0;
}

/// The lines of the section under the heading `title` (e.g. "## Source layout"), up to the next
/// heading of the same or a higher level; empty when there is no such heading.
std::vector<std::string> sectionOf(const std::string& text, const std::string& title) {
    std::vector<std::string> out;
    const int level = headingLevel(title);
    bool inside = false, fence = false;
    for (const std::string& line : linesOf(text)) {
        if (line.rfind("```", 0) == 0) fence = !fence;
        const int h = fence ? 0 : headingLevel(line);
        if (inside && h > 0 && h <= level) break;
        if (inside) out.push_back(line);
        if (line == title) inside = true;
    }
    return out;
}

/// The code spans (`…`) of `lines`.
std::vector<std::string> codeSpans(const std::vector<std::string>& lines) {
    std::vector<std::string> spans;
    for (const std::string& line : lines) {
        std::size_t a = line.find('`');
        while (a != std::string::npos) {
            const std::size_t b = line.find('`', a + 1);
            if (b == std::string::npos) break;
            spans.push_back(line.substr(a + 1, b - a - 1));
            a = line.find('`', b + 1);
        }
    }
    return spans;
}

/// What is wrong with a layout section that names the folders `named` (e.g. "renderer/src/scene/"),
/// for the tree at `root`: each folder of a module missing from it (a folder counts as named when
/// it or a folder below it is), and each named folder that does not exist. Empty when it agrees.
std::vector<std::string> layoutProblems(const fs::path& root, const std::set<std::string>& named) {
    std::vector<std::string> problems;
    std::set<std::string> covered;
    for (const std::string& folder : named) {
        if (!fs::is_directory(root / folder))
            problems.push_back("names '" + folder + "', which is not a folder of the tree");
        for (fs::path p = fs::path(folder).parent_path(); !p.empty(); p = p.parent_path())
            covered.insert(p.generic_string() + "/");
    }
    for (const std::string& module : kModules) {
        if (!fs::is_directory(root / module)) continue;
        for (auto it = fs::recursive_directory_iterator(root / module);
             it != fs::recursive_directory_iterator(); ++it) {
            if (!it->is_directory()) continue;
            const std::string name = it->path().filename().string();
            if (name.front() == '.' || name == "__pycache__") {
                it.disable_recursion_pending();
                continue;
            }
            const std::string folder = fs::relative(it->path(), root).generic_string() + "/";
            if (!named.count(folder) && !covered.count(folder))
                problems.push_back("does not name '" + folder + "'");
        }
    }
    return problems;
}

/// The module folders a layout section names: its code spans that start with a module's name
/// and end in '/'.
std::set<std::string> namedFolders(const std::vector<std::string>& section) {
    std::set<std::string> named;
    for (const std::string& span : codeSpans(section)) {
        if (span.empty() || span.back() != '/') continue;
        for (const std::string& module : kModules)
            if (span.rfind(module + "/", 0) == 0) named.insert(span);
    }
    return named;
}

/// GitHub's anchor for a heading's text: lower case, punctuation and symbols dropped (letters,
/// digits, marks, '_', '-' and spaces kept; a space becomes '-'). Non-ASCII code points are kept
/// but for the punctuation and symbols the docs use.
std::string anchorOf(const std::string& heading) {
    static const std::set<std::string> dropped = {"—", "–", "…", "×", "·", "→", "←", "≤",
                                                  "≥", "±", "‘", "’", "“", "”", "√", "≈"};
    std::string out;
    for (std::size_t i = 0; i < heading.size();) {
        const unsigned char c = heading[i];
        const std::size_t n = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
        const std::string cp = heading.substr(i, n);
        i += n;
        if (n > 1) {
            if (!dropped.count(cp)) out += cp;
        } else if (std::isalnum(c) || c == '_' || c == '-') {
            out += char(std::tolower(c));
        } else if (c == ' ') {
            out += '-';
        }
    }
    return out;
}

/// The anchors of a Markdown file's headings (outside code fences), GitHub's numbering of
/// repeats included ("x", "x-1", …).
std::set<std::string> anchorsOf(const std::string& text) {
    std::set<std::string> anchors;
    std::map<std::string, int> seen;
    bool fence = false;
    for (const std::string& line : linesOf(text)) {
        if (line.rfind("```", 0) == 0) fence = !fence;
        const int h = fence ? 0 : headingLevel(line);
        if (h == 0) continue;
        const std::string a = anchorOf(line.substr(std::size_t(h) + 1));
        const int n = seen[a]++;
        anchors.insert(n == 0 ? a : a + "-" + std::to_string(n));
    }
    return anchors;
}

/// The broken relative links of the Markdown file `file` (outside code fences and code spans):
/// "file:line: target: why".
std::vector<std::string> brokenLinks(const fs::path& file) {
    std::vector<std::string> broken;
    bool fence = false;
    int number = 0;
    for (std::string line : linesOf(readText(file))) {
        ++number;
        if (line.rfind("```", 0) == 0) fence = !fence;
        if (fence) continue;
        // Blank code spans, whose text is not Markdown.
        for (std::size_t a = line.find('`'); a != std::string::npos;) {
            const std::size_t b = line.find('`', a + 1);
            if (b == std::string::npos) break;
            std::fill(line.begin() + std::ptrdiff_t(a), line.begin() + std::ptrdiff_t(b) + 1, ' ');
            a = line.find('`', b + 1);
        }
        for (std::size_t at = line.find("]("); at != std::string::npos;
             at = line.find("](", at + 2)) {
            const std::size_t end = line.find(')', at + 2);
            if (end == std::string::npos) break;
            const std::string target = line.substr(at + 2, end - at - 2);
            if (target.empty() || target.find(' ') != std::string::npos) continue;
            if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0)
                continue;
            const std::size_t hash = target.find('#');
            const std::string path = target.substr(0, hash);
            const fs::path resolved = path.empty() ? file : file.parent_path() / path;
            const std::string place = file.string() + ":" + std::to_string(number) + ": " + target;
            if (!fs::exists(resolved)) {
                broken.push_back(place + ": no such file");
                continue;
            }
            if (hash != std::string::npos && resolved.extension() == ".md" &&
                !anchorsOf(readText(resolved)).count(target.substr(hash + 1)))
                broken.push_back(place + ": no such heading");
        }
    }
    return broken;
}

/// The source paths the Markdown file `file` names in code spans that start with a module's
/// folder (`renderer/src/scene/loader.h`) and that do not exist under `root`: "file:line: path".
/// A span with a placeholder (`<kind>.cpp`, `{h,cpp}`, `*`) is not a path.
std::vector<std::string> missingSourcePaths(const fs::path& root, const fs::path& file) {
    std::vector<std::string> missing;
    int number = 0;
    for (const std::string& line : linesOf(readText(file))) {
        ++number;
        for (const std::string& span : codeSpans({line})) {
            if (span.find_first_of("<>{}* ") != std::string::npos) continue;
            const bool module =
                std::any_of(kModules.begin(), kModules.end(),
                            [&](const std::string& m) { return span.rfind(m + "/", 0) == 0; });
            if (module && !fs::exists(root / span))
                missing.push_back(file.string() + ":" + std::to_string(number) + ": " + span);
        }
    }
    return missing;
}

/// README.md, docs/*.md and docs/lab/*.md under `root`.
std::vector<fs::path> markdownFiles(const fs::path& root) {
    std::vector<fs::path> files;
    if (fs::exists(root / "README.md")) files.push_back(root / "README.md");
    for (const fs::path& dir : {root / "docs", root / "docs" / "lab"}) {
        if (!fs::is_directory(dir)) continue;
        for (const auto& entry : fs::directory_iterator(dir))
            if (entry.is_regular_file() && entry.path().extension() == ".md")
                files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const std::string& line : lines) out += line + "\n";
    return out;
}

/// A scratch folder, removed when the test ends.
struct ScratchDir {
    fs::path path = fs::temp_directory_path() /
                    (std::string("glint-docs-test-") +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    ScratchDir() { fs::remove_all(path), fs::create_directories(path); }
    ~ScratchDir() { fs::remove_all(path); }
    void write(const std::string& name, const std::string& text) const {
        fs::create_directories((path / name).parent_path());
        std::ofstream(path / name) << text;
    }
};

TEST(Docs, SourceLayoutNamesEveryFolder) {
    const auto section = sectionOf(readText(kRoot / "docs/architecture.md"), "## Source layout");
    ASSERT_FALSE(section.empty()) << "docs/architecture.md has no \"## Source layout\" section";
    const auto problems = layoutProblems(kRoot, namedFolders(section));
    EXPECT_TRUE(problems.empty()) << "docs/architecture.md, \"Source layout\":\n"
                                  << joined(problems);
}

TEST(Docs, TheLayoutCheckFindsAMissingAndAnUnknownFolder) {
    ScratchDir tree;
    tree.write("image/src/a.cpp", "");
    tree.write("image/include/glint/image/a.h", "");
    tree.write("renderer/src/scene/b.cpp", "");
    tree.write("renderer/src/film/c.cpp", "");
    const std::set<std::string> all = {"image/src/", "image/include/glint/image/",
                                       "renderer/src/scene/", "renderer/src/film/"};
    EXPECT_TRUE(layoutProblems(tree.path, all).empty());

    auto missing = all;
    missing.erase("renderer/src/film/");
    EXPECT_EQ(layoutProblems(tree.path, missing),
              std::vector<std::string>{"does not name 'renderer/src/film/'"});

    auto unknown = all;
    unknown.insert("renderer/src/gone/");
    EXPECT_EQ(
        layoutProblems(tree.path, unknown),
        std::vector<std::string>{"names 'renderer/src/gone/', which is not a folder of the tree"});

    EXPECT_EQ(namedFolders({"- `renderer/src/scene/`: the loader; `glint_render`, `renderer.cpp`",
                            "- `gui/app/` and `docs/lab/`"}),
              (std::set<std::string>{"gui/app/", "renderer/src/scene/"}));
}

TEST(Docs, EveryRelativeLinkReachesAFileAndItsHeading) {
    const auto files = markdownFiles(kRoot);
    ASSERT_GT(files.size(), 10u);
    std::vector<std::string> broken;
    for (const fs::path& file : files) {
        const auto b = brokenLinks(file);
        broken.insert(broken.end(), b.begin(), b.end());
    }
    EXPECT_TRUE(broken.empty()) << joined(broken);
}

TEST(Docs, TheLinkCheckFindsAMissingFileAndAMissingHeading) {
    ScratchDir docs;
    docs.write("docs/lab/notes.md",
               "# Notes\n\n## Speed: EXR write + read\n\n## Tests\n\n## Tests\n");
    docs.write("docs/page.md",
               "# Page — a title\n\n"
               "[ok](lab/notes.md#speed-exr-write--read), [again](lab/notes.md#tests-1), "
               "[self](#page--a-title), [web](https://example.com/x.md)\n"
               "`[code](gone.md)` and\n```\n[fenced](gone.md)\n```\n"
               "[gone](lab/gone.md) and [no heading](lab/notes.md#speed)\n");
    EXPECT_EQ(
        brokenLinks(docs.path / "docs/page.md"),
        (std::vector<std::string>{
            (docs.path / "docs/page.md").string() + ":8: lab/gone.md: no such file",
            (docs.path / "docs/page.md").string() + ":8: lab/notes.md#speed: no such heading"}));
}

TEST(Docs, EverySourcePathTheReferenceDocsNameExists) {
    std::vector<std::string> missing;
    for (const fs::path& file : markdownFiles(kRoot)) {
        if (file.parent_path().filename() == "lab") continue;  // notebooks keep history's paths
        const auto m = missingSourcePaths(kRoot, file);
        missing.insert(missing.end(), m.begin(), m.end());
    }
    EXPECT_TRUE(missing.empty()) << joined(missing);
}

TEST(Docs, ThePathCheckFindsAPathThatDoesNotExist) {
    ScratchDir tree;
    tree.write("renderer/src/scene/loader.h", "");
    tree.write("docs/page.md",
               "`renderer/src/scene/loader.h`, `renderer/src/scene/<format>_import.cpp`,\n"
               "`glint/render/scene.h`, `docs/lab/x.md`\n"
               "`renderer/src/scene/gone.cpp` and `gui/app/`\n");
    EXPECT_EQ(missingSourcePaths(tree.path, tree.path / "docs/page.md"),
              (std::vector<std::string>{
                  (tree.path / "docs/page.md").string() + ":3: renderer/src/scene/gone.cpp",
                  (tree.path / "docs/page.md").string() + ":3: gui/app/"}));
}

TEST(Docs, TheNewcomerFindsWhereToAddAFilterAMaterialKindAndAnAssetFormat) {
    const std::string text = readText(kRoot / "docs/architecture.md");
    for (const std::string title :
         {"## Adding a filter", "## Adding a material kind", "## Adding an asset format"}) {
        SCOPED_TRACE(title);
        const auto section = sectionOf(text, title);
        ASSERT_FALSE(section.empty()) << "docs/architecture.md has no \"" << title << "\"";
        // The numbered list: each item's first code span is the file it touches.
        std::vector<std::string> files;
        for (const std::string& line : section) {
            if (line.size() < 3 || !std::isdigit((unsigned char)line[0]) || line[1] != '.')
                continue;
            const auto spans = codeSpans({line});
            ASSERT_FALSE(spans.empty()) << line;
            files.push_back(spans.front());
        }
        EXPECT_GE(files.size(), 1u);
        EXPECT_LE(files.size(), 3u) << joined(files);
        for (const std::string& file : files) {
            // A file named by a placeholder (<kind>.cpp) is checked by its folder.
            const fs::path path = kRoot / file;
            const bool placeholder = file.find('<') != std::string::npos;
            EXPECT_TRUE(placeholder ? fs::is_directory(path.parent_path()) : fs::exists(path))
                << file << " does not exist";
        }
    }
}

}  // namespace
