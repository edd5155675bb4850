#!/bin/sh
# cli_plot.sh — vsv-plot (issue 35, item 6): a vertical cross-section, a time
# series and a profile of the bundled MM5 sample, read back from their SVG
# (tests/svgtext.py, xml.etree): the axes' titles and units, tick labels in
# order, the title's time and place, the colour bar's ends; the numbers drawn
# (--csv) are vsv-query's; PNG and PDF are whole files of their kind; bad
# options exit 2 saying why, a line or point off the grid exits 1 naming the
# grid's range, and no output is left half-written.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-plot.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
PY=/usr/bin/python3
# (under SAN=1: what fontconfig keeps for cairo's text until exit is not a leak of ours)
LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$(pwd)/tests/lsan.supp:fast_unwind_on_malloc=0:print_suppressions=0"
export LSAN_OPTIONS

"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/s.vsv"
P="$B/vsv-plot $T/s.vsv"
# a column name holding a comma or a quote (units from the file) is quoted
# as RFC 4180 has it, as vsv-query --csv quotes it (cli_query.sh)
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -v CLW --no-winds --derive 'dbl=CLW*2:g,"kg"' -o "$T/odd.vsv"
expect "--csv of a species whose units hold a comma and quotes" 0 "$B/vsv-plot" "$T/odd.vsv" --profile 46,-116 \
    -s dbl -t 0 -o "$T/odd.svg" --csv "$T/odd.csv"
has "... quotes that column" "$T/odd.csv" ',"dbl (g,""kg"")"'
# a species without units: its bare name (it was "bare ()")
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -v CLW --no-winds --derive 'bare=CLW*2' -o "$T/bare.vsv"
expect "--csv of a species without units" 0 "$B/vsv-plot" "$T/bare.vsv" --profile 46,-116 -s bare -t 0 \
    -o "$T/bare.svg" --csv "$T/bare.csv"
if head -n 1 "$T/bare.csv" | grep -q ',bare$'; then pass "... names its column bare"; else fail "... names its column bare" "$(head -n 1 "$T/bare.csv")"; fi
# CLW at step 0 is 0 everywhere: the bar spans CLW's range in the file (it
# spanned a made-up 0 to 1, read as up to 1 kg/kg)
expect "a section of a field that is 0 everywhere" 0 "$B/vsv-plot" "$T/s.vsv" --section 45,-125:52,-115 -s CLW -t 0 \
    -o "$T/zero.svg"
has "... its bar spans the species' range in the file" "$T/zero.svg" ">0.0005<"
# a section whose view is all below the ground: nothing to plot, said (it
# drew an empty panel with a made-up 0 to 1 scale, exit 0)
"$B/vsv-convert" -q --vertical even samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/even.vsv"
expect "a section all below the ground exits 1" 1 "$B/vsv-plot" "$T/even.vsv" --section 45,-118:47,-114 -s CLW \
    --top 100 -o "$T/under.svg"
has "... saying there is nothing to plot" "$T/err" "nothing to plot: every value in view is no data"
[ ! -e "$T/under.svg" ] && pass "... and writes no plot" || fail "... and writes no plot" "$T/under.svg exists"
# texts FILE.svg: what it says, into FILE.txt (class TAB text per line)
texts() { $PY tests/svgtext.py "$1" > "${1%.svg}.txt" 2> "$T/svgerr" || fail "$1 is SVG" "$(cat "$T/svgerr")"; }
# col FILE CLASS: the texts of that class, one a line
col() { awk -F '\t' -v c="$2" '$1 == c { print $2 }' "$1"; }
# increasing NAME: stdin's numbers (one a line, at least 3) strictly increase
increasing() {
    r=$(awk 'NR > 1 && !($1 + 0 > p + 0) { bad = 1 } { p = $1; n++ } END { print (n >= 3 && !bad) ? "ok" : "no " n }')
    [ "$r" = ok ] && pass "$1" || fail "$1" "$r"
}

