#pragma once
// Whether this test program runs under AddressSanitizer (CI's sanitizer pass), where long
// numerical runs cost ten times more and add nothing the Release pass does not check. GCC says
// so with __SANITIZE_ADDRESS__, clang 14 with __has_feature; KHZ_TEST_ADDRESS_SANITIZER is
// defined for the preprocessor, sanitized_build for code.

#if defined(__SANITIZE_ADDRESS__)
#define KHZ_TEST_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define KHZ_TEST_ADDRESS_SANITIZER 1
#endif
#endif

namespace khz::test {

#if defined(KHZ_TEST_ADDRESS_SANITIZER)
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

}  // namespace khz::test
