// The fuzz harness of the studio's autosave (libFuzzer target fuzz_journal, docs/reliability.md):
// a journal's lines (journal.jsonl, the bytes given) replayed by recover() as "Restore your
// work?" does, beside a fixed set of side files (tests/fuzz/journal_fixture/: two 16 × 12 renders
// of a small Cornell box and a 12 × 12 one with halves, the weight maps and corrections a killed
// studio left, and the scene they were rendered from). The fuzzer mutates the lines only: the EXR
// reader has its own target (fuzz_exr). As in fuzz_targets.h, a glint::Error that is not Internal
// is the expected answer to a journal that does not apply; anything else aborts, and so does a
// restored session whose weights or composite are not finite.
// Plain C++ beside QtCore (no libFuzzer header), so that gcc builds compile it for the seeds'
// replay (tests/gui/journal_fuzz_test.cpp).
#pragma once

#include <QString>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "denoise_fuzz_targets.h"
#include "model/recovery.h"

namespace glint::fuzz {

/// The journal folder: the fixture copied into the workspace.
inline const fs::path& journalFolder() {
    static const fs::path dir = [] {
        const fs::path d = workspace() / "journal";
        fs::create_directories(d);
        for (const auto& entry :
             fs::directory_iterator(fs::path(GLINT_SOURCE_DIR) / "tests/fuzz/journal_fixture"))
            fs::copy_file(entry.path(), d / entry.path().filename(),
                          fs::copy_options::overwrite_existing);
        return d;
    }();
    return dir;
}

/// `data` as the journal's lines, restored; returns the replay's result (null when the journal
/// was refused with a clean error, whose text goes to `refusal` when given).
inline std::shared_ptr<studio::Recovered> runJournal(const std::uint8_t* data, std::size_t size,
                                                     std::string* refusal = nullptr) {
    const fs::path& dir = journalFolder();
    std::shared_ptr<studio::Recovered> out;
    expectCleanError("journal", [&] {
        writeFile(dir / "journal.jsonl", data, size);
        // The replay runs in the journal folder, so that an "open" of "scene.json" finds the
        // fixture's scene (the studio writes absolute paths; a fuzzed one may be anything); the
        // working directory is given back after it (libFuzzer reads its corpus by relative path).
        const fs::path before = fs::current_path();
        fs::current_path(dir);
        try {
            out = std::make_shared<studio::Recovered>(
                studio::recover(QString::fromStdString(dir.string())));
        } catch (const Error& e) {
            fs::current_path(before);
            if (refusal) *refusal = e.what();
            throw;
        }
        fs::current_path(before);
        if (!out->session) return;
        for (std::size_t i = 0; i < out->session->layerCount(); ++i)
            expectFinite("journal", out->session->layer(i).weights, "the restored layer weights");
        expectFinite("journal", out->session->composite(), "the restored composite");
    });
    return out;
}

/// The libFuzzer entry's body (a void function, as the regression replay takes).
inline void runJournalInput(const std::uint8_t* data, std::size_t size) {
    (void)runJournal(data, size);
}

}  // namespace glint::fuzz
