// libFuzzer target: denoise_input (tests/fuzz/denoise_fuzz_targets.h, docs/reliability.md).
#include "denoise_fuzz_targets.h"

#include <OpenImageIO/imageio.h>

// One thread in OpenImageIO and OpenEXR: a pool per read costs more than the read itself.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", 0);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    glint::fuzz::runDenoiseInput(data, size);
    return 0;
}
