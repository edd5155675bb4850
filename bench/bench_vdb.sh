#!/bin/sh
# bench_vdb.sh — the same volumes as .vsv and as OpenVDB (issue #7): size on
# disk, and the time to write and to read each, on the real MM5 run at
# 10-minute steps (19 steps, 5 species, 207x142x40).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-vdb.XXXXXX")
trap 'rm -rf "$W"' EXIT
now() { date +%s.%N; }
"$B/vsv-convert" -q --vertical even --time-res 10m "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
t0=$(now); "$B/vsv-export" -q "$W/mm5.vsv" --vdb "$W/f_%04d.vdb"; t1=$(now)
"$B/vsv-extract" --vertical even "$W"/f_*.vdb > "$W/stream"; t2=$(now)
"$B/vsv-pack" -q -o "$W/back.vsv" < "$W/stream"; t3=$(now)
"$B/vsv-info" --check "$W/mm5.vsv" > /dev/null; t4=$(now)
vsv=$(stat -c %s "$W/mm5.vsv"); vdb=$(cat "$W"/f_*.vdb | wc -c)
printf '%s cores; %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)"
echo "| data | .vsv (16-bit) | OpenVDB (float, OpenVDB's default compression) | ratio |"
echo "|---|---|---|---|"
printf '| MM5 run1, 19 steps x 5 species | %.1f MB | %.1f MB | %.2f |\n\n' "$(echo "$vsv/1000000" | bc -l)" \
    "$(echo "$vdb/1000000" | bc -l)" "$(echo "$vsv/$vdb" | bc -l)"
printf -- '- vsv-export (decode + write 19 .vdb): %.2f s; vsv-extract of the 19 .vdb: %.2f s;\n' \
    "$(echo "$t1-$t0" | bc -l)" "$(echo "$t2-$t1" | bc -l)"
printf -- '  vsv-pack of them: %.2f s; vsv-info --check (decode every brick of the .vsv): %.2f s\n' \
    "$(echo "$t3-$t2" | bc -l)" "$(echo "$t4-$t3" | bc -l)"
