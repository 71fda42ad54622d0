#pragma once
// Whether this test program runs under AddressSanitizer (CI's sanitizer pass), where long
// numerical runs cost ten times more and add nothing the Release pass does not check.

namespace khz::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

}  // namespace khz::test
