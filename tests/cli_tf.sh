#!/bin/sh
# cli_tf.sh — transfer-function files (SPEC.md §14, vsv-render --tf): a
# range is two absolute values in the species' units (the same picture as
# --range with those values, whatever the file's own data range), checked
# (finite, LO < HI, nothing after them) with errors naming the file, the
# species and the file's own line number.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-tf.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" --vars CLW,SNOW
R="$B/vsv-render -q $T/s.vsv --time 3 --size 160x120 --species CLW,SNOW"
printf '# shared scale\nspecies CLW\ncolormap clouds\nrange 0 0.0003\nopacity 0 1\n' > "$T/abs.tf"
expect "a transfer-function file with an absolute range" 0 $R --tf "$T/abs.tf" -o "$T/tf.png"
printf 'species CLW\ncolormap clouds\nopacity 0 1\n' > "$T/norange.tf"
expect "the same colour map without a range" 0 $R --tf "$T/norange.tf" --range CLW=0:0.0003 -o "$T/range.png"
same "a file's range is absolute values: the picture of --range CLW=0:0.0003" "$T/tf.png" "$T/range.png"

bad() { # NAME RANGE-LINE
    printf '# line 1\nspecies SNOW\ncolormap snow\n\nspecies CLW\ncolormap clouds\n%s\nopacity 0 1\n' "$2" > "$T/bad.tf"
    expect "range '$2' exits 1" 1 $R --tf "$T/bad.tf" -o "$T/x.png"
    has "range '$2': the file, species and line 7 named" "$T/err" "bad.tf: transfer function of CLW: line 7: range needs finite LO HI"
}
bad "LO >= HI" "range 0.001 0.0001"
bad "infinite" "range 0 inf"
bad "NaN" "range nan 1"
bad "a unit after the values" "range 0 1e-3kg"
bad "one value" "range 0.001"
[ -e "$T/x.png" ] && fail "no image is written for a bad transfer function" "x.png exists" ||
    pass "no image is written for a bad transfer function"

# a --tf that is not a regular file: a directory was read as no text and
# ignored (exit 0), a FIFO would block; each is refused naming it
mkdir "$T/tfdir"
expect "--tf naming a directory exits 1" 1 "$B/vsv-render" -q "$T/s.vsv" --tf "$T/tfdir" -o "$T/d.png" --size 64x48
has "saying what it is" "$T/err" "$T/tfdir: a directory, not a regular file: refused"
mkfifo "$T/tffifo"
expect "--tf naming a FIFO exits 1" 1 timeout 60 "$B/vsv-render" -q "$T/s.vsv" --tf "$T/tffifo" -o "$T/d.png" --size 64x48
has "saying what it is" "$T/err" "$T/tffifo: a FIFO, not a regular file: refused"
[ ! -e "$T/d.png" ] && pass "and no image" || fail "and no image" "d.png written"
