// libFuzzer target: journal (tests/fuzz/journal_fuzz_target.h, docs/reliability.md).
#include "journal_fuzz_target.h"

#include <OpenImageIO/imageio.h>

// One thread in OpenImageIO and OpenEXR: a pool per read costs more than the read itself.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", 0);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    glint::fuzz::runJournalInput(data, size);
    return 0;
}
