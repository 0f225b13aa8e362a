// Whether this test binary runs under AddressSanitizer or ThreadSanitizer. Both make the engine
// several times slower (TSan on 8 threads over 2 cores far more); a test that repeats the same
// work for more interleavings or more sizes does fewer repeats there. A sanitizer reports a bad
// access or a race on any run that takes the path, so the repeats each build keeps cover every
// option combination the test has.
#pragma once

namespace femsimp::testing {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kUnderSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif
#else
inline constexpr bool kUnderSanitizer = false;
#endif

#if defined(__SANITIZE_THREAD__)
inline constexpr bool kUnderThreadSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
inline constexpr bool kUnderThreadSanitizer = true;
#else
inline constexpr bool kUnderThreadSanitizer = false;
#endif
#else
inline constexpr bool kUnderThreadSanitizer = false;
#endif

}  // namespace femsimp::testing
