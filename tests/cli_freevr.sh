#!/bin/sh
# cli_freevr.sh — vsv-play-freevr built against the project's FreeVR stand-in
# (tests/freevr-standin/: FreeVR's conventions from ../shared/docs/FREEVR.md,
# written by the project; it is not FreeVR). Checks, under Xvfb:
#  - --help, --version and every usage or file error answer before
#    vrConfigure (the stand-in never creates its semaphore set);
#  - the one-window simulator, a four-wall CAVE (its layout in ~/.freevrrc,
#    chosen by a FreeVR argument 'usesystem "cave4";') and eight windows (the
#    FREEVR variable; the arena must hold FreeVR's own per-window state):
#    every window that faces the volume shows the rendered terrain, the model
#    time advances between two dumps 2.5-5.5 s apart, Escape (held 0.3 s: input
#    is polled at 60 Hz) ends every process within 5 s with exit 0, and the
#    run's semaphore set is gone;
#  - the simulator again on an http:// URL of the file (lighttpd on a
#    loopback port): the same checks, and the server sent ranges only.
# Windows are dumped by the stand-in (FREEVR_STANDIN_DUMP: each window's back
# buffer read just before the swap) rather than grabbed from the screen, so
# overlapping windows cannot hide each other.
B=${B:-build}
if [ "${VIEWER:-1}" != 1 ]; then
    echo "(the viewer is not built: VIEWER=0 or GLFW/GL/FreeType/fontconfig missing; FreeVR tests skipped)"
    exit 0
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-freevr.XXXXXX")
. tests/cli_lib.sh
# VSV_PLAY_FREEVR: another build of the back end to test (e.g. an older one)
BIN=${VSV_PLAY_FREEVR:-$(pwd)/$B/tests/vsv-play-freevr}
TOP=$(pwd)
SHOT="/usr/bin/python3 $TOP/tests/freevr_shot.py"
VSV=$T/crop.vsv
# semaphore sets this run's stand-in created (the id it prints), removed at
# the end whatever happened, so a failing run leaves nothing behind
sems() { sed -n 's/^FreeVR stand-in: semaphore set \([0-9]*\) .*/\1/p' "$@" 2> /dev/null; }
cleanup() {
    for id in $(sems "$T"/*.err "$T"/*/stderr "$T/err"); do ipcrm -s "$id" 2> /dev/null; done
    pkill -KILL -f "$VSV" 2> /dev/null
    [ -n "${LPID:-}" ] && kill -INT "$LPID" 2> /dev/null
    rm -rf "$T"
}
trap cleanup EXIT
export HOME=$T/home FREEVR_HOME=$T/home
unset FREEVR FREEVR_STANDIN_DUMP
mkdir -p "$T/home" "$T/run"

if [ ! -x "$BIN" ]; then
    fail "the back end builds against the FreeVR stand-in" "no $BIN"
    exit 0
fi
# the build: a clear message without FreeVR; install takes the program and its page
make -s --no-print-directory B="$B" -W viewer/vsv-play-freevr.c FREEVR_DIR=/nonexistent freevr > "$T/out" 2>&1
has "make freevr with a wrong FREEVR_DIR says what is missing" "$T/out" "no include/freevr.h or lib/libfreevr.a"
make -n --no-print-directory B="$B" install FREEVR_DIR="$B/tests/freevr-standin" PREFIX=/p DESTDIR="$T/root" \
    > "$T/out" 2>&1
has "make install FREEVR_DIR=... installs vsv-play-freevr" "$T/out" "$B/vsv-play-freevr"
has "and its manual page" "$T/out" "man/vsv-play-freevr.1"
make -n --no-print-directory B="$B" install PREFIX=/p DESTDIR="$T/root" > "$T/out" 2>&1
grep -q "vsv-play-freevr" "$T/out" && fail "without FREEVR_DIR nothing of it is installed" "$(grep -m1 vsv-play-freevr "$T/out")" ||
    pass "without FREEVR_DIR nothing of it is installed"
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$VSV" || { fail "convert the MM5 sample" "vsv-convert failed"; exit 0; }
cd "$T/run" || exit 1

