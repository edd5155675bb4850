#!/bin/sh
# bench_freevr.sh — the FreeVR back end at wall size (issue #30): four
# 1024 x 1024 walls of a CAVE (front, left, right, floor), the project's
# FreeVR stand-in under Xvfb (it is not FreeVR: its windows are what a
# FreeVR render process draws into), the head 5.5 feet up in the middle.
# The clock runs far faster than the walls (every frame takes a new tick
# with a new step: every eye renders every frame), so the figures are of
# rendering, not of redrawing a kept picture. Per wall, from --trace: frames
# a second and CPU milliseconds a frame (its render process's CPU time over
# its frames, all threads). For each CPU renderer (RENDERERS; the GPU
# raycaster too with RENDERERS="shearwarp raycast gl": not by default, as on
# Mesa's llvmpipe a 1024 x 1024 wall takes it seconds a frame), on the real MM5
# run (10-minute steps, the four hydrometeors) and gen-plume's plume and
# haze (16-step series, bench_play --plume). Then the memory of the run (the
# sum of its processes' proportional set sizes) with four walls and with
# one. SECONDS_PER_RUN (default 20) each.
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
TOP=$(pwd)
BIN=${VSV_PLAY_FREEVR:-$TOP/$B/tests/vsv-play-freevr}
RENDERERS=${RENDERERS:-shearwarp raycast}
SECS=${SECONDS_PER_RUN:-20}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-freevr.XXXXXX")
trap 'pkill -KILL -f "^$BIN $W/" 2> /dev/null; rm -rf "$W"' EXIT
[ -x "$BIN" ] || make -s --no-print-directory "$B/tests/vsv-play-freevr"
command -v xvfb-run > /dev/null && command -v xdotool > /dev/null || {
    echo "(bench_freevr: needs xvfb-run and xdotool: sh tools/deps.sh --install)"
    exit 0
}
printf '%s cores; %s; %s\n\n' "$(nproc)" "$(date -u +%Y-%m-%d)" "$(uptime | sed 's/.*load/load/')"

# the data: the real MM5 run, the plume and the haze
sets=""
if [ -f "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" ]; then
    "$B/vsv-convert" -q --vertical even --time-res 10m "$SHARED/data/mm5/run1/MMOUT_DOMAIN1" -o "$W/mm5.vsv"
    sets="mm5"
fi
if [ -f "$SHARED/tools/gen-plume/gen_volume.c" ]; then
    [ -x "$B/bench/bench_play" ] || make -s --no-print-directory "$B/bench/bench_play"
    ${CC:-cc} -O2 -o "$W/gen_volume" "$SHARED/tools/gen-plume/gen_volume.c" -lm
    "$W/gen_volume" "$W" > /dev/null
    "$B/bench/bench_play" --plume "$W/plume.vsv" 16 "$W/plume_t0.f32"
    "$B/bench/bench_play" --plume "$W/haze.vsv" 16 "$W/plume_haze.f32"
    rm -f "$W"/plume_*.f32 "$W"/plume_*.u8 "$W"/plume_*.u16
    sets="$sets plume haze"
fi
[ -n "$sets" ] || { echo "(bench_freevr: no data: $SHARED/data and $SHARED/tools/gen-plume are missing)"; exit 0; }

mkdir -p "$W/home"
wall() { printf 'window "%s" = { mount = "fixed"; GraphicsType = "glx"; args = "geometry=1024x1024+%s; decoration=window"; rw2w_coords = %s; }\n' "$@"; }
{
    echo 'system "cave4" = { type = "cave"; procs = "pf", "pl", "pr", "pb", "pin"; }'
    echo 'system "wall1" = { type = "cave"; procs = "pf", "pin"; }'
    wall front 1030+0 "-5,0,-5, 5,0,-5, -5,10,-5"
    wall left 0+0 "-5,0,5, -5,0,-5, -5,10,5"
    wall right 0+1030 "5,0,-5, 5,0,5, 5,10,-5"
    wall floor 1030+1030 "-5,0,5, 5,0,5, -5,0,-5"
    for p in "pf front" "pl left" "pr right" "pb floor"; do
        set -- $p
        echo "process \"$1\" = { type = visren; objects = \"$2\"; }"
    done
    echo 'process "pin" = { type = input; usecmin = 15000; objects = "xin"; }'
    echo 'inputdevice "xin" = { type = "xwindows"; args = "window = front;";'
    echo '  input "Escape Key" = "2switch(keyboard:key[Escape])";'
    echo '  input "head" = "6sensor(sim6[0])"; t2rw_translate = 0, 5.5, 0; }'
} > "$W/home/.freevrrc"

