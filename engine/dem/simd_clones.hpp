// The DEM engine's hot loops are compiled for AVX-512 and AVX2 as well as the baseline
// instruction set, and the best one the CPU has is chosen at run time (function
// multi-versioning; other architectures get the baseline only). FMA contraction is off
// for these files (CMakeLists.txt), so every version rounds each operation alike: the
// same bits on every CPU.
#pragma once

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define GRAINFLOW_DEM_SIMD_CLONES [[gnu::target_clones("avx512f", "avx2", "default")]]
#else
#define GRAINFLOW_DEM_SIMD_CLONES
#endif
