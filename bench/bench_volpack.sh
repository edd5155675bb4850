#!/bin/sh
# bench_volpack.sh — the shear-warp renderer beside VolPack (libvolpack1-dev) on
# the same 8-bit volumes from the converted real MM5 run (CLW and SNOW sparse,
# Q dense), the real WRF file (QCLOUD) and gen-plume's plume (sparse) and haze
# (never empty),
# set up alike (bench/vp_match.h), after a closed-form box that checks the
# set-up; each run prints the PSNR between the two pictures (a comparison
# counts at 35 dB or more) and the machine's load.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-volpack.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q --vertical even "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
printf '%s cores; %s; load average %s at the start\n\n' "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M UTC')" \
    "$(cut -d' ' -f1 /proc/loadavg)"
# each run printed and kept for the summary at the end
vp() {
    "$B/bench/bench_volpack" "$@" > "$W/one.txt"
    cat "$W/one.txt" >> "$W/all.txt"
    cat "$W/one.txt"
}
# the closed-form case first: a box off the middle of an otherwise empty grid
vp --box "$W/box.vsv"
echo
vp "$W/mm5.vsv" CLW 3
echo
vp "$W/mm5.vsv" Q 3
echo
vp "$W/mm5.vsv" SNOW 3
# the real WRF file: QCLOUD at its fourth time (21 UTC)
"$B/vsv-convert" -q --vertical even "$SHARED/data/wrf/katrina_ci_test_file.nc" -o "$W/wrf.vsv"
echo
vp "$W/wrf.vsv" QCLOUD 3
# gen-plume's synthetic volumes: the sparse plume and the hazy one
${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
"$W/gen_volume" "$W" >/dev/null
echo
vp --plume "$W"
echo
vp --haze "$W"
# worst beside best: one thread's CPU, x VolPack, volumes whose pictures matched
printf '\nWorst beside best, × VolPack (one thread'"'"'s CPU; volumes whose pictures matched):\n'
awk -F'|' '
/^volume: / {
    split($0, w, " "); n = w[2]; sub(/.*\//, "", n); sub(/\.vsv$/, "", n)
    if (w[3] != "box" && w[3] != "plume") n = n " " w[3]
    name = n; ok = index($0, "(matched") > 0
}
/^\| Vesuvius shear-warp, .* RGBA \| 1 \|/ && ok {
    k = ($2 ~ /8-bit/) ? "8-bit RGBA" : "float RGBA"
    if (!match($7, /[0-9.]+/)) next
    x = substr($7, RSTART, RLENGTH) + 0
    if (!(k in lo) || x < lo[k]) { lo[k] = x; lon[k] = name }
    if (!(k in hi) || x > hi[k]) { hi[k] = x; hin[k] = name }
    if (x < 1.5) below[k] = below[k] (below[k] == "" ? "" : ", ") name " " sprintf("%.2f", x) "×"
}
END {
    split("8-bit RGBA,float RGBA", ks, ",")
    for (i = 1; i <= 2; i++) {
        k = ks[i]
        if (!(k in lo)) continue
        printf "%s: worst %.2f× (%s), best %.2f× (%s); %s\n", k, lo[k], lon[k], hi[k], hin[k],
            below[k] == "" ? "the 1.5× goal met on every volume" : "the 1.5× goal not met on " below[k]
    }
}' "$W/all.txt"
printf '\nload average %s at the end\n' "$(cut -d' ' -f1 /proc/loadavg)"
