#pragma once
// RIDGE_TARGET_CLONES: compile a hot loop twice, for AVX2 and for the x86-64 baseline, and let
// the dynamic loader pick the clone for the running CPU (GCC function multiversioning).
// Baseline SSE2 lacks packed 32-bit min/max/abs, which the integer error loops live on, so
// the AVX2 clone is 2-4x faster while the binary still runs on any x86-64. Elsewhere
// (clang, other architectures) it expands to nothing, and so it does under AddressSanitizer:
// ifunc resolvers run before ASan is initialised, and the sanitizer run then covers the
// portable clone while Release runs cover the AVX2 one.
#include "ridge/core/sanitizer.h"

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__) && !RIDGE_ADDRESS_SANITIZER
#define RIDGE_TARGET_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RIDGE_TARGET_CLONES
#endif
