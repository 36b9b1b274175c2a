// The fuzz harnesses of what glint-denoise and the studio read (libFuzzer targets
// fuzz_denoise_input, fuzz_paint_script, fuzz_session, fuzz_bank_index, fuzz_shard_merge;
// docs/reliability.md): a render denoised, paint scripts, session files, bank indexes, and sets
// of shards to merge. As in fuzz_targets.h, a glint::Error that is not Internal is the expected
// answer to bad input; anything else aborts.
// Plain C++ (no libFuzzer header), so that gcc builds compile them for the regression replays.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_targets.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/denoised_frame.h"
#include "glint/denoise/paint_script.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/shard.h"

namespace glint::fuzz {

/// A 16×12 render with every feature layer and a variance: two regions of colour and features
/// (the magic wand and the guided filters have edges to find).
inline const FrameBuffers& smallRender() {
    static const FrameBuffers frame = [] {
        FrameBuffers f(16, 12);
        Image& c = f.color();
        Image& albedo = f.ensure(Layer::Albedo);
        Image& normal = f.ensure(Layer::Normal);
        Image& depth = f.ensure(Layer::Depth);
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) {
                const bool right = x + y > 14;
                const float ripple = 0.05f * float((x * 7 + y * 13) % 5);
                for (int ch = 0; ch < 3; ++ch) c(x, y, ch) = (right ? 0.8f : 0.2f) + ripple;
                for (int ch = 0; ch < 3; ++ch) albedo(x, y, ch) = right ? 0.7f : 0.3f;
                normal(x, y, 0) = right ? 1.0f : 0.0f;
                normal(x, y, 2) = right ? 0.0f : 1.0f;
                depth(x, y, 0) = right ? 3.0f : 5.0f;
            }
        f.ensure(Layer::Variance).fill(0.01f);
        f.ensure(Layer::SampleCount).fill(4.0f);
        return f;
    }();
    return frame;
}

/// Aborts when `image` holds a value that is not finite: what a filter or auto accepts must come
/// out finite (a missing pixel is filled from its neighbours or refused, docs/denoise.md).
inline void expectFinite(const char* target, const Image& image, const std::string& what) {
    for (float v : image.data())
        if (!std::isfinite(v)) {
            std::fprintf(stderr, "%s: %s accepted the input and wrote %f\n", target, what.c_str(),
                         double(v));
            std::abort();
        }
}

/// An EXR as glint-denoise reads it (a render, or the render a denoised file keeps), then, when
/// it is at most 32 × 32, what `apply` and `auto` do with it: every filter that can run here with
/// its defaults (the non-finite policy: what a filter accepts comes out finite,
/// docs/denoise.md), and auto at the fast and balanced qualities on a small bank, with its
/// per-pixel error (the input checks first, as the CLI runs them).
inline void runDenoiseInput(const std::uint8_t* data, std::size_t size) {
    expectCleanError("denoise_input", [&] {
        writeFile(workspace() / "input.exr", data, size);
        const std::string file = (workspace() / "input.exr").string();
        const FrameBuffers frame = denoise::renderOf(readExr(file));
        if (std::int64_t(frame.width()) * frame.height() > 32 * 32) return;
        for (const denoise::Filter* filter : denoise::allFilters()) {
            if (!filter->unavailable(denoise::resolveParams(*filter, {})).empty())
                continue;  // external without its command
            denoise::FilterOptions one;
            one.threads = 1;
            try {
                expectFinite("denoise_input", denoise::applyFilter(*filter, frame, {}, one),
                             std::string(filter->name()));
            } catch (const Error& e) {
                if (e.kind() == ErrorKind::Internal) throw;
            }
        }
        denoise::checkAutoInput(frame, denoise::AutoEstimator::Auto, file);
        denoise::BankOptions bank;
        bank.size = 4;
        bank.filters = {"gaussian", "bilateral", "cross-bilateral"};
        for (denoise::AutoQuality quality :
             {denoise::AutoQuality::Fast, denoise::AutoQuality::Balanced}) {
            denoise::AutoOptions options;
            options.tuning = denoise::autoQualityTuning(quality);
            // The per-pixel error glint-final steers by (the halves estimator's alone).
            options.estimateError = frame.has(Layer::HalfColor);
            const denoise::StreamedAuto result =
                denoise::autoCompositeStreamed(frame, bank, options);
            const std::string what = std::string("auto ") + denoise::autoQualityName(quality);
            expectFinite("denoise_input", result.result.composite, what);
            if (options.estimateError)
                expectFinite("denoise_input", result.result.error, what + " (its error)");
        }
    });
}

/// A paint script, read and replayed on a session of smallRender().
inline void runPaintScript(const std::uint8_t* data, std::size_t size) {
    expectCleanError("paint_script", [&] {
        const std::string text(reinterpret_cast<const char*>(data), size);
        const denoise::PaintScript script = denoise::PaintScript::parse(text, "fuzz.json");
        denoise::Session session(smallRender());
        script.apply(session);
    });
}

/// The session fuzz.glint-session.json of the workspace, whose side folder holds a good input
/// and the weights of two layers (layer-0.exr, layer-1.exr), so that a fuzzed file naming them
/// reaches the layers.
inline void runSessionFile(const std::uint8_t* data, std::size_t size) {
    static const fs::path file = [] {
        denoise::Session good(smallRender());
        good.addLayer("gaussian", {});
        good.addLayer("bilateral", {});
        good.save(workspace() / "fuzz.glint-session.json");
        return workspace() / "fuzz.glint-session.json";
    }();
    expectCleanError("session", [&] {
        writeFile(file, data, size);
        const denoise::Session session = denoise::Session::load(file);
        (void)session;
    });
}

/// index.json of a bank folder of smallRender() (members of two gaussian samples and the
/// defaults), opened as oracle and navigate open it; large banks are only read, not computed.
inline void runBankIndex(const std::uint8_t* data, std::size_t size) {
    static const fs::path dir = [] {
        denoise::BankOptions o;
        o.size = 2;
        o.filters = {"gaussian"};
        o.cacheDir = workspace() / "bank";
        fs::create_directories(o.cacheDir);
        denoise::buildBank(smallRender(), o);
        return o.cacheDir;
    }();
    expectCleanError("bank_index", [&] {
        writeFile(dir / "index.json", data, size);
        const denoise::BankOptions options = denoise::readBankOptions(dir);
        if (options.size > 16) return;
        const denoise::FilterBank bank = denoise::openBank(smallRender(), dir);
        (void)bank;
    });
}

/// The separator between the files of a shard-merge input.
inline constexpr std::string_view kShardSeparator = "--glint-shard--";

/// Up to four EXR files (separated by kShardSeparator), merged as glint-image merge does: a
/// whole merge, then a partial one.
inline void runShardMerge(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> files;
    std::size_t begin = 0;
    while (files.size() < 4) {
        const std::size_t end = std::min(bytes.find(kShardSeparator, begin), bytes.size());
        const fs::path file = workspace() / ("shard-" + std::to_string(files.size()) + ".exr");
        writeFile(file, data + begin, end - begin);
        files.push_back(file.string());
        if (end == bytes.size()) break;
        begin = end + kShardSeparator.size();
    }
    for (MergeKind kind : {MergeKind::Whole, MergeKind::Partial})
        expectCleanError("shard_merge", [&] {
            const FrameBuffers merged = mergeShardFiles(files, kind);
            (void)merged;
        });
}

}  // namespace glint::fuzz