# ---------------------------------------------------------------- the section
expect "--section to SVG" 0 $P --section 45,-125:52,-115 --species CLW --time 3 -o "$T/sec.svg" --csv "$T/sec.csv"
texts "$T/sec.svg"
has "section: 800 x 600 by default" "$T/sec.txt" "size 800px 600px"
has "section: the x axis is distance (km)" "$T/sec.txt" "xlabel	distance (km)"
has "section: the y axis is height (km)" "$T/sec.txt" "ylabel	height (km)"
has "section: the colour bar names the species and its units" "$T/sec.txt" "cbar-label	CLW (kg/kg)"
col "$T/sec.txt" title > "$T/title"
has "section: the title has the time" "$T/title" "1995-10-24T03:00:00Z"
has "section: the title has the species" "$T/title" "CLW"
has "section: the subtitle has the place" "$T/sec.txt" "45.00N 125.00W to 52.00N 115.00W"
col "$T/sec.txt" xtick | increasing "section: distance tick labels increase"
[ "$(col "$T/sec.txt" xtick | head -n 1)" = 0 ] && pass "section: distance starts at 0" ||
    fail "section: distance starts at 0" "$(col "$T/sec.txt" xtick | head -n 1)"
col "$T/sec.txt" ytick | increasing "section: height tick labels increase"
col "$T/sec.txt" cbar-tick | increasing "section: colour bar labels increase"
awk '$1 == "images" && $2 >= 1 { ok = 1 } END { exit !ok }' "$T/sec.txt" && pass "section: the values are an image" ||
    fail "section: the values are an image" "$(grep images "$T/sec.txt")"
