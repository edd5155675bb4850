#!/bin/sh
# cli_http.sh — .vsv files read from a web server (issue 23): a real lighttpd
# on the loopback interface (a free port, started here and stopped after, its
# access log read), the tools reading http:// URLs of the real MM5 run, the
# on-disk cache (a second run costs no body bytes; damaged cached bytes are
# fetched again), HTTPS with a self-signed certificate, and the failures a
# fault-injecting proxy of our own makes (tests/http_proxy.py): dropped
# connections and truncated replies retried, a server that ignores Range, a
# file that changes while read, garbled bytes and gzip-encoded replies
# reported, exit 1.
set -u
B=${B:-build}
SHARED=${SHARED:-../shared}
PY=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-http.XXXXXX")
. tests/cli_lib.sh
server_down() { fail "lighttpd starts on a loopback port" "$1"; exit 0; }
. tests/lighttpd_lib.sh
if [ -z "$LIGHTTPD" ]; then
    echo "note: cli_http.sh skipped: no lighttpd (apt-get install lighttpd, tools/deps.sh)"
    rm -rf "$T"
    exit 0
fi
PPID_=
stop_proxy() { [ -n "$PPID_" ] && kill "$PPID_" 2> /dev/null && wait "$PPID_" 2> /dev/null; PPID_=; }
trap 'stop_proxy; stop_server; rm -rf "$T"' EXIT INT TERM
mkdir -p "$T/www"
# start_proxy MODE [N]: tests/http_proxy.py before the server, on $PPORT
start_proxy() {
    rm -f "$T/pport"
    "$PY" tests/http_proxy.py "$PORT" "$T/pport" "$@" > "$T/proxy.out" 2>&1 &
    PPID_=$!
    i=0
    while [ ! -s "$T/pport" ] && [ $i -lt 300 ] && kill -0 "$PPID_" 2> /dev/null; do sleep 0.1; i=$((i + 1)); done
    PPORT=$(cat "$T/pport" 2> /dev/null)
    listening "${PPORT:-1}" || { fail "the proxy starts" "$(head -c 300 "$T/proxy.out")"; exit 0; }
}

# the real MM5 run, hourly: 4 steps of 5 species (without ../shared, the
# bundled crop of it at 20-minute steps)
# (the step drawn: one past the reader's first range, as in the run; even
# heights, the file the README's figures were measured on)
IN=$(data mm5/run1/MMOUT_DOMAIN1) CELL=100,70,5 RES= STEP=2
[ -f "$IN" ] || IN=samples/mm5/MMOUT_DOMAIN1_CROP CELL=20,20,5 RES="--time-res 20m" STEP=8
"$B/vsv-convert" -q --vertical even $RES "$IN" -o "$T/www/run.vsv" ||
    { fail "the MM5 run converts" "vsv-convert failed"; exit 0; }
# lighttpd sends no validators (ETag, Last-Modified) for a file modified in
# the last second or so; a file on a server is older than that
touch -d '1 hour ago' "$T/www/run.vsv"
SIZE=$(wc -c < "$T/www/run.vsv")
"$B/vsv-render" "$T/www/run.vsv" --species CLW --time $STEP -o "$T/local.png" -q
start_server
URL=http://127.0.0.1:$PORT/run.vsv
export VSV_CACHE_DIR="$T/cache"

# ---- the done-when: one species of one step, a part of the file
expect "vsv-render URL --species CLW --time $STEP exits 0" 0 "$B/vsv-render" "$URL" --species CLW --time $STEP -o "$T/x.png"
same "and gives the same PNG as the local file" "$T/x.png" "$T/local.png"
stop_server
sent=$(body_bytes)
if [ "$sent" -gt 0 ] && [ $((sent * 3)) -lt "$SIZE" ]; then
    pass "the server sent $sent bytes, under 1/3 of the $SIZE-byte file"
else
    fail "the server sent under 1/3 of the file" "$sent of $SIZE bytes"
