#!/bin/sh
# cli_render.sh — vsv-render from the command line: PNG frames of the MM5
# sample, sequences, species and transfer-function options, errors.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-render.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
# png_size FILE: "W H" from the IHDR chunk
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}'; }

"$B/vsv-convert" -q --time-res 30m samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/storm.vsv"
expect "vsv-render --help" 0 "$B/vsv-render" --help
has "usage printed" "$T/out" "Usage: vsv-render"
expect "vsv-render without -o exits 2" 2 "$B/vsv-render" "$T/storm.vsv"
expect "vsv-render --renderer nope exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --renderer nope
expect "an unknown species exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --species NOPE
expect "a species named twice exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --species CLW,SNOW:0.5,CLW
has "and names it (as vsv-export and vsv-query do)" "$T/err" "vsv-render: --species: 'CLW' named twice"
expect "an empty name in --species exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --species CLW,
has "and says so" "$T/err" "vsv-render: --species CLW,: an empty species name"
expect "--background above 1 exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --background 2,0,0
has "and says each is from 0 to 1" "$T/err" "--background 2,0,0: expected R,G,B, each from 0 to 1"
expect "--background with trailing text exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --background 0,0,0.5x
expect "--background with a negative exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --background 0,-0.1,0
[ ! -e "$T/x.png" ] && pass "and no picture is written" || fail "and no picture is written" "$T/x.png is there"
expect "--size 99999x5 exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --size 99999x5
has "... naming the limits" "$T/err" "--size 99999x5: expected WxH, 1x1 to 16384x16384"
expect "--size with text after WxH exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --size 300x200junk
has "--help states them" "$(sh -c "$B/vsv-render --help > $T/help; echo $T/help")" "image size (default 800x600; at most 16384x16384)"
expect "--background 0,0,1 renders" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/bg.png" --background 0,0,1 --size 64x48
# the default exaggeration of a grid one 20 m level tall (8320 by the rule): at most --exaggerate's 1000
"$B/vsv-convert" -q --vertical even --nz 1 --ztop 20 samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/flat.vsv"
expect "a grid 20 m tall renders" 0 "$B/vsv-render" "$T/flat.vsv" -o "$T/flat.png" --size 64x48
has "... exaggerated 1000 times, the most --exaggerate takes" "$T/err" "exaggeration 1000"
expect "a render of the last step" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/last.png" --size 320x240
if [ "$(head -c 8 "$T/last.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] && [ "$(png_size "$T/last.png")" = "320 240" ]; then
    pass "a 320x240 PNG is written"; else fail "a 320x240 PNG is written" "$(png_size "$T/last.png")"; fi
