/* vsv_raycast_avx512.c — vsv_raycast_simd.c built for AVX-512F (the Makefile
 * adds the flags): the sixteen rays in one register, the same operations in
 * the same order; the renderer calls it only on CPUs that have AVX-512F. */
#define VSV_RC_AVX512 1
#include "vsv_raycast_simd.c"