fi
grep -q ' 206 ' "$T/access.log" && ! grep -q '^GET .* 200 ' "$T/access.log" && pass "only range requests (206) fetched it" ||
    fail "only range requests (206) fetched it" "$(head -c 300 "$T/access.log")"

start_server
URL=http://127.0.0.1:$PORT/run.vsv
expect "the second run exits 0" 0 "$B/vsv-render" "$URL" --species CLW --time $STEP -o "$T/x2.png"
same "and gives the same PNG" "$T/x2.png" "$T/local.png"
stop_server
sent=$(body_bytes)
# (the file's first block is fetched and compared on every open: issue 33)
first=$((SIZE < 16384 ? SIZE : 16384))
[ "$sent" = "$first" ] && pass "the second run costs only the first block, $first bytes (the cache; the log: $(wc -l < "$T/access.log") requests)" ||
    fail "the second run costs only the first block ($first bytes)" "$sent bytes: $(head -c 300 "$T/access.log")"

# ---- every tool that reads a .vsv
start_server
URL=http://127.0.0.1:$PORT/run.vsv
expect "vsv-info URL exits 0" 0 "$B/vsv-info" "$URL"
tail -n +2 "$T/out" > "$T/info-url"
"$B/vsv-info" "$T/www/run.vsv" | tail -n +2 > "$T/info-local"
same "and says what it says of the local file" "$T/info-url" "$T/info-local"
expect "vsv-info --check URL exits 0 (every byte fetched and checked)" 0 "$B/vsv-info" --check "$URL"
expect "vsv-query URL exits 0" 0 "$B/vsv-query" "$URL" --cell $CELL --species CLW,Q
cp "$T/out" "$T/q-url"
"$B/vsv-query" "$T/www/run.vsv" --cell $CELL --species CLW,Q > "$T/q-local"
same "and gives the local file's values" "$T/q-url" "$T/q-local"
expect "vsv-export URL --netcdf exits 0" 0 "$B/vsv-export" "$URL" --netcdf "$T/url.nc" --species CLW --times 1:2
"$B/vsv-export" "$T/www/run.vsv" --netcdf "$T/local.nc" --species CLW --times 1:2 -q
if command -v ncdump > /dev/null; then
    ncdump -v CLW "$T/url.nc" | grep -v '^netcdf\|:history\|:source' > "$T/url.cdl"
    ncdump -v CLW "$T/local.nc" | grep -v '^netcdf\|:history\|:source' > "$T/local.cdl"
    same "and writes the local file's values" "$T/url.cdl" "$T/local.cdl"
