// The streamed selection's entry with its strip height (auto_stream.h; the tests run it on tiny
// strips so that every strip boundary and margin is crossed).
#pragma once

#include "glint/denoise/auto_stream.h"

namespace glint::denoise::detail {

/// autoCompositeStreamed with strips of `streamRows` rows for the members and the scores (0:
/// AutoSettings::streamRows and scoreRows).
StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options, int streamRows);

}  // namespace glint::denoise::detail
