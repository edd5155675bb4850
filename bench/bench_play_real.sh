#!/bin/sh
# bench_play_real.sh — the real player at x8 (issue #36, item 5): vsv-play
# itself under Xvfb, driven by a script, decoding and drawing as a user's
# would (its pager's workers, its renderer, its window), on the real MM5 run
# at 5-minute steps (vsv-convert --time-res 5m), the cache at MB MiB,
# forward and backward at speed 8 for 4 s, looping, with 1 and 2 render
# threads, ROUNDS rounds. Each run prints the frames drawn while playing, how
# many were late (the clock's step not decoded in time: an earlier decoded
# step shown) and how many of those stalled (the picture of the frame
# before again while the clock moved on), how many waited for their step
# (a quarter of a frame at most) and the longest wait, and the pager's
# stalls (species gets that found a brick missing). Needs xvfb (Debian xvfb).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
ROUNDS=${ROUNDS:-3}
MB=${MB:-64}
MM5="$SHARED/data/mm5/run1/MMOUT_DOMAIN1"
if ! command -v xvfb-run >/dev/null; then
    echo "bench_play_real: needs xvfb: apt-get install -y xvfb" >&2
    exit 1
fi
if [ ! -r "$MM5" ]; then
    echo "bench_play_real: $MM5 absent: nothing measured" >&2
    exit 1
fi
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench-play.XXXXXX")
trap 'rm -rf "$W"' EXIT
"$B/vsv-convert" -q --time-res 5m "$MM5" -o "$W/m5.vsv"
printf '0.5 speed 8\n0.6 play\n4.6 quit\n' >"$W/fwd.txt"
printf '0.3 end\n0.5 speed -8\n0.6 play\n4.6 quit\n' >"$W/back.txt"
printf '%s cores; %s UTC; load %s; %s\n\n' "$(nproc)" "$(date -u '+%Y-%m-%d %H:%M')" \
    "$(cut -d' ' -f1-3 /proc/loadavg)" "$("$B/vsv-info" "$W/m5.vsv" | head -1 | sed 's/.*: //')"
echo "vsv-play m5.vsv --cache-mb $MB --loop on --threads N --script (speed 8 or -8 from 0.6 s, quit at 4.6 s)"
echo
echo "| direction | threads | round | frames drawn while playing | late frames | stalled frames | frames that waited | longest wait, ms | pager stalls |"
echo "|---|---|---|---|---|---|---|---|---|"
for threads in 1 2; do
    for dir in fwd back; do
        r=1
        while [ "$r" -le "$ROUNDS" ]; do
            xvfb-run -a -s "-screen 0 1280x1024x24" "$B/vsv-play" "$W/m5.vsv" --cache-mb "$MB" --loop on \
                --threads "$threads" --script "$W/$dir.txt" >"$W/out" 2>&1 || {
                cat "$W/out" >&2
                exit 1
            }
            frames=$(sed -n 's/.* \([0-9]*\) frames drawn while playing: \([0-9]*\) late.*, \([0-9]*\) of them stalled.*/\1 \2 \3/p' "$W/out")
            waits=$(sed -n 's/.* \([0-9]*\) waited for their step, at most \([0-9]*\) ms.*/\1 \2/p' "$W/out")
            stalls=$(sed -n 's/.* \([0-9]*\) stalls, cache peak.*/\1/p' "$W/out")
            set -- $frames $waits
            echo "| $([ $dir = fwd ] && echo forward || echo backward) | $threads | $r | ${1:-?} | ${2:-?} | ${3:-?} | ${4:-?} | ${5:-?} | ${stalls:-?} |"
            echo "$dir $threads $r ${3:--1}" >>"$W/stalled"
            r=$((r + 1))
        done
    done
done
# worst beside best against the goal (issue #36, item 5): x8 both ways
# without a stalled frame (a run whose count could not be read: -1, and a miss)
awk -v mb="$MB" '
    $4 < 0 { bad++; unread++; n++; next }
    { d = ($1 == "fwd" ? "forward" : "backward") ", " $2 " thread" ($2 == 1 ? "" : "s") ", round " $3
      if (!seen || $4 > hi) { hi = $4; hin = d }
      if (!seen || $4 < lo) { lo = $4; lon = d }
      seen = 1; bad += $4 != 0; n++ }
    END { printf "\nStalled frames at x8, %s MiB, both ways: ", mb
          if (seen) printf "worst %d (%s), best %d (%s); ", hi, hin, lo, lon
          if (unread) printf "%d runs whose count could not be read; ", unread
          if (bad) printf "the goal of 0 not met in %d of %d runs\n", bad, n
          else printf "0 in all %d runs: the goal met\n", n }' "$W/stalled"
printf '\nload %s at the end\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
