#!/bin/sh
# demo.sh — the main job end to end on the bundled sample (no ../shared needed):
# real model output → field stream → .vsv → vsv-info.
set -eu
B=${B:-build}
OUT=${OUT:-demo-out}
mkdir -p "$OUT"
step() { printf '\n\033[1m== %s\033[0m\n$ %s\n' "$1" "$2"; }

step "What the sample holds (GrADS model output, 72x46x7, 5 days)" \
     "vsv-extract --list samples/grads/model.ctl"
"$B/vsv-extract" --list samples/grads/model.ctl

step "Convert: extract the 3-D fields and pack them into a .vsv" \
     "vsv-extract samples/grads/model.ctl | vsv-pack -o $OUT/model.vsv"
"$B/vsv-extract" samples/grads/model.ctl | "$B/vsv-pack" -o "$OUT/model.vsv"

step "Inspect" "vsv-info $OUT/model.vsv"
"$B/vsv-info" "$OUT/model.vsv"

step "Verify every checksum and decode everything" "vsv-info --check $OUT/model.vsv"
"$B/vsv-info" --check "$OUT/model.vsv"

step "For scripts: one value of the JSON description" "vsv-info -f species.3.max_abs_error $OUT/model.vsv"
"$B/vsv-info" -f species.3.max_abs_error "$OUT/model.vsv"

step "Statistics of temperature per day" "vsv-info --json --stats $OUT/model.vsv (T rows)"
"$B/vsv-info" --stats "$OUT/model.vsv" | grep -E '^ +(species|T) '
printf '\nDone: %s/model.vsv\n' "$OUT"
