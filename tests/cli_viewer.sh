#!/bin/sh
# cli_viewer.sh — vsv-play: options and errors, then a real window under Xvfb
# (Mesa) driven by --script: screenshots equal where they must (paused, a
# species shown again, a seek back) and differ where they must (time
# advanced, a species hidden). And the FreeVR back end still compiles.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-viewer.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
differ() { if cmp -s "$2" "$3"; then fail "$1" "$2 and $3 are identical"; else pass "$1"; fi; }
if [ "${VIEWER:-1}" != 1 ]; then
    echo "(vsv-play not built: VIEWER=0 or GLFW/GL/FreeType/fontconfig missing; viewer tests skipped)"
    exit 0
fi

if make -s --no-print-directory B="$B" freevr-syntax > "$T/fv" 2>&1; then
    pass "the FreeVR back end compiles against the declarations from FREEVR.md"
else
    fail "the FreeVR back end compiles against the declarations from FREEVR.md" "$(head -c 400 "$T/fv")"
fi

expect "vsv-play --help exits 0" 0 "$B/vsv-play" --help
has "the help names --script" "$T/out" "--script FILE"
expect "vsv-play without a file exits 2" 2 "$B/vsv-play"
expect "vsv-play on a missing file exits 1" 1 "$B/vsv-play" "$T/none.vsv"
has "and names it" "$T/err" "none.vsv"
printf 'not a vsv file at all, just text\n' > "$T/text.vsv"
expect "vsv-play on a wrong kind of file exits 1" 1 "$B/vsv-play" "$T/text.vsv"
has "and says what it is not" "$T/err" "vsv-play: "
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/crop.vsv"
expect "vsv-play --species with an unknown name exits 2 (misuse, as in vsv-render)" 2 "$B/vsv-play" "$T/crop.vsv" --species NOPE
has "and names the species" "$T/err" "'NOPE'"
expect "vsv-play --species naming one twice exits 2" 2 "$B/vsv-play" "$T/crop.vsv" --species CLW:0.3,CLW
has "and names it" "$T/err" "--species: 'CLW' named twice"
expect "vsv-play --size with text after WxH exits 2" 2 "$B/vsv-play" "$T/crop.vsv" --size 300x200x
printf '0.1 play\nsoon quit\n' > "$T/bad.script"
expect "a script line without a time exits 1" 1 "$B/vsv-play" "$T/crop.vsv" --script "$T/bad.script"
has "naming the line" "$T/err" "line 2"
# every line is tried before the window opens: a bad action at 5 s fails at
# once, before the screenshot at 0.2 s (it used to run 5 s first)
printf '0.2 screenshot %s\n0.3 seek 2\n5 bogus\n' "$T/early.png" > "$T/late.script"
expect "a bad action late in a script exits 1 before anything runs" 1 "$B/vsv-play" "$T/crop.vsv" --script "$T/late.script"
has "naming its line" "$T/err" "vsv-play: $T/late.script: line 3: unknown action 'bogus'"
[ -e "$T/early.png" ] && fail "nothing is written" "the screenshot of 0.2 s was" || pass "nothing is written"
printf '0.2 seek 99\n' > "$T/range.script"
expect "a step out of range in a script exits 1 before the window opens" 1 "$B/vsv-play" "$T/crop.vsv" --script "$T/range.script"
has "with the range" "$T/err" "line 1: seek 99: step 99 is out of range (steps 0..3"
# --script FILE: a regular file; a directory read as an empty script, a
# FIFO waited on forever (issue 18)
expect "a directory as --script exits 1" 1 "$B/vsv-play" "$T/crop.vsv" --script "$T"
has "naming it and what it is" "$T/err" "vsv-play: $T: a directory, not a regular file: refused"
expect "a device as --script exits 1" 1 "$B/vsv-play" "$T/crop.vsv" --script /dev/null
has "naming the device" "$T/err" "vsv-play: /dev/null: a character device, not a regular file: refused"
( unset DISPLAY; expect "no display: exits 1" 1 "$B/vsv-play" "$T/crop.vsv" )
( unset DISPLAY; "$B/vsv-play" "$T/crop.vsv" 2>&1 | grep -q "no display" ) && pass "and says there is no display" ||
    fail "and says there is no display" "no message"

if ! command -v xvfb-run > /dev/null; then
    fail "xvfb-run is installed (apt-get install xvfb xauth)" "missing"
    exit 0
fi
cat > "$T/play.script" <<EOS
0.3 screenshot $T/s1.png
0.5 screenshot $T/s2.png
0.6 play
1.6 pause
1.7 screenshot $T/s3.png
1.8 hide CLW
1.9 screenshot $T/s4.png
2.0 show CLW
2.1 screenshot $T/s5.png
2.2 seek 0
2.3 screenshot $T/s6.png
2.4 opacity Q 0
2.5 renderer raycast
2.6 camera 90 45
2.7 screenshot $T/s7.png
2.8 step +2
2.9 screenshot $T/s8.png
3.0 seek 1995-10-24T02:00:00Z
3.1 screenshot $T/s9.png
3.2 quit
EOS
# (leak checking off for the window: Mesa's and fontconfig's own allocations
# live to the end; the player itself is leak-checked in test_viewer)
ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
expect "vsv-play runs a script in a real window (Xvfb) and quit exits 0" 0 \
    xvfb-run -a -s "-screen 0 1024x768x24" "$B/vsv-play" "$T/crop.vsv" --size 480x320 --script "$T/play.script"