# the colour bar spans the values shown: its end labels are their extremes (3 digits)
lo=$(col "$T/sec.txt" cbar-tick | head -n 1) hi=$(col "$T/sec.txt" cbar-tick | tail -n 1)
set -- $(awk -F, 'NR > 1 && $9 != "NaN" { v = $9 + 0; if (!n++ || v < mn) mn = v; if (n == 1 || v > mx) mx = v }
    END { printf "%.9g %.9g\n", mn, mx }' "$T/sec.csv")
awk -v a="$lo" -v b="$hi" -v mn="$1" -v mx="$2" 'function d(x, y) { return x - y < 0 ? y - x : x - y }
    BEGIN { exit !(mx > 0 && d(a, mn) <= 0.005 * mx && d(b, mx) <= 0.005 * mx) }' &&
    pass "section: the colour bar runs from the least to the greatest value drawn ($lo to $hi)" ||
    fail "section: the colour bar runs from the least to the greatest value drawn" "bar $lo..$hi, values $1..$2"
# the numbers: a cell of the section is vsv-query's cell, byte for byte
head -n 1 "$T/sec.csv" > "$T/head"
has "section CSV: its columns" "$T/head" "time,distance (km),i,j,k,lat,lon,height (m),CLW (kg/kg)"
row=$(awk -F, 'NR > 1 && $9 != "NaN" && $9 + 0 > best { best = $9 + 0; r = $0 } END { print r }' "$T/sec.csv")
set -- $(echo "$row" | awk -F, '{ print $3, $4, $5 }')
"$B/vsv-query" "$T/s.vsv" --cell "$1,$2,$3" --species CLW --time 3 --csv | sed -n 2p > "$T/q"
echo "$row" | cut -d, -f1,3- > "$T/r"
[ -s "$T/q" ] && same "section: its cloudiest cell ($1,$2,$3) is vsv-query's value there" "$T/q" "$T/r"
awk -F, 'NR > 1 && $9 + 0 > 0 { n++ } END { exit !(n > 0) }' "$T/sec.csv" && pass "section: cloud on the line" ||
    fail "section: cloud on the line" "every value 0"
# distances from 0 to the line's length on the sphere (R 6370 km), within 1 %
len=$($PY -c 'import math
a, b, c, d = map(math.radians, (45, -125, 52, -115))
print(6370 * math.acos(math.sin(a) * math.sin(c) + math.cos(a) * math.cos(c) * math.cos(d - b)))')
awk -F, -v L="$len" 'NR == 2 { first = $2 } NR > 1 { last = $2 }
    END { exit !(first == 0 && last > 0.99 * L && last < 1.01 * L) }' "$T/sec.csv" &&
    pass "section: distances run from 0 to the line's length ($len km)" ||
    fail "section: distances run from 0 to the line's length ($len km)" "$(sed -n '2p;$p' "$T/sec.csv" | cut -d, -f2 | tr '\n' ' ')"

# its options
expect "--range 0:0.0006" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --range 0:0.0006 -o "$T/range.svg"
texts "$T/range.svg"
lo=$(col "$T/range.txt" cbar-tick | head -n 1) hi=$(col "$T/range.txt" cbar-tick | tail -n 1)
awk -v a="$lo" -v b="$hi" 'BEGIN { exit !(a == 0 && b == 0.0006) }' &&
    pass "--range 0:0.0006: the colour bar's ends are 0 and 0.0006" || fail "--range 0:0.0006: the colour bar's ends" "$lo, $hi"
expect "--log" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --log -o "$T/log.svg"
texts "$T/log.svg"
has "--log: the colour bar says so" "$T/log.txt" "cbar-label	CLW (kg/kg, log)"
lo=$(col "$T/log.txt" cbar-tick | head -n 1) hi=$(col "$T/log.txt" cbar-tick | tail -n 1)
awk -v a="$lo" -v b="$hi" 'BEGIN { exit !(a > 0 && a >= b * 0.99e-4 && a < b) }' &&
    pass "--log: the bar spans at most four decades below the top ($lo to $hi)" || fail "--log: the bar's range" "$lo, $hi"
expect "--top 5000" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --top 5000 -o "$T/top.svg"
texts "$T/top.svg"
t=$(col "$T/top.txt" ytick | tail -n 1)
awk -v t="$t" 'BEGIN { exit !(t <= 5 && t >= 4) }' && pass "--top 5000: the height axis ends at 5 km ($t)" ||
    fail "--top 5000: the height axis ends at 5 km" "last tick $t"
expect "--top 1500" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --top 1500 -o "$T/low.svg"
texts "$T/low.svg"
has "--top 1500: heights in metres" "$T/low.txt" "ylabel	height (m)"
expect "--size 640x480 --colormap magma" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --size 640x480 \
    --colormap magma -o "$T/magma.svg"
texts "$T/magma.svg"
has "--size 640x480: the SVG's size" "$T/magma.txt" "size 640px 480px"
if [ ! -s "$T/magma.svg" ] || cmp -s "$T/magma.svg" "$T/sec.svg"; then fail "--colormap magma changes the colours" "same file"; else
    pass "--colormap magma changes the colours"; fi
expect "--title with % and markup" 0 $P --section 45,-125:52,-115 --species CLW --time 3 \
    --title 'Cloud %s%n & <b>"x"</b>' -o "$T/title.svg"
texts "$T/title.svg"
[ "$(col "$T/title.txt" title)" = 'Cloud %s%n & <b>"x"</b>' ] && pass "--title: the title as given (no format, escaped)" ||
    fail "--title: the title as given" "$(col "$T/title.txt" title)"
expect "--title with a byte that is not UTF-8" 0 $P --section 45,-125:52,-115 --species CLW --time 3 \
    --title "$(printf 'bad \377 byte')" -o "$T/bad.svg"
texts "$T/bad.svg"
[ "$(col "$T/bad.txt" title)" = 'bad ? byte' ] && pass "... shows it as ? (the SVG stays XML)" ||
    fail "... shows it as ? (the SVG stays XML)" "$(col "$T/bad.txt" title)"

# ------------------------------------------------------------------ the series
expect "--series to SVG" 0 $P --series 51,-126,2000 --species CLW,SNOW -o "$T/ser.svg" --csv "$T/ser.csv"
texts "$T/ser.svg"
has "series: the x axis is time" "$T/ser.txt" "xlabel	time (UTC)"
has "series: the y axis names the species and units" "$T/ser.txt" "ylabel	CLW, SNOW (kg/kg)"
has "series: a legend entry for CLW" "$T/ser.txt" "legend	CLW"
has "series: a legend entry for SNOW" "$T/ser.txt" "legend	SNOW"
has "series: the date under the time axis" "$T/ser.txt" "xdate	1995-10-24"
col "$T/ser.txt" title > "$T/title"
has "series: the title has the place" "$T/title" "51.00N 126.00W"
has "series: the title has the height" "$T/title" "2000 m"
has "series: the subtitle has the times" "$T/ser.txt" "1995-10-24T00:00:00Z to 1995-10-24T03:00:00Z"
col "$T/ser.txt" xtick | awk -F: '{ print $1 * 60 + $2 }' | increasing "series: time tick labels increase (HH:MM)"
col "$T/ser.txt" ytick | increasing "series: value tick labels increase"
"$B/vsv-query" "$T/s.vsv" --at 51,-126,2000 --species CLW,SNOW --csv > "$T/q.csv"
same "series: its numbers are vsv-query --at's" "$T/ser.csv" "$T/q.csv"
expect "--series one step (--time)" 0 $P --series 50,-120 --species CLW --time 1 -o "$T/one.svg"

# ----------------------------------------------------------------- the profile
expect "--profile to SVG" 0 $P --profile 50,-120 --species Q,CLW --time 3 -o "$T/pro.svg" --csv "$T/pro.csv"
texts "$T/pro.svg"
has "profile: the x axis names the species and units" "$T/pro.txt" "xlabel	Q, CLW (kg/kg)"
has "profile: the y axis is height (km)" "$T/pro.txt" "ylabel	height (km)"
has "profile: a legend entry for Q" "$T/pro.txt" "legend	Q"
col "$T/pro.txt" title > "$T/title"
has "profile: the title has the time" "$T/title" "1995-10-24T03:00:00Z"
has "profile: the title has the place" "$T/title" "50.00N 120.00W"
col "$T/pro.txt" ytick | increasing "profile: height tick labels increase"
col "$T/pro.txt" xtick | increasing "profile: value tick labels increase"
"$B/vsv-query" "$T/s.vsv" --profile 50,-120 --species Q,CLW --time 3 --csv > "$T/q.csv"
same "profile: its numbers are vsv-query --profile's" "$T/pro.csv" "$T/q.csv"
expect "--profile --csv - (stdout)" 0 $P --profile 50,-120 --species Q,CLW --time 3 -o "$T/pro2.svg" --csv -
same "--csv -: the same numbers on stdout" "$T/out" "$T/q.csv"

# --------------------------------------------------------------- PNG and PDF
expect "--section to PNG" 0 $P --section 45,-125:52,-115 --species CLW --time 3 --size 640x480 -o "$T/sec.png"
r=$($PY -c 'import struct, sys
b = open(sys.argv[1], "rb").read()
ok = b[:8] == b"\x89PNG\r\n\x1a\n" and b[12:16] == b"IHDR" and b.endswith(b"IEND\xaeB`\x82")
print("%s %dx%d" % ("ok" if ok else "bad", *struct.unpack(">II", b[16:24])))' "$T/sec.png")
[ "$r" = "ok 640x480" ] && pass "PNG: a whole PNG of 640 x 480" || fail "PNG: a whole PNG of 640 x 480" "$r"
expect "--series to PDF" 0 $P --series 50,-120 --species CLW,SNOW -o "$T/ser.pdf"
head -c 5 "$T/ser.pdf" > "$T/pdfhead"
has "PDF: it starts %PDF-" "$T/pdfhead" "%PDF-"
tail -c 8 "$T/ser.pdf" > "$T/pdftail"
has "PDF: it ends %%EOF" "$T/pdftail" "%%EOF"
expect "--profile to PDF (.PDF)" 0 $P --profile 50,-120 --species Q -o "$T/pro.PDF"

# ------------------------------------------------------------------- misuse
expect "no plot kind exits 2" 2 $P -o "$T/x.svg"
has "... saying which there are" "$T/err" "give one of --section, --series or --profile"
expect "two plot kinds exit 2" 2 $P --series 50,-120 --profile 50,-120 -o "$T/x.svg"
expect "no -o exits 2" 2 $P --profile 50,-120
has "... saying so" "$T/err" "no output"
expect "-o x.gif exits 2" 2 $P --profile 50,-120 -o "$T/x.gif"
has "... naming the formats" "$T/err" ".png, .svg or .pdf"
expect "--section with one point exits 2" 2 $P --section 45,-125 -o "$T/x.svg"
has "... saying what it takes" "$T/err" "expected LAT1,LON1:LAT2,LON2"
expect "--section with one point twice exits 2" 2 $P --section 45,-125:45,-125 -o "$T/x.svg"
expect "--section of two species exits 2" 2 $P --section 45,-125:52,-115 --species CLW,SNOW -o "$T/x.svg"
has "... saying it draws one" "$T/err" "one species"
expect "--species NOPE exits 2" 2 $P --profile 50,-120 --species NOPE -o "$T/x.svg"
expect "--range 2:1 exits 2" 2 $P --profile 50,-120 --range 2:1 -o "$T/x.svg"
has "... saying what it takes" "$T/err" "LO < HI"
expect "--log --range 0:1 exits 2" 2 $P --profile 50,-120 --log --range 0:1 -o "$T/x.svg"
has "... a log scale needs LO > 0" "$T/err" "a log scale needs LO > 0"
expect "--colormap rainbow exits 2" 2 $P --section 45,-125:52,-115 --colormap rainbow -o "$T/x.svg"
has "... naming the maps" "$T/err" "no colour map 'rainbow' (viridis, magma"
expect "--size 0x10 exits 2" 2 $P --profile 50,-120 --size 0x10 -o "$T/x.svg"
expect "--times with --section exits 2" 2 $P --section 45,-125:52,-115 --times 0:2 -o "$T/x.svg"
expect "--top -5 exits 2" 2 $P --profile 50,-120 --top -5 -o "$T/x.svg"
expect "--top with --series exits 2" 2 $P --series 50,-120 --top 5000 -o "$T/x.svg"
expect "--csv with the plot's own name exits 2" 2 $P --profile 50,-120 -o "$T/x.svg" --csv "$T/x.svg"
expect "--series 50 exits 2" 2 $P --series 50 -o "$T/x.svg"
expect "an unknown option exits 2" 2 $P --profile 50,-120 --bogus -o "$T/x.svg"
# off the grid: exit 1, naming the grid's range; nothing written
expect "a line off the grid exits 1" 1 $P --section 10,-100:12,-90 -o "$T/x.svg"
has "... naming the file and the grid's range" "$T/err" \
    "vsv-plot: $T/s.vsv: --section 10,-100:12,-90: 10,-100 is outside the grid (39 x 39 cells spanning latitude 42.515..56.454"
expect "a point off the grid exits 1" 1 $P --series 10,-100 -o "$T/x.svg"
has "... naming the grid's range" "$T/err" "is outside the grid (39 x 39 cells"
expect "a time outside the run exits 1" 1 $P --profile 50,-120 --time 9 -o "$T/x.svg"
expect "a missing file exits 1" 1 "$B/vsv-plot" "$T/none.vsv" --profile 50,-120 -o "$T/x.svg"
expect "an output in a missing folder exits 1" 1 $P --profile 50,-120 -o "$T/no/x.svg"
has "... naming it" "$T/err" "$T/no/x.svg"
# the plot and its CSV: both or neither
expect "a CSV in a missing folder exits 1" 1 $P --profile 50,-120 -o "$T/x.svg" --csv "$T/no/x.csv"
has "... naming it" "$T/err" "$T/no/x.csv: cannot create"
expect "a plot in a missing folder with a CSV exits 1" 1 $P --profile 50,-120 -o "$T/no/x.svg" --csv "$T/x.csv"
[ ! -e "$T/x.csv" ] && pass "... and leaves no CSV" || fail "... and leaves no CSV" "$T/x.csv exists"
[ ! -e "$T/x.svg" ] && pass "no output after an error" || fail "no output after an error" "$T/x.svg exists"
left=$(ls "$T" | grep -c '\.tmp\.')
[ "$left" = 0 ] && pass "no temporary left behind" || fail "no temporary left behind" "$(ls "$T" | grep '\.tmp\.')"
# a CSV the final rename could not replace (another user's, in a sticky
# folder): refused before the plot is written (as root: run as nobody)
# (in /tmp itself: make test's TMPDIR is private, and nobody must reach it)
S=$(mktemp -d /tmp/vsv-plot-sticky.XXXXXX)
trap 'rm -rf "$T" "$S"' EXIT
NOBODY="setpriv --reuid=nobody --regid=nogroup --clear-groups"
chmod 1777 "$S" && cp "$T/s.vsv" "$S/in.vsv" && chmod 644 "$S/in.vsv"
echo old > "$S/q.csv"
if [ "$(id -u)" = 0 ] && $NOBODY "$B/vsv-plot" --version > /dev/null 2>&1 && $NOBODY test -r "$S/in.vsv"; then
    expect "a CSV another user owns in a sticky folder exits 1" 1 $NOBODY "$B/vsv-plot" "$S/in.vsv" --profile 50,-120 \
        -o "$S/q.svg" --csv "$S/q.csv"
    has "... saying why" "$T/err" "vsv-plot: $S/q.csv: another user's file in a sticky folder (as /tmp): it cannot be replaced"
    [ ! -e "$S/q.svg" ] && [ "$(cat "$S/q.csv")" = old ] && [ "$(ls "$S" | wc -l)" = 2 ] &&
        pass "... before the plot is written (the CSV kept, nothing left)" ||
        fail "... before the plot is written (the CSV kept, nothing left)" "$(ls "$S")"
    # the name's owner counts: root's dangling symlink is refused, nobody's
    # own symlink to root's file is nobody's to replace
    ln -s "$S/nothere.csv" "$S/dq.csv"
    expect "root's dangling symlink as the CSV exits 1" 1 $NOBODY "$B/vsv-plot" "$S/in.vsv" --profile 50,-120 \
        -o "$S/dq.svg" --csv "$S/dq.csv"
    has "... before the plot" "$T/err" "$S/dq.csv: another user's file in a sticky folder"
    [ ! -e "$S/dq.svg" ] && pass "... and no plot" || fail "... and no plot" "$S/dq.svg written"
    $NOBODY ln -s "$S/q.csv" "$S/mine.csv"
    expect "one's own symlink to another's file is replaced" 0 $NOBODY "$B/vsv-plot" "$S/in.vsv" --profile 50,-120 \
        -o "$S/m.svg" --csv "$S/mine.csv"
    rm -f "$S/mine.csv" "$S/m.svg"
else
    skip "a CSV another user owns in a sticky folder" "not root, or setpriv cannot run the tool as nobody"
fi

# ------------------------------------------------------ every option written up
"$B/vsv-plot" --help > "$T/help"
has "--help names --section" "$T/help" "--section LAT1,LON1:LAT2,LON2"
grep -oE -- '--[a-z][a-z-]*' "$T/help" | sort -u > "$T/opts"
n=0 miss=""
while read -r o; do
    n=$((n + 1))
    m=$(echo "$o" | sed 's/-/\\-/g')
    grep -qF -- "$m" man/vsv-plot.1 || miss="$miss man:$o"
    grep -qF -- "$o" README.md || miss="$miss README:$o"
done < "$T/opts"
[ -z "$miss" ] && [ "$n" -ge 15 ] && pass "man/vsv-plot.1 and README.md name every option of --help ($n)" ||
    fail "man/vsv-plot.1 and README.md name every option of --help" "$n options; missing:$miss"
