#!/bin/sh
# cli_picture.sh — vsv-render's picture options (issue 20): --range fixes the
# values a species' colours span, water vapour is off by default, --view.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-picture.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv" --vars Q,CLW,SNOW
R="$B/vsv-render -q $T/s.vsv --time 3 --size 160x120"
expect "a default render" 0 $R -o "$T/default.png"
expect "CLW and SNOW alone" 0 $R -o "$T/cs.png" --species CLW,SNOW
same "water vapour is off by default" "$T/default.png" "$T/cs.png"
expect "--range CLW=0:0.01" 0 $R -o "$T/range.png" --range CLW=0:0.01
if cmp -s "$T/range.png" "$T/default.png"; then fail "--range changes the colours" "same image"; else pass "--range changes the colours"; fi
expect "--range with LO >= HI exits 2" 2 $R -o "$T/x.png" --range CLW=1:0
expect "--range of an unknown species exits 2" 2 $R -o "$T/x.png" --range NOPE=0:1
expect "--range without a species exits 2" 2 $R -o "$T/x.png" --range 0:1
expect "--view plan" 0 $R -o "$T/plan.png" --view plan
expect "--view sideways exits 2" 2 $R -o "$T/x.png" --view sideways
has "--help names --range" "$(sh -c "$B/vsv-render --help > $T/help; echo $T/help")" "--range SPECIES:LO:HI"
# colour maps and log scales by species, in every renderer alike
expect "--colormap CLW:magma" 0 $R -o "$T/magma.png" --colormap CLW:magma
if cmp -s "$T/magma.png" "$T/default.png"; then fail "--colormap changes the colours" "same image"; else pass "--colormap changes the colours"; fi
expect "--log CLW" 0 $R -o "$T/log.png" --log CLW
if cmp -s "$T/log.png" "$T/default.png"; then fail "--log changes the colours" "same image"; else pass "--log changes the colours"; fi
expect "--colormap CLW:rainbow exits 2" 2 $R -o "$T/x.png" --colormap CLW:rainbow
has "... naming the maps there are" "$T/err" "no colour map 'rainbow' (viridis, magma, cividis"
expect "--log NOPE exits 2" 2 $R -o "$T/x.png" --log NOPE
has "... naming the file and species" "$T/err" "--log: $T/s.vsv has no species 'NOPE'"
expect "--log CLW --range CLW:0:1 exits 2" 2 $R -o "$T/x.png" --log CLW --range CLW:0:1
has "... a log scale needs a range above 0" "$T/err" "a log scale needs a range above 0"
for tool in vsv-play vsv-play-freevr; do
    [ -x "$B/$tool" ] || continue
    "$B/$tool" --help > "$T/help"
    has "$tool --help names --colormap, --log and --range" "$T/help" "--log SPECIES"
    expect "$tool --colormap CLW:rainbow exits 2" 2 "$B/$tool" "$T/s.vsv" --colormap CLW:rainbow
    expect "$tool --log NOPE exits 2" 2 "$B/$tool" "$T/s.vsv" --log NOPE
    has "... naming the species" "$T/err" "has no species 'NOPE'"
done
# a shared scale: two files of the same data, one quantised over another
# range (vsv-convert --range), differ by default (each colours its own
# range) and agree within 1/255 with the same --range (one colour, one value)
if /usr/bin/python3 -c "import numpy, PIL" 2> /dev/null; then
    "$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP --vars CLW -o "$T/a.vsv"
    "$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP --vars CLW --range CLW=0:0.01 -o "$T/b.vsv"
    for f in a b; do
        "$B/vsv-render" -q "$T/$f.vsv" --time 3 --size 160x120 --no-annotate -o "$T/$f-own.png"
        "$B/vsv-render" -q "$T/$f.vsv" --time 3 --size 160x120 --no-annotate --range CLW=0:0.0003 -o "$T/$f-shared.png"
    done
    set -- $(/usr/bin/python3 tests/imgregion.py diff "$T/a-own.png" "$T/b-own.png")
    [ "$1" -ge 20 ] && pass "two files' own ranges: different colours ($2 pixels, by up to $1/255)" ||
        fail "two files' own ranges: different colours" "by at most $1/255"
    set -- $(/usr/bin/python3 tests/imgregion.py diff "$T/a-shared.png" "$T/b-shared.png")
    [ "$1" -le 1 ] && pass "--range CLW=0:0.0003 on both: the same colours ($2 pixels differ by <= $1/255)" ||
        fail "--range CLW=0:0.0003 on both: the same colours" "$2 pixels differ, by up to $1/255"
fi