# run NAME SECONDS ARGS...: the back end for SECONDS, its trace in
# $W/NAME.trace and its peak PSS (kB) in $W/NAME.pss
cat > "$W/run.sh" << 'EOS'
name=$1 secs=$2
shift 2
"$BIN" "$@" > "$W/$name.out" 2> "$W/$name.err" &
pid=$!
peak=0
end=$(($(date +%s) + secs))
while [ "$(date +%s)" -lt $end ] && kill -0 $pid 2> /dev/null; do
    sleep 1
    p=0
    for q in $pid $(pgrep -P $pid); do
        v=$(awk '/^Pss:/ {print $2}' /proc/$q/smaps_rollup 2> /dev/null)
        p=$((p + ${v:-0}))
    done
    [ $p -gt $peak ] && peak=$p
done
echo $peak > "$W/$name.pss"
xdotool keydown Escape
sleep 0.3
xdotool keyup Escape
wait $pid || echo "exit $? ($(tail -c 200 "$W/$name.err"))"
EOS
run() {
    HOME=$W/home FREEVR_HOME=$W/home BIN=$BIN W=$W xvfb-run -a -s "-screen 0 2060x2060x24" sh "$W/run.sh" "$@"
}

echo "## four 1024 x 1024 walls, a new step every tick"
echo
echo "The room's pace is its ticks a second (every wall draws every tick); per"
echo "wall: CPU ms a tick (rendering that wall's picture, all threads of its"
echo "render process), and its frames a second (between ticks a faster wall"
echo "redraws the picture it keeps)."
echo
printf '%-8s %-10s %-12s %s\n' "data" "renderer" "ticks/s" "front / left / right / floor: CPU ms a tick (frames/s)"
for set in $sets; do
    for r in $RENDERERS; do
        # 10-minute steps at 36000 model seconds a second: 60 steps a second
        run "$set-$r" "$SECS" "$W/$set.vsv" --renderer "$r" --play --loop --rate 36000 --no-panel \
            --trace "$W/$set-$r.trace" 'usesystem "cave4";'
        line=""
        rates=$(/usr/bin/python3 "$TOP/tests/freevr_trace.py" rates "$W/$set-$r.trace")
        for win in front left right floor; do
            line="$line$(echo "$rates" | awk -v w="$win" '$1 == w { printf "%.0f (%.1f)", $6, $3 }') / "
        done
        tps=$(echo "$rates" | awk '$1 == "front" { printf "%.2f", $5 }')
        printf '%-8s %-10s %-12s %s\n' "$set" "$r" "$tps" "${line% / }"
        /usr/bin/python3 "$TOP/tests/freevr_trace.py" check "$W/$set-$r.trace" 4 > "$W/check" ||
            echo "  (the time lock did not hold: $(grep -m1 FAULT "$W/check"))"
    done
done
echo
echo "## memory of the run: four walls against one (the sum of its processes' PSS, peak)"
echo
for set in $sets; do
    run "$set-mem4" 12 "$W/$set.vsv" --play --loop --rate 36000 'usesystem "cave4";'
    run "$set-mem1" 12 "$W/$set.vsv" --play --loop --rate 36000 'usesystem "wall1";'
    four=$(cat "$W/$set-mem4.pss") one=$(cat "$W/$set-mem1.pss")
    printf '%-10s four walls %5d MB, one wall %5d MB: %.2fx\n' "$set" $((four / 1024)) $((one / 1024)) \
        "$(echo "$four / $one" | bc -l)"
done
