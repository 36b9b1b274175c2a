// GLINT_TEST_ASAN is defined in an AddressSanitizer build (make test-sanitize; GCC's
// __SANITIZE_ADDRESS__ or Clang's __has_feature), for tests whose expectation differs there.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define GLINT_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GLINT_TEST_ASAN 1
#endif
#endif
