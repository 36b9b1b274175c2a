// libFuzzer target: tev (tests/fuzz/fuzz_targets.h, docs/reliability.md).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    glint::fuzz::runTevStream(data, size);
    return 0;
}
