#pragma once
// RIDGE_ADDRESS_SANITIZER is 1 in a build with AddressSanitizer, else 0. GCC says so with a
// macro, clang with a feature test; one place answers for both, for the code that must act
// differently under the sanitizer (fewer cameras in a sweep, an explicit leak check).
#if defined(__SANITIZE_ADDRESS__)
#define RIDGE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RIDGE_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef RIDGE_ADDRESS_SANITIZER
#define RIDGE_ADDRESS_SANITIZER 0
#endif
