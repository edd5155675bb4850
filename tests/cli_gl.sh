#!/bin/sh
# cli_gl.sh — the GPU raycaster from the tools (issue 31), on Mesa's llvmpipe:
# vsv-render --renderer gl renders headless (EGL, no display) the picture of
# --renderer raycast; --renderer gl where no OpenGL 3.3 context can be had
# (MESA_GL_VERSION_OVERRIDE=2.1 stands in for an old driver) exits 2 saying
# why, in vsv-render and vsv-play; vsv-play's default picks the CPU's
# shear-warp on a software rasteriser and says so, and says why when the
# GPU raycaster cannot run. Frame against frame at length: tests/test_gl.c.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-gl.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" || { fail "convert the sample" "vsv-convert failed"; exit 0; }
R="$B/vsv-render -q $T/s.vsv --size 200x150 --no-annotate"
unset DISPLAY
expect "vsv-render --renderer gl with no display (EGL)" 0 $R -r gl -o "$T/gl.png"
expect "vsv-render --renderer raycast" 0 $R -r raycast -o "$T/rc.png"
if /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    set -- $(/usr/bin/python3 tests/imgcmp.py "$T/gl.png" "$T/rc.png")
    [ "$(echo "$2 >= 35" | bc)" = 1 ] && pass "--renderer gl draws --renderer raycast's picture ($2 dB PSNR)" ||
        fail "--renderer gl draws --renderer raycast's picture" "$2 dB PSNR"
fi
MESA_GL_VERSION_OVERRIDE=2.1 expect "vsv-render --renderer gl without OpenGL 3.3: exit 2" 2 $R -r gl -o "$T/x.png"
has "... saying why" "$T/err" "--renderer gl: no OpenGL 3.3"
[ -e "$T/x.png" ] && fail "... and writing nothing" "$T/x.png exists" || pass "... and writing nothing"
expect "vsv-render --gpu-mb 8: usage error" 2 $R -r gl --gpu-mb 8 -o "$T/x.png"
if [ "${VIEWER:-1}" = 1 ] && command -v xvfb-run > /dev/null; then
    printf '0.3 screenshot %s\n0.4 quit\n' "$T/p.png" > "$T/q.script"
    # (the GLX driver and fontconfig keep memory to the end: not Vesuvius's leaks)
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
    export ASAN_OPTIONS
    P="$B/vsv-play $T/s.vsv --size 200x150 --script $T/q.script"
    CMD_TIMEOUT=120 expect "vsv-play by default on llvmpipe" 0 $XVFB -s "-screen 0 640x480x24" $P
    has "... says it takes the CPU's shear-warp, and why" "$T/err" \
        "vsv-play: renderer: shear-warp (OpenGL here is llvmpipe"
    CMD_TIMEOUT=120 MESA_GL_VERSION_OVERRIDE=2.1 expect "vsv-play --renderer gl without OpenGL 3.3: exit 2" 2 \
        $XVFB -s "-screen 0 640x480x24" $P -r gl
    has "... saying why" "$T/err" "--renderer gl: OpenGL 2.1"
    CMD_TIMEOUT=120 expect "vsv-play --renderer gl on llvmpipe" 0 $XVFB -s "-screen 0 640x480x24" $P -r gl
fi
