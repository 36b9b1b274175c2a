// Image assertions for other projects' test suites (docs/testing.md). Needs no test framework
// to include: imagesMatch() returns a result any framework can check, and with GoogleTest the
// macros GLINT_EXPECT_IMAGE_MATCHES / GLINT_ASSERT_IMAGE_MATCHES report a failure with Glint's
// one-line message (they use GoogleTest's macros only where they are expanded).
//
//   GLINT_EXPECT_IMAGE_MATCHES("out.exr", "ref.exr", "mc", "flip<=0.05");
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/expectation.h"

namespace glint::testing {

/// Whether an image meets its expectations, and a one-line account.
struct ImageMatch {
    bool ok = false;
    std::string message;
    explicit operator bool() const { return ok; }
};

/// Reads `file` and `reference` (layered EXR, or PNG/JPEG/... as display values) and checks each
/// expectation ("ssim>=0.98", "flip<=0.05", "psnr>=30", "relmse<=0.01", "mc", "mc:1e-5"; see
/// glint/image/expectation.h). Never throws: bad input is a failed match carrying Glint's error.
inline ImageMatch imagesMatch(const std::string& file, const std::string& reference,
                              std::initializer_list<std::string> expectations) {
    try {
        std::vector<Expectation> parsed;
        for (const std::string& text : expectations) parsed.push_back(parseExpectation(text));
        const ComparedImage image = readComparedImage(file);
        const ComparedImage ref = readComparedImage(reference);
        std::string failures, passes;
        for (const ExpectationOutcome& outcome : checkExpectations(image, ref, parsed))
            (outcome.passed ? passes : failures) += (outcome.passed ? passes : failures).empty()
                                                        ? outcome.message
                                                        : "; " + outcome.message;
        if (failures.empty()) return {true, file + " matches " + reference + ": " + passes};
        return {false, file + " does not match " + reference + ": " + failures};
    } catch (const Error& e) {
        return {false, e.what()};
    }
}

}  // namespace glint::testing

/// GoogleTest: a non-fatal failure unless `file` meets every expectation against `reference`.
#define GLINT_EXPECT_IMAGE_MATCHES(file, reference, ...)                           \
    switch (0)                                                                     \
    case 0:                                                                        \
    default:                                                                       \
        if (const ::glint::testing::ImageMatch glint_image_match_ =                \
                ::glint::testing::imagesMatch((file), (reference), {__VA_ARGS__}); \
            glint_image_match_)                                                    \
            ;                                                                      \
        else                                                                       \
            ADD_FAILURE() << glint_image_match_.message

/// GoogleTest: as GLINT_EXPECT_IMAGE_MATCHES, but a fatal failure (returns from the test).
#define GLINT_ASSERT_IMAGE_MATCHES(file, reference, ...)                           \
    switch (0)                                                                     \
    case 0:                                                                        \
    default:                                                                       \
        if (const ::glint::testing::ImageMatch glint_image_match_ =                \
                ::glint::testing::imagesMatch((file), (reference), {__VA_ARGS__}); \
            glint_image_match_)                                                    \
            ;                                                                      \
        else                                                                       \
            FAIL() << glint_image_match_.message
