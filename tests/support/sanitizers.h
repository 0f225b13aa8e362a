// Whether this test binary runs under AddressSanitizer or ThreadSanitizer. Both make the engine
// several times slower (TSan on 8 threads over 2 cores far more); a test that repeats the same
// work for more interleavings or more sizes does fewer repeats there. A sanitizer reports a bad
// access or a race on any run that takes the path, so the repeats each build keeps cover every
// option combination the test has.
#pragma once

namespace femsimp::testing {

// gcc defines __SANITIZE_*__; clang answers __has_feature.
#if defined(__has_feature)
#define FEMSIMP_TEST_HAS_FEATURE(x) __has_feature(x)
#else
#define FEMSIMP_TEST_HAS_FEATURE(x) 0
#endif

#if defined(__SANITIZE_THREAD__) || FEMSIMP_TEST_HAS_FEATURE(thread_sanitizer)
inline constexpr bool kUnderThreadSanitizer = true;
#else
inline constexpr bool kUnderThreadSanitizer = false;
#endif
#if defined(__SANITIZE_ADDRESS__) || FEMSIMP_TEST_HAS_FEATURE(address_sanitizer)
inline constexpr bool kUnderAddressSanitizer = true;
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif
inline constexpr bool kUnderSanitizer = kUnderThreadSanitizer || kUnderAddressSanitizer;

}  // namespace femsimp::testing