expect "a sequence with %04d" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/f%04d.png" --times 0:2 --size 64x48 --species CLW:2,SNOW
if [ -f "$T/f0000.png" ] && [ -f "$T/f0002.png" ] && [ ! -f "$T/f0003.png" ]; then pass "three frames numbered from 0"; else fail "three frames numbered from 0" "$(ls "$T")"; fi
expect "several steps without %04d exit 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --times 0:2
cat > "$T/tf.txt" <<'TF'
species CLW
colormap magma
range 0 0.0003
opacity 0 1
TF
expect "a transfer-function file" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/tf.png" --tf "$T/tf.txt" --species CLW --size 64x48
if ! cmp -s "$T/tf.png" "$T/f0006.png" 2>/dev/null; then pass "the transfer function changes the image"; else fail "the transfer function changes the image" "same"; fi
printf 'species CLW\ncolormap rainbow\n' > "$T/bad.txt"
expect "a bad transfer-function file exits 1" 1 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --tf "$T/bad.txt"
has "the bad line is named" "$T/err" "line 2: unknown colour map"
# a binary file as --tf: named by line and byte, its bytes never echoed
printf '\177ELF\002\001\001\000\033[2J\n' > "$T/bin.tf"
expect "a binary file as --tf exits 1" 1 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --tf "$T/bin.tf"
has "... saying it is not text" "$T/err" "bin.tf: line 1: byte 0x7f: not a text file of transfer functions"
LC_ALL=C grep -q "$(printf '\033')" "$T/err" && fail "... no escape byte echoed" "$(cat -v "$T/err")" || pass "... no escape byte echoed"
# tf_refused NAME BYTES WHAT MESSAGE: a --tf file of these bytes (printf
# escapes) exits 1 saying MESSAGE
tf_refused() {
    printf "$2" > "$T/$1.tf"
    expect "$3 in --tf exits 1" 1 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --tf "$T/$1.tf"
    has "... $4" "$T/err" "$1.tf: $4"
}
# a PNG (its first line has no control byte, only 0x89), a NUL, a C1
# control (CSI, which terminals act on) and an overlong form are not text
tf_refused png '\211PNG\r\n\032\n' "a PNG" "line 1: byte 0x89: not a text file of transfer functions (ASCII or UTF-8)"
tf_refused nul 'species CLW\000junk\ncolormap rain\n' "a NUL" "line 1: byte 0x00: not a text file"
tf_refused c1 '\302\23331mRED\n' "a C1 control" "line 1: byte 0xc2: not a text file"
tf_refused long 'species CLW\n# \340\200\257\n' "an overlong UTF-8 form" "line 2: byte 0xe0: not a text file"
printf '# 10 \302\265g/m\302\263, caf\303\251\nspecies CLW\ncolormap rain\n' > "$T/utf8.tf"
expect "UTF-8 in a --tf comment is text" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/utf8.png" --tf "$T/utf8.tf" --size 64x48
# a long comment (characters across byte 511) is one line: the error after it at its line
{ printf '#'; head -c 509 /dev/zero | tr '\0' a; printf '\302\265\342\202\254\nspecies CLW\ncolormap rain\nbogus 1\n'; } > "$T/wide.tf"
expect "a long UTF-8 comment in --tf" 1 "$B/vsv-render" "$T/storm.vsv" -o "$T/x.png" --tf "$T/wide.tf" --species CLW
has "... the error after it at its own line" "$T/err" "wide.tf: transfer function of CLW: line 4: unknown key 'bogus'"
expect "the same frame twice is identical" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/again.png" --size 320x240 --threads 1
if cmp -s "$T/last.png" "$T/again.png"; then pass "1 thread and all threads write the same PNG"; else fail "1 thread and all threads write the same PNG" "differ"; fi
expect "a damaged .vsv exits 1" 1 "$B/vsv-render" tests/golden/bad/payload.vsv -o "$T/x.png" --time 1
has "the damage is named" "$T/err" "payload checksum mismatch"
if [ ! -e "$T/x.png" ] && ! ls "$T" | grep -q '\.tmp\.'; then pass "no image after a failure"; else fail "no image after a failure" "$(ls "$T")"; fi
expect "an EXR frame" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/frame.exr" --size 64x48
if [ "$(head -c 4 "$T/frame.exr" | od -An -tx1 | tr -d ' \n')" = "762f3101" ]; then pass "EXR magic written"; else fail "EXR magic written" "no"; fi
expect "a stereo pair" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/stereo.png" --size 64x48 --stereo
if [ "$(png_size "$T/stereo.png")" = "128 48" ]; then pass "stereo is side by side, twice as wide"; else fail "stereo is side by side, twice as wide" "$(png_size "$T/stereo.png")"; fi
expect "a look-at camera" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/look.png" --size 64x48 --look-at -2600000,700000,30000,-1800000,1500000,0
expect "a look-at camera with eye = target exits 2" 2 "$B/vsv-render" "$T/storm.vsv" -o "$T/x2.png" --look-at 1,2,3,1,2,3
expect "the shear-warp renderer" 0 "$B/vsv-render" -q "$T/storm.vsv" -o "$T/sw.png" --renderer shearwarp --size 64x48
if [ "$(png_size "$T/sw.png")" = "64 48" ]; then pass "shear-warp writes the PNG"; else fail "shear-warp writes the PNG" "$(png_size "$T/sw.png")"; fi
# movies: through ffmpeg, one frame per rendered step
nsteps=$("$B/vsv-info" -f times "$T/storm.vsv" | tr ',' '\n' | grep -c Z)
expect "a movie without ffmpeg on the PATH exits 1" 1 env PATH=/nonexistent "$B/vsv-render" "$T/storm.vsv" --movie "$T/none.mp4" --size 64x48
has "and says ffmpeg is missing" "$T/err" "needs ffmpeg"
if [ ! -e "$T/none.mp4" ]; then pass "and writes no movie"; else fail "and writes no movie" "found"; fi
if command -v ffmpeg > /dev/null && command -v ffprobe > /dev/null; then
    expect "a movie of every step" 0 "$B/vsv-render" -q "$T/storm.vsv" --movie "$T/storm.mp4" --fps 8 --size 97x61 --renderer shearwarp
    frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 "$T/storm.mp4")
    [ "$frames" = "$nsteps" ] && pass "the movie has one frame per step ($frames)" || fail "the movie has one frame per step" "$frames frames, $nsteps steps"
    info=$(ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,width,height,r_frame_rate -of csv=p=0 "$T/storm.mp4")
    [ "$info" = "h264,98,62,8/1" ] && pass "H.264, odd sizes padded to even, 8 frames/s" || fail "H.264, odd sizes padded to even, 8 frames/s" "$info"
    expect "a movie of a range, with frames too" 0 "$B/vsv-render" -q "$T/storm.vsv" --movie "$T/part.mkv" --times 2:4 -o "$T/m%04d.png" --size 64x48
    frames=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 "$T/part.mkv")
    [ "$frames" = 3 ] && [ -f "$T/m0002.png" ] && pass "three steps: three movie frames and three PNGs" || fail "three steps: three movie frames and three PNGs" "$frames"
    if ! ls "$T" | grep -q '\.tmp\.'; then pass "no temporary files left"; else fail "no temporary files left" "$(ls "$T")"; fi
else
    fail "ffmpeg and ffprobe are installed (apt-get install ffmpeg)" "missing"
fi
exit 0