# ------------------------------------------------ answered before vrConfigure
before() { # NAME CODE ARGS...: exit code, and no semaphore set was created
    name=$1 code=$2
    shift 2
    expect "$name" "$code" "$BIN" "$@"
    cat "$T/err" >> "$T/before.err"
    if grep -q "semaphore set" "$T/err"; then
        fail "$name: before vrConfigure" "FreeVR was configured (a semaphore set was created)"
    fi
}
before "--help exits 0" 0 --help
has "--help shows the usage" "$T/out" "Usage: vsv-play-freevr FILE.vsv"
has "--help names what it reads" "$T/out" "Reads .vsv files (vsv(5)), transfer-function files (--tf) and FreeVR's"
before "--version exits 0" 0 --version
before "no file: usage error" 2
before "an unknown option: usage error" 2 "$VSV" --bogus
before "--renderer gpu: usage error" 2 "$VSV" --renderer gpu
before "two files: usage error" 2 "$VSV" "$VSV"
before "a missing file exits 1" 1 "$T/none.vsv"
has "and names it" "$T/err" "none.vsv"
before "an unknown species: usage error (as vsv-play, vsv-render)" 2 "$VSV" --species NOPE
has "and names the species" "$T/err" "'NOPE'"
before "--iso of an unknown species: usage error (as vsv-play, vsv-render)" 2 "$VSV" --iso NOPE:1e-5
has "and names the file's species" "$T/err" "--iso NOPE:1e-5: no species NOPE (the file has"
before "--iso with no number: usage error" 2 "$VSV" --iso CLW:lots
mkfifo "$T/run/.freevrrc"
CMD_TIMEOUT=20 before "a FIFO as ./.freevrrc exits 1 (no wait for a writer)" 1 "$VSV"
has "and names it" "$T/err" "./.freevrrc: a FIFO, not a regular file: refused"
rm -f "$T/run/.freevrrc"
left=""
for id in $(sems "$T/before.err"); do ipcs -s | awk '{print $2}' | grep -qx "$id" && left="$left $id"; done
[ -z "$left" ] && pass "no semaphore set is left by --help or an error" || fail "no semaphore set is left by --help or an error" "left:$left"

if ! command -v xvfb-run > /dev/null || ! command -v xdotool > /dev/null; then
    fail "xvfb-run and xdotool are installed (sh tools/deps.sh --install)" "missing"
    exit 0
fi

# ------------------------------------------------------------- the layouts
cp "$TOP/tests/freevr_grab.sh" "$T/session.sh"
cat >> "$T/session.sh" << 'EOS'
# runs inside xvfb-run: the back end, two dumps 2.5-5.5 s apart, then Escape
O=$1
shift
FREEVR_STANDIN_DUMP=$O/dump "$BIN" "$VSV" "$@" > "$O/stdout" 2> "$O/stderr" &
pid=$!
frame() { sed -n '2s/^# frame //p;2q' "$1" 2> /dev/null; }
end=$(($(date +%s) + 60))
while [ "$(date +%s)" -lt $end ] && kill -0 $pid 2> /dev/null; do # every window's second frame, 60 s at most
    ok=1
    for w in $WINDOWS; do [ "$(frame "$O/dump/$w.ppm")" -ge 2 ] 2> /dev/null || ok=0; done
    [ $ok = 1 ] && break
    sleep 0.2
done
echo "windows drawn (or 60 s passed) at $(date +%T)" >> "$O/log"
# the second dumps: a newer frame of $CHECK at least 2.5 s later that
# shows another picture (a step lasts 2 s and a lap of four 8 s, so the
# step shown changes; on a loaded machine paging the next step can take
# longer, so the wait for the change is long, 40 s, and not a measure)
# (a copy on a full disk would leave an empty file: grab links)
snap() { for f in "$O"/dump/*.ppm; do grab "$f" "$1/${f##*/}"; done; }
mkdir -p "$O/shot1" "$O/shot2"
t1=$(date +%s%3N)
snap "$O/shot1"
f1=$(frame "$O/shot1/$CHECK.ppm")
sleep 2.5
while :; do
    snap "$O/shot2"
    [ "$(frame "$O/shot2/$CHECK.ppm")" -gt "${f1:-0}" ] 2> /dev/null &&
        ! $SHOT same "$O/shot1/$CHECK.ppm" "$O/shot2/$CHECK.ppm" 2> /dev/null && break
    [ $(($(date +%s%3N) - t1)) -gt 40000 ] && break
    sleep 0.2
done
echo "$CHECK: frames $f1 and $(frame "$O/shot2/$CHECK.ppm") $(($(date +%s%3N) - t1)) ms apart" >> "$O/log"
xdotool keydown Escape
sleep 0.3
xdotool keyup Escape
echo "Escape sent" >> "$O/log"
i=0
while kill -0 $pid 2> /dev/null && [ $i -lt 50 ]; do
    sleep 0.1
    i=$((i + 1))
done
if kill -0 $pid 2> /dev/null; then
    echo "still running 5 s after Escape" > "$O/result"
    kill -KILL $pid
    wait $pid
else
    wait $pid
    echo "exit $?" > "$O/result"
fi
EOS