fi
expect "--cache-dir off: exits 0" 0 "$B/vsv-render" "$URL" --cache-dir off --species CLW --time $STEP -o "$T/off.png"
same "and gives the same PNG" "$T/off.png" "$T/local.png"
# a --cache-dir that cannot hold anything is said, not passed over (every
# run fetched the file again, silently)
: > "$T/a-file"
expect "--cache-dir a regular file: exits 1" 1 "$B/vsv-render" "$URL" --cache-dir "$T/a-file" --species CLW --time $STEP -o "$T/x.png"
has "and says so" "$T/err" "vsv-render: --cache-dir $T/a-file: not a directory"
expect "--cache-dir in a folder that cannot be made: exits 1" 1 "$B/vsv-info" "$URL" --cache-dir /proc/no/cache
has "naming what could not be made" "$T/err" "vsv-info: --cache-dir /proc/no/cache: cannot make /proc/no"
expect "--cache-dir a new nested folder: made, exits 0" 0 "$B/vsv-info" "$URL" --cache-dir "$T/new/cache/dir"
[ -d "$T/new/cache/dir" ] && pass "and the folder is there" || fail "and the folder is there" "no $T/new/cache/dir"
# a cache others can write is refused, and a link planted in one's own is
# never followed (issue 33: KEY.data was opened without O_NOFOLLOW and
# truncated: the victim's file got the server's bytes)
mkdir -m 0777 "$T/shared-cache" && chmod 0777 "$T/shared-cache"
expect "--cache-dir writable by others: exits 1" 1 "$B/vsv-info" "$URL" --cache-dir "$T/shared-cache"
has "... saying why" "$T/err" "refused: a cache folder must be yours and writable by you alone"
mkdir -m 0700 "$T/own-cache"
echo "precious" > "$T/victim"
key=$(/usr/bin/python3 -c "
import sys
h = 1469598103934665603
for c in sys.argv[1].encode():
    h = ((h ^ c) * 1099511628211) % 2 ** 64
print('%016x' % h)" "$URL")
ln -s "$T/victim" "$T/own-cache/$key.data"
ln -s "$T/victim" "$T/own-cache/$key.meta.tmp"
expect "a link planted as the cache's data file: the run goes on (in memory)" 0 "$B/vsv-info" "$URL" --cache-dir "$T/own-cache"
has "... and the linked file is untouched" "$T/victim" "precious"
[ "$(wc -c < "$T/victim")" = 9 ] && pass "... not one byte of it" || fail "... not one byte of it" "$(wc -c < "$T/victim") bytes"
expect "--help names --cache-dir" 0 "$B/vsv-render" --help
has "and says what it does" "$T/out" "--cache-dir DIR"
expect "an ftp:// URL: exits 1" 1 "$B/vsv-info" "ftp://127.0.0.1:$PORT/run.vsv"
has "saying which URLs are read" "$T/err" "vsv-info: ftp://127.0.0.1:$PORT/run.vsv: no such file; of URLs, only http:// and https:// ones are read"
expect "a missing file: exits 1" 1 "$B/vsv-info" "http://127.0.0.1:$PORT/none.vsv"
has "and says HTTP 404" "$T/err" "vsv-info: http://127.0.0.1:$PORT/none.vsv: HTTP 404 (not found)"
if [ "${VIEWER:-1}" = 1 ] && [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null; then
    printf '0.2 play\n0.4 screenshot %s\n0.6 quit\n' "$T/play.png" > "$T/play.script"
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
    expect "vsv-play URL --script plays (Xvfb)" 0 \
        xvfb-run -a -s "-screen 0 800x600x24" "$B/vsv-play" "$URL" --size 320x240 --script "$T/play.script"
    [ -s "$T/play.png" ] && pass "and takes its screenshot" || fail "and takes its screenshot" "no $T/play.png"
fi
if [ -n "${PYMOD:-}" ] && [ -z "${PY_MISSING:-}" ]; then
    PYTHONPATH="$B/python" expect "the Python module opens the URL and reads the local file's values" 0 "$PY" -c "
import sys, numpy, vesuvius
a = vesuvius.open(sys.argv[1]).read('CLW', 2)
b = vesuvius.open(sys.argv[2]).read('CLW', 2)
sys.exit(0 if numpy.array_equal(a, b, equal_nan=True) and numpy.nanmax(a) > 0 else 1)" "$URL" "$T/www/run.vsv"
fi

# ---- a file replaced by another of the same length, its date kept (the
# same inode: lighttpd's ETag and Last-Modified do not change): the cache
# held the first file's metadata and mixed it with the second's bricks
# (issue 33: 0.5569 printed where the files give 0.4275 or 3.898)
cp "$T/www/run.vsv" "$T/www/swap.vsv"
touch -d '1 hour ago' "$T/www/swap.vsv"
touch -r "$T/www/swap.vsv" "$T/swap.date"
# the second file: every species' quantisation range doubled (the metadata
# and header checksums made again), so every value that is not 0 doubles
"$PY" - "$T/www/swap.vsv" "$T/swapB.vsv" <<'EOF2'
import struct, sys, zlib
d = bytearray(open(sys.argv[1], "rb").read())
def crc32c(b):
    c = 0xFFFFFFFF
    for x in b:
        c ^= x
        for _ in range(8):
            c = (c >> 1) ^ (0x82F63B78 & -(c & 1))
    return c ^ 0xFFFFFFFF
meta_off, meta_size = struct.unpack_from("<QQ", d, 24)
at = meta_off
while at < meta_off + meta_size:
    tag, n = d[at:at + 4], struct.unpack_from("<I", d, at + 4)[0]
    if tag == b"QUAN":
        lo, hi = struct.unpack_from("<dd", d, at + 8 + 16)
        struct.pack_into("<dd", d, at + 8 + 16, lo * 2, hi * 2)
    at += 8 + (n + 7) // 8 * 8
struct.pack_into("<I", d, 40, crc32c(d[meta_off:meta_off + meta_size]))
struct.pack_into("<I", d, 124, crc32c(d[:124]))
open(sys.argv[2], "wb").write(d)
EOF2
"$B/vsv-query" "$T/www/swap.vsv" --cell $CELL --species CLW,Q > "$T/qA"
"$B/vsv-query" "$T/swapB.vsv" --cell $CELL --species CLW,Q > "$T/qB"
! cmp -s "$T/qA" "$T/qB" && [ "$(wc -c < "$T/swapB.vsv")" = "$SIZE" ] && pass "two files of one length that give other values" ||
    fail "two files of one length that give other values" "$(head -c 200 "$T/qB")"
SWAP=http://127.0.0.1:$PORT/swap.vsv
VSV_CACHE_DIR="$T/cache-swap" expect "the first file through a cache: exits 0" 0 "$B/vsv-query" "$SWAP" --cell $CELL --species CLW,Q
same "... and gives its values" "$T/out" "$T/qA"
cat "$T/swapB.vsv" > "$T/www/swap.vsv"
touch -r "$T/swap.date" "$T/www/swap.vsv"
VSV_CACHE_DIR="$T/cache-swap" expect "the file replaced in place, same length and date: exits 0" 0 "$B/vsv-query" "$SWAP" --cell $CELL --species CLW,Q
same "... and gives the new file's values, never a mix of the two" "$T/out" "$T/qB"
VSV_CACHE_DIR="$T/cache-swap" expect "once more, its cache confirmed: exits 0" 0 "$B/vsv-query" "$SWAP" --cell $CELL --species CLW,Q
same "... with the new file's values" "$T/out" "$T/qB"

# ---- a cache data file cut while a run has it mapped (another program
# truncates it; the test shim cuts it right after the map, so no timing):
# an error or the file fetched again, never SIGBUS (issue 33)
# ($key: the cache's name of $URL, above)
cp -r "$T/cache" "$T/cache-cut"
rm -f "$T/x4.png"
VSV_CACHE_DIR="$T/cache-cut" expect "a cache data file cut while mapped: vsv-render exits 0 (fetched again)" 0 \
    env LD_PRELOAD="$(pwd)/$B/tests/libcutmap.so" VSV_TEST_CUT="$T/cache-cut/$key.data" \
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0" \
    "$B/vsv-render" "$URL" --species CLW --time $STEP -o "$T/x4.png"
same "... and gives the same PNG" "$T/x4.png" "$T/local.png"

# ---- damaged cached bytes: the checksums catch them, they are fetched again
"$PY" - "$T/cache" > /dev/null <<'EOF'
import glob, os, sys
meta = glob.glob(os.path.join(sys.argv[1], "*.meta"))[0]
rec = open(meta, "rb").read()
held = rec[rec.index(b"held\n") + 5:]
n = 0
with open(meta[:-5] + ".data", "r+b") as f:
    for b in range(8, len(held) - 2):  # past the header, before the table of contents
        if held[b] == 1:
            f.seek(b * 16384 + 5000)
            c = f.read(1)
            f.seek(b * 16384 + 5000)
            f.write(bytes([c[0] ^ 0xFF]))
            n += 1
print(n)
EOF
expect "damaged cached bytes: vsv-render exits 0" 0 "$B/vsv-render" "$URL" --species CLW --time $STEP -o "$T/x3.png"
same "and gives the same PNG (fetched again)" "$T/x3.png" "$T/local.png"

# ---- the cache's bound: least recently used files go first
cp "$T/www/run.vsv" "$T/www/run2.vsv"
VSV_CACHE_DIR="$T/cache-small" VSV_CACHE_MAX=100000 \
    expect "a cache bound below one file: the first URL" 0 "$B/vsv-render" "$URL" --species CLW --time $STEP -o "$T/b1.png"
VSV_CACHE_DIR="$T/cache-small" VSV_CACHE_MAX=100000 \
    expect "then a second URL" 0 "$B/vsv-render" "${URL%/*}/run2.vsv" --species CLW --time $STEP -o "$T/b2.png"
same "the first gives the same PNG" "$T/b1.png" "$T/local.png"
n=$(ls "$T/cache-small" | grep -c '\.data$')
[ "$n" -le 1 ] && pass "the cache stays under its bound ($n of 2 files kept)" || fail "the cache stays under its bound" "$(ls -s "$T/cache-small")"
stop_server

# ---- faults, through the proxy; no cache, so every range is fetched
start_server
export VSV_CACHE_DIR=off
fault() { # fault NAME MODE N CODE [TEXT: an extended regular expression]
    start_proxy "$2" "$3"
    PURL=http://127.0.0.1:$PPORT/run.vsv
    rm -f "$T/f.png"
    expect "$1: exits $4" "$4" "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/f.png"
    if [ "$4" = 0 ]; then
        same "$1: the same PNG" "$T/f.png" "$T/local.png"
    else
        grep -qE -- "$5" "$T/err" && pass "$1: says so" || fail "$1: says so" "no /$5/ in: $(head -c 300 "$T/err")"
        has "$1: names the URL" "$T/err" "vsv-render: $PURL: "
        [ ! -e "$T/f.png" ] && pass "$1: writes no PNG" || fail "$1: writes no PNG" "$T/f.png exists"
    fi
    stop_proxy
}
fault "through the proxy" pass 0 0
fault "two dropped connections (retried)" drop 2 0
fault "two truncated replies (retried)" truncate 2 0
fault "slow replies" delay 2 0
fault "a server that ignores Range" norange 0 1 "the server ignores range requests"
fault "the file changes while read" etag 3 1 "the file changed on the server while it was read"
fault "garbled bytes" garble 2 1 "checksum mismatch|end marker damaged"
# (the default: 5 retries, 6 attempts in all)
fault "every connection dropped" drop 1000 1 "after 6 attempts"
# a server that stalls: the headers of a chunk's range, then nothing, held
# open until the proxy is killed (issue 33: vsv-play froze, minutes). Each
# attempt fails after $VSV_HTTP_STALL s without a byte, its message saying
# so; the two tools run at once (6 attempts and their back-off: 14 s)
start_proxy stall
PURL=http://127.0.0.1:$PPORT/run.vsv
t0=$(date +%s)
VSV_HTTP_STALL=1 timeout 100 "$B/vsv-query" "$PURL" --cell $CELL --species CLW > "$T/sq.out" 2> "$T/sq.err" &
qpid=$!
VSV_HTTP_STALL=1 timeout 100 "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/s.png" > "$T/sr.out" 2> "$T/sr.err"
rrc=$?
wait $qpid
qrc=$?
took=$(($(date +%s) - t0))
for tool in query render; do
    [ $tool = query ] && rc=$qrc err="$T/sq.err" || rc=$rrc err="$T/sr.err"
    [ "$rc" = 1 ] && pass "a stalled server: vsv-$tool exits 1" || fail "a stalled server: vsv-$tool exits 1" "exit $rc: $(head -c 300 "$err")"
    grep -qE "^vsv-$tool: $PURL: the server stalled: headers, then no data for 1 s \(bytes [0-9]+-[0-9]+\), after 6 attempts\$" "$err" &&
        pass "... vsv-$tool says the server stalled, for how long, where" ||
        fail "... vsv-$tool says the server stalled, for how long, where" "$(head -c 300 "$err")"
done
[ "$took" -lt 40 ] && pass "... both within $took s (6 attempts of 1 s and the back-off)" ||
    fail "... both within 40 s" "$took s"
[ ! -e "$T/s.png" ] && pass "... and no PNG written" || fail "... and no PNG written" "$T/s.png exists"
# vsv-play never waits for the server on its main thread: the script's quit
# runs at its time while a worker waits (the default 30 s stall), and a
# screenshot whose step never comes is said, not waited for
if [ "${VIEWER:-1}" = 1 ] && [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null; then
    printf '0.2 seek %s\n0.3 play\n1 quit\n' $STEP > "$T/stall.script"
    printf '0.2 seek %s\n0.4 screenshot %s\n1 quit\n' $STEP "$T/stall.png" > "$T/stallshot.script"
    for run in quit shot; do
        [ $run = quit ] && script="$T/stall.script" want=0 || script="$T/stallshot.script" want=1
        t0=$(date +%s)
        ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 timeout 100 \
            xvfb-run -a -s "-screen 0 800x600x24" "$B/vsv-play" "$PURL" --size 320x240 --script "$script" \
            > "$T/sp.out" 2> "$T/sp.err"
        rc=$? took=$(($(date +%s) - t0))
        [ $rc = $want ] && [ $took -lt 20 ] &&
            pass "a stalled server: vsv-play --script quits at 1 s, exit $want ($took s)" ||
            fail "a stalled server: vsv-play --script quits at 1 s, exit $want" "exit $rc after $took s: $(tail -c 300 "$T/sp.err")"
    done
    has "... a screenshot whose step never came: said, exit 1" "$T/sp.err" "vsv-play: $PURL: screenshot $T/stall.png not taken: step $STEP not loaded when the run ended"
    [ ! -e "$T/stall.png" ] && pass "... and not written" || fail "... and not written" "$T/stall.png exists"
fi
stop_proxy
# a server that stalls before the file is open (every range request, the
# first included): the script's quit still ends the run at its time, counted
# from the start, said, exit 1; no display needed (no window was opened)
if [ -x "$B/vsv-play" ]; then
    start_proxy stallopen
    PURL=http://127.0.0.1:$PPORT/run.vsv
    printf '0.5 seek %s\n3 quit\n' $STEP > "$T/open.script"
    t0=$(date +%s.%N)
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 timeout 100 env -u DISPLAY \
        "$B/vsv-play" "$PURL" --script "$T/open.script" > "$T/op.out" 2> "$T/op.err"
    rc=$? took=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    [ $rc = 1 ] && awk -v t="$took" 'BEGIN { exit !(t >= 3 && t <= 5) }' &&
        pass "a server stalled at the open: vsv-play quits at the script's 3 s, exit 1 ($took s)" ||
        fail "a server stalled at the open: vsv-play quits at the script's 3 s, exit 1" "exit $rc after $took s: $(tail -c 300 "$T/op.err")"
    has "... and says the file was still opening" "$T/op.err" \
        "vsv-play: $PURL: still opening when the script quit at 3 s (line 2): nothing shown"
    stop_proxy
fi
# the server stalls until the player has said that a step's transfer failed
# (VSV_HTTP_STALL=1: 6 attempts, 14 s), then answers: a later frame tries
# again (a failed transfer is not damage), and the screenshot comes
if [ "${VIEWER:-1}" = 1 ] && [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null; then
    : > "$T/pport.stall"
    start_proxy stallflag
    PURL=http://127.0.0.1:$PPORT/run.vsv
    printf '0.2 seek %s\n0.4 screenshot %s\n30 quit\n' $STEP "$T/back.png" > "$T/back.script"
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 VSV_HTTP_STALL=1 timeout 100 \
        xvfb-run -a -s "-screen 0 800x600x24" "$B/vsv-play" "$PURL" --size 320x240 --script "$T/back.script" \
        > "$T/back.out" 2> "$T/back.err" &
    bpid=$!
    i=0
    while ! grep -q "not loaded yet, trying again" "$T/back.err" 2> /dev/null && [ $i -lt 600 ] && kill -0 $bpid 2> /dev/null; do
        sleep 0.1
        i=$((i + 1))
    done
    rm -f "$T/pport.stall"
    wait $bpid
    rc=$?
    [ $rc = 0 ] && pass "a server that stalls, then answers: vsv-play exits 0" ||
        fail "a server that stalls, then answers: vsv-play exits 0" "exit $rc: $(tail -c 300 "$T/back.err")"
    has "... it said the step was not loaded yet, naming the stall" "$T/back.err" \
        "not loaded yet, trying again: $PURL: the server stalled: headers, then no data for 1 s"
    ! grep -q "damaged" "$T/back.err" && pass "... never called it damaged" || fail "... never called it damaged" "$(grep damaged "$T/back.err")"
    [ -s "$T/back.png" ] && pass "... and the screenshot came once the server answered (tried again)" ||
        fail "... and the screenshot came once the server answered" "no $T/back.png: $(tail -c 300 "$T/back.err")"
    stop_proxy
fi
# the ETag alone changes (a file replaced by one of the same length: the
# proxy's etag mode changes the length too, which tells on its own)
fault "the ETag alone changes while read" etagonly 3 1 "the file changed on the server while it was read \\(ETag "
# a reply gzip-encoded though no encoding was asked for (issue 33 item 11):
# it read as a truncated reply and was retried six times
rm -f "$T/pport.count"
fault "gzip-encoded replies" gzip 1 1 "the server sent the range gzip-encoded \\(Content-Encoding: gzip\\)"
[ "$(cat "$T/pport.count" 2> /dev/null)" = 1 ] && pass "gzip-encoded replies: not retried (one range request)" ||
    fail "gzip-encoded replies: not retried" "$(cat "$T/pport.count" 2> /dev/null) range requests"
# a reply for a range other than the one asked, consistent in itself (its
# body as long as its Content-Range says): refused, not used nor retried
fault "a reply one byte short of the range asked, Content-Range saying so" crend 2 1 "the server answered with another range"
# the file replaced between two runs by one of the same length and
# Last-Modified, another ETag: the cache of the first run is not trusted
rm -f "$T/pport.count" "$T/pport.etag"
start_proxy newetag
PURL=http://127.0.0.1:$PPORT/run.vsv
VSV_CACHE_DIR="$T/cache-etag" expect "through the proxy with a cache: exits 0" 0 \
    "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/e1.png"
n1=$(cat "$T/pport.count" 2> /dev/null || echo 0)
VSV_CACHE_DIR="$T/cache-etag" expect "again, the same ETag: exits 0" 0 \
    "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/e2.png"
n2=$(cat "$T/pport.count" 2> /dev/null || echo 0)
[ "$n1" -gt 0 ] && [ "$n2" = $((n1 + 1)) ] && pass "... and fetches one range, the first block (the cache; $n1 ranges the first time)" ||
    fail "... and fetches one range, the first block (the cache)" "range requests: $n1 after the first run, $n2 after the second"
: > "$T/pport.etag"
VSV_CACHE_DIR="$T/cache-etag" expect "the file replaced (another ETag, the same length): exits 0" 0 \
    "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/e3.png"
same "... and gives the same PNG" "$T/e3.png" "$T/local.png"
n3=$(cat "$T/pport.count" 2> /dev/null || echo 0)
[ "$n3" -gt "$n2" ] && pass "... its cache not trusted: the ranges fetched again ($((n3 - n2)) requests)" ||
    fail "... its cache not trusted: the ranges fetched again" "range requests: $n2 before, $n3 after"
stop_proxy
rm -f "$T/pport.etag" "$T/pport.count"
# a server that gives no validators (no ETag, no Last-Modified): nothing
# tells that a cached copy is still the file, so none is used again
start_proxy novalid
PURL=http://127.0.0.1:$PPORT/run.vsv
VSV_CACHE_DIR="$T/cache-noval" expect "no validators, with a cache: exits 0" 0 \
    "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/v1.png"
n1=$(cat "$T/pport.count" 2> /dev/null || echo 0)
VSV_CACHE_DIR="$T/cache-noval" expect "no validators, again: exits 0" 0 \
    "$B/vsv-render" "$PURL" --species CLW --time $STEP -o "$T/v2.png"
same "... and gives the same PNG" "$T/v2.png" "$T/local.png"
n2=$(cat "$T/pport.count" 2> /dev/null || echo 0)
[ "$n1" -gt 0 ] && [ "$n2" -ge $((2 * n1)) ] && pass "... the cache not used: every range fetched again ($n1, then $((n2 - n1)))" ||
    fail "... the cache not used: every range fetched again" "range requests: $n1 after the first run, $n2 after the second"
stop_proxy
# the server gone in the middle of a session: the first range that fails
# takes all its attempts, the ones after it one each (a player goes on past
# steps it cannot fetch instead of waiting out every back-off: it froze for
# minutes), and the first to succeed again is served
if [ -n "${PYMOD:-}" ] && [ -z "${PY_MISSING:-}" ]; then
    start_proxy down
    PYTHONPATH="$B/python" "$PY" - "http://127.0.0.1:$PPORT/run.vsv" "$T/pport" > "$T/down.out" 2>&1 <<'EOF'
import os, sys, numpy, vesuvius
url, pfile = sys.argv[1], sys.argv[2]
f = vesuvius.open(url)
count = lambda: int(open(pfile + ".count").read()) if os.path.exists(pfile + ".count") else 0
open(pfile + ".down", "w").close()
c0, fails, msg = count(), 0, ""
for t in range(len(f.times)):
    for s in f.species:
        try:
            f.read(s.name, t)
        except vesuvius.Error as e:
            fails, msg = fails + 1, msg or str(e)
c1 = count()
os.remove(pfile + ".down")
back = numpy.nanmax(f.read("CLW", len(f.times) - 1)) > 0 if fails else False  # (NaN below the ground)
print("reads", len(f.times) * len(f.species), "failed", fails, "attempts", c1 - c0, "back", back)
print(msg)
EOF
    set -- $(sed -n 's/^reads \([0-9]*\) failed \([0-9]*\) attempts \([0-9]*\) back \(.*\)$/\1 \2 \3 \4/p' "$T/down.out")
    # (6 attempts a range by default; a read fetches one or two ranges;
    # with every range retried it was over 6 a read)
    if [ $# = 4 ] && [ "$2" -ge 2 ] && [ "$3" -le $((6 + 2 * $2)) ]; then
        pass "a server gone: the first range takes 6 attempts, those after it one each ($3 for $2 failed reads)"
    else
        fail "a server gone: the first range takes 6 attempts, those after it one each" "$(head -c 300 "$T/down.out")"
    fi
    [ "${4:-}" = True ] && pass "and the server back, a read succeeds" ||
        fail "and the server back, a read succeeds" "$(head -c 300 "$T/down.out")"
    stop_proxy
fi
stop_server

# ---- HTTPS: a self-signed certificate for 127.0.0.1, trusted through $CURL_CA_BUNDLE
if [ -f /usr/lib/lighttpd/mod_openssl.so ] && command -v openssl > /dev/null &&
    openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 \
        -keyout "$T/key.pem" -out "$T/cert.pem" > /dev/null 2>&1; then
    start_server ssl
    export VSV_CACHE_DIR="$T/cache-tls"
    SURL=https://127.0.0.1:$PORT/run.vsv
    expect "an untrusted certificate: exits 1" 1 "$B/vsv-render" "$SURL" --species CLW --time $STEP -o "$T/t.png"
    has "and says so" "$T/err" "vsv-render: $SURL: "
    has "and how to trust it" "$T/err" "CURL_CA_BUNDLE=FILE.pem names one to trust"
    CURL_CA_BUNDLE="$T/cert.pem" expect "HTTPS, the certificate trusted: exits 0" 0 \
        "$B/vsv-render" "$SURL" --species CLW --time $STEP -o "$T/t.png"
    same "and gives the same PNG" "$T/t.png" "$T/local.png"
    stop_server
else
    echo "note: HTTPS not tested (lighttpd-mod-openssl or openssl missing)"
fi
