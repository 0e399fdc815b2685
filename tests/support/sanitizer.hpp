#pragma once

// Whether this build (and so the mblab it runs) has AddressSanitizer: g++ says so with
// __SANITIZE_ADDRESS__, clang with __has_feature. Its shadow memory and the quarantine that
// keeps freed blocks add to any process's resident memory, so memory bounds allow for them.
namespace mblab::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

// What AddressSanitizer may add to a process's peak resident memory, in KiB.
inline constexpr long kSanitizerKb = kAddressSanitizer ? 256 * 1024 : 0;

}  // namespace mblab::test
