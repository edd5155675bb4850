/* vsv_sw_row_avx2.c — vsv_sw_row.c built for AVX2 and FMA (the Makefile adds
 * the flags); vsv_shearwarp.c calls it only on CPUs that have them. */
#define VSV_SW_PAR_ROWS vsv_sw_par_rows_avx2
#define VSV_SW_PAR_WARP vsv_sw_par_warp_avx2
#include "vsv_sw_row.c"
