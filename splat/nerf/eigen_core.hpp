#pragma once
// <Eigen/Core> for the NeRF code, without GCC 12's false -Wmaybe-uninitialized warnings.
// GCC 12's AVX-512 intrinsics define _mm512_undefined_ps()/_pd() as `__m512 __Y = __Y;`,
// which the warning reports wherever Eigen's GEMM kernels inline them (GCC PR 105593,
// fixed in GCC 13). The diagnostic state is that of the intrinsics header's own lines, so it
// is switched off while <immintrin.h> is first read: include this header before any other
// that reaches it (oneTBB, Eigen). The warning stays on for every line of our own code.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#include <Eigen/Core>
#pragma GCC diagnostic pop
