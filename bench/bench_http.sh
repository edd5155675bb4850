#!/bin/sh
# bench_http.sh — a .vsv read from a web server (issue #23): the real MM5 run
# (hourly, and at 5-minute steps) served by lighttpd on a free loopback port;
# `vsv-render URL --species CLW --time 2` run twice with a fresh cache
# directory: the body bytes the server's access log shows for each run
# against the file's size, the wall time of each run, and whether the PNG
# equals the local file's. Then `vsv-play URL --script` (under Xvfb, when
# there) for a few seconds of playing, its bytes likewise. Needs lighttpd
# (sh tools/deps.sh --install-bench).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-http.XXXXXX")
server_down() { echo "bench_http.sh: lighttpd does not start: $1"; exit 1; }
. tests/lighttpd_lib.sh
[ -n "$LIGHTTPD" ] || { echo "bench_http.sh: no lighttpd (sh tools/deps.sh --install-bench)"; rm -rf "$T"; exit 0; }
trap 'stop_server; rm -rf "$T"' EXIT INT TERM
mkdir -p "$T/www"
now() { date +%s.%N; }
requests() { wc -l < "$T/access.log"; }

printf '%s cores; %s; load %s\n\n' "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M UTC')" "$(cut -d' ' -f1-3 /proc/loadavg)"
"$B/vsv-convert" -q --vertical even "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$T/www/run.vsv"
"$B/vsv-convert" -q --vertical even --time-res 5m "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$T/www/run5m.vsv"
touch -d '1 hour ago' "$T/www/run.vsv" "$T/www/run5m.vsv" # lighttpd sends validators for files not just written
echo "| file | size | run | body bytes sent | share of the file | requests | seconds | PNG equals the local file's |"
echo "|---|---|---|---|---|---|---|---|"
for f in run run5m; do
    size=$(wc -c < "$T/www/$f.vsv")
    "$B/vsv-render" "$T/www/$f.vsv" --species CLW --time 2 -o "$T/local.png" -q
    export VSV_CACHE_DIR="$T/cache-$f"
    PORT=
    for run in first second; do
        start_server
        t0=$(now)
        "$B/vsv-render" "http://127.0.0.1:$PORT/$f.vsv" --species CLW --time 2 -o "$T/url.png" -q
        t1=$(now)
        stop_server
        sent=$(body_bytes)
        same=no
        cmp -s "$T/url.png" "$T/local.png" && same=yes
        printf '| %s.vsv (MM5) | %s | %s | %s | %.1f %% | %s | %.2f | %s |\n' "$f" "$size" "$run" "$sent" \
            "$(echo "100 * $sent / $size" | bc -l)" "$(requests)" "$(echo "$t1 - $t0" | bc -l)" "$same"
    done
done
if [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null; then
    echo
    echo "| file | run | body bytes sent | share of the file | vsv-play --script exit |"
    echo "|---|---|---|---|---|"
    export VSV_CACHE_DIR="$T/cache-play"
    printf '0.2 play\n3 screenshot %s\n3.2 quit\n' "$T/play.png" > "$T/play.script"
    size=$(wc -c < "$T/www/run5m.vsv")
    PORT=
    for run in first second; do
        start_server
        rc=0
        xvfb-run -a -s "-screen 0 800x600x24" "$B/vsv-play" "http://127.0.0.1:$PORT/run5m.vsv" --size 320x240 \
            --script "$T/play.script" > /dev/null 2>&1 || rc=$?
        stop_server
        sent=$(body_bytes)
        printf '| run5m.vsv (MM5) | %s | %s | %.1f %% | %s |\n' "$run" "$sent" "$(echo "100 * $sent / $size" | bc -l)" "$rc"
    done
fi
printf '\nload %s at the end\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