layout() { # NAME "WINDOWS" "FACING" ARGS...: runs one layout and checks it
    name=$1 WINDOWS=$2 facing=$3
    shift 3
    O=$T/$name
    mkdir -p "$O/dump"
    BIN=$BIN VSV=$VSV WINDOWS=$WINDOWS CHECK=${facing%% *} SHOT=$SHOT timeout -k 5 150 xvfb-run -a -s "-screen 0 1024x768x24" \
        sh "$T/session.sh" "$O" "$@" > "$O/xvfb.log" 2>&1
    r=$(cat "$O/result" 2> /dev/null)
    [ "$r" = "exit 0" ] && pass "$name: Escape ends it, exit 0" ||
        fail "$name: Escape ends it, exit 0" "${r:-no result}; stderr: $(tail -c 400 "$O/stderr")"
    sleep 0.5
    if pgrep -f "$VSV" > /dev/null; then
        fail "$name: no process is left" "$(pgrep -af "$VSV" | head -c 300)"
    else
        pass "$name: no process is left"
    fi
    id=$(sems "$O/stderr")
    if [ -z "$id" ]; then
        fail "$name: FreeVR created its semaphore set" "none reported"
    elif ipcs -s | awk '{print $2}' | grep -qx "$id"; then
        fail "$name: its semaphore set is removed" "set $id is left"
    else
        pass "$name: its semaphore set is removed"
    fi
    if grep -q "Not enough room to amalloc" "$O/stderr"; then
        fail "$name: the shared arena holds FreeVR's state" "$(grep -m1 amalloc "$O/stderr")"
    fi
    if grep -q "cannot understand the configuration string" "$O/stderr"; then
        fail "$name: FreeVR gets only configuration strings" "$(grep -m1 "cannot understand" "$O/stderr")"
    fi
    for w in $WINDOWS; do
        [ -s "$O/shot2/$w.ppm" ] || fail "$name: the $w window draws frames" \
            "no dump of it; dumps: $(cd "$O/dump" && ls -l | tr '\n' ' ' | head -c 600); $(tr '\n' ' ' < "$O/log"); $(df -k "$O" | tail -1)"
    done
    for w in $facing; do
        s=$($SHOT shown "$O/shot2/$w.ppm" 2> /dev/null)
        if [ -n "$s" ] && [ "$(echo "$s >= 0.01" | bc)" = 1 ]; then
            pass "$name: the $w window shows the scene ($s of its pixels)"
        else
            fail "$name: the $w window shows the scene" "${s:-no picture}: nothing but background"
        fi
    done
    w=${facing%% *}
    s=$($SHOT scene "$O/shot2/$w.ppm" 2> /dev/null)
    if [ -n "$s" ] && [ "$(echo "$s >= 0.01" | bc)" = 1 ]; then
        pass "$name: the $w window shows the terrain ($s of its pixels)"
    else
        fail "$name: the $w window shows the terrain" "${s:-no picture}: no land"
    fi
    w=${facing%% *}
    if [ -s "$O/shot1/$w.ppm" ] && ! $SHOT same "$O/shot1/$w.ppm" "$O/shot2/$w.ppm"; then
        pass "$name: the model time advances on the $w window"
    else
        fail "$name: the model time advances on the $w window" "two dumps are the same (or missing): $(grep -m1 frames "$O/log")"
    fi
}

# a step every 2 s, so dumps 2.5-5.5 s apart differ (VSV_FREEVR_PLAY: other
# options, e.g. those an older back end knew: --play --loop)
# Each eye renders at half its window's size: four times less work (the
# sanitizer build renders a 200x200 wall in about 4 s on a busy machine).
PLAY=${VSV_FREEVR_PLAY:---play --loop --rate 1800 --render-scale 0.5}

# the simulator: no configuration at all
layout sim "simulator" "simulator" $PLAY
# an isosurface on the walls (drawn magenta: nothing else is), at the steps
# with cloud (one of the two dumps may show step 0, before any)
layout sim-iso "simulator" "simulator" $PLAY --species RNW --iso 'CLW:5e-5:#ff00ff'
m0=$($SHOT magenta "$T/sim/shot2/simulator.ppm" 2> /dev/null)
m1=$($SHOT magenta "$T/sim-iso/shot1/simulator.ppm" 2> /dev/null)
m2=$($SHOT magenta "$T/sim-iso/shot2/simulator.ppm" 2> /dev/null)
if [ -n "$m1" ] && [ -n "$m2" ] && [ "$(echo "$m1 + $m2 >= 0.0005 && ${m0:-0} == 0" | bc)" = 1 ]; then
    pass "sim-iso: the isosurface shows on the wall ($m1, $m2 of its pixels; $m0 without it)"
else
    fail "sim-iso: the isosurface shows on the wall" "magenta ${m1:-none} and ${m2:-none} of the pixels; ${m0:-none} without it"
fi

