// The artist's three qualities of auto (auto.h, AutoQuality): each a bank size and tuning
// overrides. Balanced is the defaults. Fast filters the halves one-sided (with the shortlist made
// on A alone: docs/lab/auto.md, "Fast's one-sided shortlist"), which the lab measured
// at 1.59–1.73 × the bank's time against 1.85–1.96 × for the defaults, 2 of 12 cells below the
// best single member (docs/lab/auto-notebook.md, step 7; auto-notebook-2.md, "Speed"), and builds
// half the bank. Best builds twice the bank with the default tuning; no setting has yet been
// measured better than balanced (docs/auto.md, "Command line": --shortlist 0 lost on cornell 4 and
// glossy 16 spp, 128 members tied on cornell and lost 0.002 on glossy).
#include <string>

#include "glint/denoise/auto.h"
#include "glint/image/error.h"

namespace glint::denoise {

AutoQuality parseAutoQuality(const std::string& name) {
    if (name == "fast") return AutoQuality::Fast;
    if (name == "balanced") return AutoQuality::Balanced;
    if (name == "best") return AutoQuality::Best;
    throw Error(ErrorKind::InvalidArgument,
                "unknown quality '" + name + "' (expected fast, balanced or best)");
}

const char* autoQualityName(AutoQuality quality) {
    switch (quality) {
        case AutoQuality::Fast:
            return "fast";
        case AutoQuality::Balanced:
            return "balanced";
        case AutoQuality::Best:
            return "best";
    }
    return "?";
}

ParamValues autoQualityTuning(AutoQuality quality) {
    switch (quality) {
        case AutoQuality::Fast:
            return {{"oneSided", 1.0}};
        case AutoQuality::Best:
        case AutoQuality::Balanced:
            break;
    }
    return {};
}

int autoQualityBankSize(AutoQuality quality) {
    switch (quality) {
        case AutoQuality::Fast:
            return 32;
        case AutoQuality::Best:
            return 128;
        case AutoQuality::Balanced:
            break;
    }
    return 64;
}

}  // namespace glint::denoise