has "it reports the pager's statistics" "$T/err" "bricks decoded"
# one second of playing: the frames drawn then, how many showed an earlier step than the clock's
# and how many of those the step of the frame before (counted in order: stalled <= late <= frames)
line=$(grep "frames drawn while playing" "$T/err" || true)
set -- $(echo "$line" | sed -n 's/.* \([0-9]*\) frames drawn while playing: \([0-9]*\) late.*, \([0-9]*\) of them stalled.*/\1 \2 \3/p')
if [ $# -eq 3 ] && [ "$1" -ge 3 ] && [ "$2" -le "$1" ] && [ "$3" -le "$2" ]; then
    pass "it counts the frames drawn while playing, the late and the stalled ones"
else
    fail "it counts the frames drawn while playing, the late and the stalled ones" "$line"
fi
for i in 1 2 3 4 5 6 7 8 9; do
    [ -s "$T/s$i.png" ] || fail "screenshot $i written" "missing"
done
file_ok=$(head -c 8 "$T/s1.png" | od -An -tx1 | tr -d ' \n')
[ "$file_ok" = "89504e470d0a1a0a" ] && pass "screenshots are PNG files" || fail "screenshots are PNG files" "$file_ok"
same "paused with no input: two screenshots are identical" "$T/s1.png" "$T/s2.png"
differ "after playing, time has advanced on screen" "$T/s1.png" "$T/s3.png"
differ "hiding a species changes the picture" "$T/s3.png" "$T/s4.png"
same "showing it again gives the same picture back" "$T/s3.png" "$T/s5.png"
same "seeking back to the start shows the first picture again" "$T/s1.png" "$T/s6.png"
differ "opacity, renderer and camera change the picture" "$T/s6.png" "$T/s7.png"
differ "stepping +2 changes the picture" "$T/s7.png" "$T/s8.png"
same "seeking to the ISO time of step 2 equals stepping there" "$T/s8.png" "$T/s9.png"

# a damaged step (step 2's chunk index fails its checksum): reported on
# stderr once, naming the file and the step, drawn as nothing (not the
# picture before it), and playback goes on (issue 18: the previous picture
# stayed, silently, exit 0); the run ends with exit 1 and a count, so a
# script sees it
python3 - "$T/crop.vsv" "$T/dmg.vsv" <<'EOP'
import struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
toc = struct.unpack_from("<Q", d, 48)[0]
off = struct.unpack_from("<Q", d, toc + 24 * 2)[0]
d[off + 28] ^= 0xff
open(sys.argv[2], "wb").write(d)
EOP
cat > "$T/dmg.script" <<EOS
0.2 seek 1
0.3 screenshot $T/d1.png
0.4 seek 2
0.5 screenshot $T/d2.png
0.6 seek 0
0.7 play
1.5 screenshot $T/d3.png
1.6 quit
EOS
ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
expect "vsv-play through a damaged step plays on, then exits 1" 1 \
    $XVFB -s "-screen 0 1024x768x24" "$B/vsv-play" "$T/dmg.vsv" --size 320x240 --script "$T/dmg.script"
has "the damaged step is reported, naming the file and the step" "$T/err" \
    "vsv-play: $T/dmg.vsv: step 2 (1995-10-24T02:00:00Z) is damaged, not drawn; playing on: "
has "with the damage" "$T/err" "chunk 2"
has "step 3, a delta on step 2, is damaged too" "$T/err" "vsv-play: $T/dmg.vsv: step 3 (1995-10-24T03:00:00Z) is damaged"
has "and counted at the end" "$T/err" "vsv-play: $T/dmg.vsv: 2 steps damaged, not drawn"
# step 1 does not need chunk 2: it plays although the step after it (in the
# pager's window) is damaged (it was reported damaged and drawn as nothing)
grep -q "step 1 (" "$T/err" && fail "step 1, before the damage, is not reported" "$(grep -m1 'step 1 (' "$T/err")" ||
    pass "step 1, before the damage, is not reported"
"$B/vsv-render" "$T/dmg.vsv" --time 1 --size 320x240 -r shearwarp -o "$T/r1.png" -q
same "and its screenshot is vsv-render's frame of it" "$T/r1.png" "$T/d1.png"
[ "$(grep -c 'step 2 (' "$T/err")" = 1 ] && pass "once" || fail "once" "$(grep -c 'step 2 (' "$T/err") times"
[ -s "$T/d1.png" ] && [ -s "$T/d2.png" ] && [ -s "$T/d3.png" ] && pass "screenshots around it written" ||
    fail "screenshots around it written" "$(ls "$T")"
differ "the damaged step is not the picture before it" "$T/d1.png" "$T/d2.png"