# the simulator reading the file from a web server (lighttpd on a loopback
# port, tests/lighttpd_lib.sh): every render process fetches ranges of it
PY=${PYTHON:-/usr/bin/python3}
server_down() { fail "lighttpd starts on a loopback port" "$1"; }
. "$TOP/tests/lighttpd_lib.sh"
if [ -n "$LIGHTTPD" ]; then
    mkdir -p "$T/www"
    cp "$VSV" "$T/www/crop.vsv"
    touch -d '1 hour ago' "$T/www/crop.vsv" # lighttpd sends validators for files not just written
    if start_server; then
        LOCAL=$VSV
        VSV=http://127.0.0.1:$PORT/crop.vsv
        layout sim-url "simulator" "simulator" $PLAY --cache-dir off
        VSV=$LOCAL
        stop_server
        grep -q '^GET .* 206 ' "$T/access.log" && ! grep -q '^GET .* 200 ' "$T/access.log" &&
            pass "sim-url: the file came in range requests only" ||
            fail "sim-url: the file came in range requests only" "$(head -c 300 "$T/access.log")"
    fi
else
    echo "note: vsv-play-freevr on a URL not tested: no lighttpd (tools/deps.sh)"
fi

# four walls of a CAVE from ~/.freevrrc, the system chosen on the command line
wall() { # NAME GEOMETRY CORNERS
    printf 'window "%s" = { mount = "fixed"; GraphicsType = "glx"; args = "geometry=%s; decoration=window"; rw2w_coords = %s; }\n' "$@"
}
# FreeVR's simulated head starts at its tracker's origin, on the floor
# (FREEVR.md): the tracker's origin 5 feet up (t2rw_translate) puts the
# head where a standing user's eyes are, as a CAVE's configuration would
input='process "pin" = { type = input; usecmin = 15000; objects = "xin"; }
inputdevice "xin" = { type = "xwindows"; args = "window = front;";
  input "Escape Key" = "2switch(keyboard:key[Escape])";
  input "left" = "2switch(mouse:button[left])";
  input "middle" = "2switch(mouse:button[middle])";
  input "right" = "2switch(mouse:button[right])";
  input "head" = "6sensor(sim6[0])";
  input "wand" = "6sensor(sim6[1])";
  t2rw_translate = 0, 5, 0; }'
{
    echo '# a four-wall CAVE: front, left, right, floor (feet; corners: lower-left, lower-right, upper-left)'
    echo 'system "cave4" = { type = "cave"; procs = "pf", "pl", "pr", "pb", "pin"; inputmap = "default"; visrenmode = "default"; }'
    wall front 200x200+210+0 "-5,0,-5, 5,0,-5, -5,10,-5"
    wall left 200x200+0+0 "-5,0,5, -5,0,-5, -5,10,5"
    wall right 200x200+420+0 "5,0,-5, 5,0,5, 5,10,-5"
    wall floor 200x200+210+210 "-5,0,5, 5,0,5, -5,0,-5"
    for p in "pf front" "pl left" "pr right" "pb floor"; do
        set -- $p
        echo "process \"$1\" = { type = visren; objects = \"$2\"; }"
    done
    echo "$input"
} > "$T/home/.freevrrc"
layout cave4 "front left right floor" "front left right floor" $PLAY 'usesystem "cave4";'

# eight windows (front and floor halves, left, right, back and ceiling; one
# render process draws the last two) from FREEVR
FREEVR=$(
    echo 'usesystem "wall8";'
    echo 'system "wall8" = { type = "cave"; procs = "p1", "p2", "p3", "p4", "p5", "p6", "p7", "pin"; }'
    wall front-l 120x120+0+0 "-5,0,-5, 0,0,-5, -5,10,-5"
    wall front-r 120x120+125+0 "0,0,-5, 5,0,-5, 0,10,-5"
    wall left 120x120+250+0 "-5,0,5, -5,0,-5, -5,10,5"
    wall right 120x120+375+0 "5,0,-5, 5,0,5, 5,10,-5"
    wall floor-f 120x120+0+125 "-5,0,0, 5,0,0, -5,0,-5"
    wall floor-b 120x120+125+125 "-5,0,5, 5,0,5, -5,0,0"
    wall back 120x120+250+125 "5,0,5, -5,0,5, 5,10,5"
    wall ceiling 120x120+375+125 "-5,10,-5, 5,10,-5, -5,10,5"
    n=1
    for w in front-l front-r left right floor-f floor-b 'back", "ceiling'; do # p7 draws two windows
        echo "process \"p$n\" = { type = visren; objects = \"$w\"; }"
        n=$((n + 1))
    done
    echo "$input"
)
export FREEVR
layout wall8 "front-l front-r left right floor-f floor-b back ceiling" "front-l front-r left right floor-f floor-b" \
    $PLAY
grep -q "8 windows" "$T/wall8/stderr" && pass "wall8: FreeVR started eight windows" ||
    fail "wall8: FreeVR started eight windows" "$(grep -m1 "semaphore set" "$T/wall8/stderr")"
