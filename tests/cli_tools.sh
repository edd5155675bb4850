#!/bin/sh
# cli_tools.sh — command-line contract of vsv-extract, vsv-pack and vsv-info:
# exit codes (0 ok, 1 data error, 2 misuse), messages "tool: file: what,
# where", the JSON contract, atomic output. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
PY=/usr/bin/python3
CTL=$(data grads/model.ctl)


for tool in vsv-extract vsv-pack vsv-info; do
    expect "$tool --help exits 0" 0 "$B/$tool" --help
    has "$tool --help prints usage on stdout" "$T/out" "Usage: $tool"
    expect "$tool --version exits 0" 0 "$B/$tool" --version
    has "$tool --version names the format" "$T/out" "format 4.0"
    expect "$tool with an unknown option exits 2" 2 "$B/$tool" --no-such-option
    has "$tool misuse points to --help" "$T/err" "Try '$tool --help'"
done
# an option without its argument: getopt's line naming the tool, then the
# pointer to --help, nothing else (an "unknown option" line followed, for
# an option every tool knows)
for ta in "vsv-export --netcdf" "vsv-convert --output" "vsv-render --fps" "vsv-query --cell" "vsv-info --field" \
    "vsv-plot --series" "vsv-extract --times" "vsv-interp --time-res" "vsv-pack --brick"; do
    tool=${ta%% *} opt=${ta#* }
    expect "$tool $opt without its argument exits 2" 2 "$B/$tool" "$opt"
    printf "%s: option '%s' requires an argument\nTry '%s --help'.\n" "$tool" "$opt" "$tool" > "$T/want"
    same "... and says so in two lines naming $tool" "$T/want" "$T/err"
done
# every tool's --help names every format it reads and writes (#17): one row
# a tool, the phrases its help must hold
helpfmt() { # TOOL PHRASE...
    tool=$1
    shift
    if [ ! -x "$B/$tool" ]; then
        echo "SKIP $tool --help names its formats: $tool not built"
        return
    fi
    "$B/$tool" --help > "$T/help" 2>&1
    missing=""
    for w in "$@"; do grep -qF -- "$w" "$T/help" || missing="$missing '$w'"; done
    [ -z "$missing" ] && pass "$tool --help names the formats it reads and writes" ||
        fail "$tool --help names the formats it reads and writes" "missing:$missing"
}
set -- "MM5 v3" REGRID "WRF netCDF" "CAMx UAM-IV" "IOAPI netCDF" CMAQ "CF netCDF" GrADS
helpfmt vsv-extract "$@" OpenVDB "field stream"
helpfmt vsv-convert "$@" OpenVDB ".vsv format"
# (Open MPI's own start-up leaks: suppressed as in cli_mpi.sh)
(
    LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$(pwd)/tests/lsan.supp:fast_unwind_on_malloc=0:print_suppressions=0"
    export LSAN_OPTIONS
    helpfmt vsv-convert-mpi "$@" OpenVDB ".vsv format"
)
helpfmt vsv-info "$@" ".vsv" OpenVDB JSON
helpfmt vsv-interp "Reads and writes the field stream"
helpfmt vsv-pack "Reads a field stream" ".vsv format"
helpfmt vsv-render "Reads .vsv" "transfer-function files" PNG OpenEXR ffmpeg MP4
helpfmt vsv-export "Reads .vsv" OpenVDB "CF netCDF-4"
helpfmt vsv-query "Reads .vsv" CSV JSON
helpfmt vsv-play "Reads .vsv" "transfer-function files" "PNG screenshots"

expect "vsv-pack without -o exits 2" 2 "$B/vsv-pack"
expect "vsv-info without files exits 2" 2 "$B/vsv-info"

# the pipe
expect "vsv-extract --list" 0 "$B/vsv-extract" --list "$CTL"
has "--list shows fields and times" "$T/out" "Geopotential Heights"
"$B/vsv-extract" --vertical even "$CTL" > "$T/stream" 2> "$T/err"
expect "vsv-pack from stdin" 0 sh -c "'$B/vsv-pack' -o '$T/a.vsv' < '$T/stream'"
# a 359-byte stream whose header claims 2 GB (found by fuzz_stream): read
# as it arrives, within 1 GB of address space (not under the sanitizers,
# which reserve more), refused as truncated, not as out of memory
if [ -z "${SANFLAGS:-}" ]; then
    expect "a stream header longer than the stream exits 1" 1 sh -c "ulimit -v 1000000; '$B/vsv-pack' -o '$T/oom.vsv' < tests/corpus/stream/oom-header-length"
    has "it is reported truncated where it ends" "$T/err" "vsv-pack: (stdin): field stream truncated in header at byte 359"
fi
expect "vsv-pack from a file argument" 0 "$B/vsv-pack" -q -o "$T/b.vsv" "$T/stream"
if cmp -s "$T/a.vsv" "$T/b.vsv"; then pass "stdin and file input give identical files"; else fail "stdin and file input give identical files" "differ"; fi
# two streams joined (two commands' output in one pipe): refused, never the
# first alone (the second was dropped without a word)
cat "$T/stream" "$T/stream" > "$T/joined"
for tool in vsv-pack vsv-interp; do
    case $tool in vsv-pack) a="-q -o $T/joined.vsv" ;; *) a="--time-res 1h" ;; esac
    expect "$tool on two joined streams exits 1" 1 "$B/$tool" $a "$T/joined"
    has "... saying where the second begins" "$T/err" "$tool: $T/joined: bytes after the end marker at byte $(wc -c < "$T/stream")"
done
[ ! -e "$T/joined.vsv" ] && pass "vsv-pack writes nothing then" || fail "vsv-pack writes nothing then" "joined.vsv exists"
# a stream named on the command line: a regular file or a pipe; a
# directory or a device is refused naming it (issue 18)
mkdir "$T/adir"
for tool in vsv-pack vsv-interp; do
    case $tool in vsv-pack) a="-q -o $T/dir.vsv" ;; *) a="--time-res 1h" ;; esac
    expect "$tool on a directory exits 1" 1 "$B/$tool" $a "$T/adir"
    has "$tool says what it is" "$T/err" "$tool: $T/adir: a directory, not a regular file or a pipe: refused"
    expect "$tool on a device exits 1" 1 "$B/$tool" $a /dev/null
    has "$tool names the device" "$T/err" "$tool: /dev/null: a character device, not a regular file or a pipe: refused"
done
[ ! -e "$T/dir.vsv" ] && pass "vsv-pack left no output" || fail "vsv-pack left no output" "$T/dir.vsv exists"
rm -f "$T/fifo"
if mkfifo "$T/fifo"; then
    cat "$T/stream" > "$T/fifo" &
    expect "vsv-pack reads a stream from a named pipe" 0 "$B/vsv-pack" -q -o "$T/f.vsv" "$T/fifo"
    wait
    if cmp -s "$T/a.vsv" "$T/f.vsv"; then pass "the pipe gives the same file"; else fail "the pipe gives the same file" "differ"; fi
    cat "$T/stream" > "$T/fifo" &
    expect "vsv-interp reads a stream from a named pipe" 0 sh -c "'$B/vsv-interp' --time-res 1h '$T/fifo' > '$T/interp.stream'"
    wait
fi
expect "vsv-info on the packed sample" 0 "$B/vsv-info" "$T/a.vsv"
# standard output that cannot be written (a full disk): exit 1, saying so
for args in "vsv-info $T/a.vsv" "vsv-info --json $T/a.vsv" "vsv-info -f grid.nx $T/a.vsv" "vsv-extract --list $CTL"; do
    set -- $args
    tool=$1
    shift
    case $1 in -*) what="$tool $1" ;; *) what=$tool ;; esac
    "$B/$tool" "$@" < /dev/null > /dev/full 2> "$T/err"
    rc=$?
    [ "$rc" = 1 ] && pass "$what to a full standard output exits 1" ||
        fail "$what to a full standard output exits 1" "exit $rc; stderr: $(head -c 300 "$T/err")"
    has "... saying so" "$T/err" "$tool: standard output: No space left on device"
done
has "human summary shows the grid" "$T/out" "72 x 46 x 7 cells"
has "human summary shows the species" "$T/out" "Geopotential Heights"
has "human summary shows the compression ratio" "$T/out" "ratio"

# JSON contract
expect "vsv-info --json" 0 "$B/vsv-info" --json "$T/a.vsv"
cp "$T/out" "$T/a.json"
if $PY - "$T/a.json" <<'EOF'
import json, sys, re
d = json.load(open(sys.argv[1]))
need = ["format_version", "grid", "projection", "corners", "times", "species", "bricks", "keyframe_interval", "bytes", "raw_bytes"]
missing = [k for k in need if k not in d]
assert not missing, missing
g = d["grid"]
assert (g["nx"], g["ny"], g["nz"]) == (72, 46, 7) and len(g["origin"]) == 3 and len(g["spacing"]) == 3
assert d["projection"]["name"] == "latlon"
assert len(d["corners"]) == 4 and all("lat" in c and "lon" in c for c in d["corners"])
assert d["corners"][0]["lat"] == -90 and d["corners"][3]["lon"] == 355
assert d["times"][0] == "1987-01-02T00:00:00Z" and len(d["times"]) == 5
assert all(re.match(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$", t) for t in d["times"])
# U and V, and the wind stored from them (a horizontal vector: GrADS has no W)
assert [s["name"] for s in d["species"]] == ["U", "V", "Z", "T", "Q", "wind_east", "wind_north"]
for s in d["species"]:
    for k in ["name", "units", "description", "min", "max", "bits", "scale", "max_abs_error"]:
        assert k in s, k
    assert s["bits"] == 16 and s["scale"] == "linear" and s["max_abs_error"] > 0 and s["min"] <= s["max"]
assert all("colormap" in s["transfer_function"] for s in d["species"])
b = d["bricks"]
assert b["size"] == 32 and b["total"] == 6 * 5 * 7 and 0 < b["stored"] <= b["total"]
assert d["raw_bytes"] == 72 * 46 * 7 * 4 * 5 * 7 and d["bytes"] < d["raw_bytes"]
EOF
then pass "JSON has the contract's keys and values"; else fail "JSON has the contract's keys and values" "see above"; fi
expect "-f grid.nx" 0 "$B/vsv-info" -f grid.nx "$T/a.vsv"
has "-f grid.nx is 72" "$T/out" "72"
expect "-f times.0" 0 "$B/vsv-info" -f times.0 "$T/a.vsv"
has "-f times.0 is the first time" "$T/out" "1987-01-02T00:00:00Z"
expect "-f species[3].name" 0 "$B/vsv-info" -f 'species[3].name' "$T/a.vsv"
has "-f species[3].name is T" "$T/out" "T"
expect "-f of a missing field exits 2" 2 "$B/vsv-info" -f grid.nope "$T/a.vsv"
# a species by its name (issue 32): the same value as by its index
"$B/vsv-info" -f species.3.max_abs_error "$T/a.vsv" > "$T/byindex"
expect "-f species.T.max_abs_error (by name)" 0 "$B/vsv-info" -f species.T.max_abs_error "$T/a.vsv"
same "... is species 3's" "$T/out" "$T/byindex"
expect "-f species.NOPE.units: no such species, exit 2" 2 "$B/vsv-info" -f species.NOPE.units "$T/a.vsv"
has "... saying so" "$T/err" "-f species.NOPE.units: no such field"
expect "vsv-info -f twice" 0 "$B/vsv-info" -f grid.nx -f species.0.name "$T/a.vsv"
[ "$(tr '\n' ' ' < "$T/out")" = "72 U " ] && pass "... a line each, in order" || fail "... a line each, in order" "$(tr '\n' ' ' < "$T/out")"
expect "vsv-info -f a field then a missing one exits 2" 2 "$B/vsv-info" -f grid.nx -f nope "$T/a.vsv"
[ ! -s "$T/out" ] && pass "... printing none" || fail "... printing none" "$(cat "$T/out")"
# numbers at the edges (issue 33): an exaggeration of 1e308 overflowed the
# heap, a cell index of 10^20 was read as -2147483648
expect "vsv-render -x 1e308 exits 2" 2 "$B/vsv-render" "$T/a.vsv" -x 1e308 -o "$T/x.png"
has "... naming the largest" "$T/err" "--exaggerate 1e308: a number above 0 and at most 1000"
expect "vsv-query --cell 99999999999999999999,1 exits 2" 2 "$B/vsv-query" "$T/a.vsv" --cell 99999999999999999999,1
has "... not as a negative index" "$T/err" "--cell 99999999999999999999,1: indices are whole numbers from 0"
# the model's own layer count, not the even grid's (issue 32)
expect "vsv-info of a CMAQ file" 0 "$B/vsv-info" tests/corpus/netcdf/ioapi-cmaq.nc
has "... counts its 3 layers" "$T/out" "6 x 5 columns, 3 layers (sigma-P"
grep -q "converted onto" "$T/out" && fail "... which conversion keeps by default" "$(cat "$T/out")" ||
    pass "... which conversion keeps by default"
expect "vsv-extract --list of a CMAQ file" 0 "$B/vsv-extract" --list tests/corpus/netcdf/ioapi-cmaq.nc
has "... its 3 layers kept" "$T/out" "IOAPI, grid 6 x 5 x 3, 2 times"
expect "vsv-extract --list --vertical even of a CMAQ file" 0 "$B/vsv-extract" --list --vertical even tests/corpus/netcdf/ioapi-cmaq.nc
has "... 3 model layers resampled onto 40 even levels" "$T/out" "grid 6 x 5, 3 model layers (resampled onto 40 even levels)"
expect "vsv-extract --list of the MM5 crop" 0 "$B/vsv-extract" --list samples/mm5/MMOUT_DOMAIN1_CROP
has "... its 15 half-sigma layers" "$T/out" "MM5 v3, grid 39 x 39 x 15, 4 times"
# a --range the values go beyond: converted, with a note for each side
expect "vsv-convert --range narrower than the data" 0 "$B/vsv-convert" samples/mm5/MMOUT_DOMAIN1_CROP --vars CLW,Q \
    --range CLW=0:1e-4,Q=0.001:0.01 -o "$T/clip.vsv"
has "... notes the values above its top" "$T/err" "vsv-convert: note: CLW: values up to 0.000596868 lie above --range's top, 0.0001, and are stored as it"
has "... and those below its bottom" "$T/err" "vsv-convert: note: Q: values down to 1.11111e-14 lie below --range's bottom, 0.001, and are stored as it"
expect "vsv-convert -q --range: no note" 0 "$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP --vars CLW --range CLW=0:1e-4 -o "$T/clip2.vsv"
[ ! -s "$T/err" ] && pass "... standard error empty" || fail "... standard error empty" "$(head -c 200 "$T/err")"
expect "vsv-convert --range wider than the data" 0 "$B/vsv-convert" samples/mm5/MMOUT_DOMAIN1_CROP --vars CLW --range CLW=0:0.01 -o "$T/clip3.vsv"
grep -q "note:" "$T/err" && fail "... no note" "$(grep -m1 note: "$T/err")" || pass "... no note"
"$B/vsv-extract" --vars CLW samples/mm5/MMOUT_DOMAIN1_CROP > "$T/clw.fs"
expect "vsv-pack --range narrower than the data" 0 "$B/vsv-pack" --range CLW=0:1e-4 -o "$T/clip4.vsv" "$T/clw.fs"
has "... notes it too" "$T/err" "vsv-pack: note: CLW: values up to 0.000596868 lie above --range's top, 0.0001"
expect "vsv-info --json --stats" 0 "$B/vsv-info" --json --stats "$T/a.vsv"
if $PY -c "
import json,sys
d=json.load(open('$T/out'))
st=d['stats']
assert len(st)==35 and [r['species'] for r in st[:6]]==['U']*5+['V'] and st[1]['time']==d['times'][1]
t=[r for r in st if r['species']=='T']
assert all(180<r['min']<=r['mean']<=r['max']<320 for r in t) and t[0]['min'] > 197, 'no-data cells must not count'
"; then pass "--stats gives min/max/mean per species then time"; else fail "--stats gives min/max/mean per species then time" "bad stats"; fi

# checks and damage
expect "vsv-info --check on a good file" 0 "$B/vsv-info" --check "$T/a.vsv"
has "--check says ok" "$T/out" "ok"
expect "vsv-info --check on a damaged payload exits 1" 1 "$B/vsv-info" --check tests/golden/bad/payload.vsv
has "--check names chunk, species, brick and offset" "$T/err" "vsv-info: tests/golden/bad/payload.vsv: $(grep '^payload.vsv' tests/golden/bad/EXPECTED | cut -f2)"
# the golden damaged files (tests/golden/bad, the s-* ones with valid
# checksums and invalid structure): exit 1 and exactly the expected message
ngold=0
tab=$(printf '\t')
while IFS=$tab read -r g msg; do
    case $g in '#'* | '') continue ;; esac
    "$B/vsv-info" --check "tests/golden/bad/$g" > /dev/null 2> "$T/gold.err"
    rc=$?
    want="vsv-info: tests/golden/bad/$g: $msg"
    if [ $rc -eq 1 ] && [ "$(cat "$T/gold.err")" = "$want" ]; then
        ngold=$((ngold + 1))
    else
        fail "vsv-info --check tests/golden/bad/$g: exit 1 and '$want'" "exit $rc: $(head -c 300 "$T/gold.err")"
    fi
done < tests/golden/bad/EXPECTED
[ $ngold -ge 32 ] && pass "vsv-info --check: each of $ngold golden damaged files exits 1 with its exact message" ||
    fail "every golden damaged file gives its exact message" "$ngold matched"
expect "vsv-info on a damaged chunk index exits 1 (not fewer bricks)" 1 "$B/vsv-info" tests/golden/bad/index.vsv
has "the damaged index is named, with the count" "$T/err" "vsv-info: tests/golden/bad/index.vsv: chunk 2 (offset 5120): index checksum mismatch (1 of 5 chunks damaged)"
expect "vsv-info on a file whose TOC hides in its metadata exits 1" 1 "$B/vsv-info" tests/golden/bad/s-toc-in-meta.vsv
has "the overlap is named" "$T/err" "overlaps the metadata"
expect "vsv-info on a truncated file exits 1" 1 "$B/vsv-info" tests/golden/bad/truncated.vsv
has "truncation is named" "$T/err" "truncated"
# a .vsv truncated while a tool reads it (cut right after the tool maps it,
# by a preloaded test shim, so without timing): an error naming the file,
# never SIGBUS (issue 18)
mkdir -p "$T/trunc"
for tool in vsv-info vsv-render vsv-export vsv-query; do
    cp "$T/a.vsv" "$T/trunc/a.vsv"
    case $tool in
    vsv-info) args="--check" ;; vsv-render) args="-o $T/trunc/a.png --time 0" ;;
    vsv-export) args="--vdb $T/trunc/a_%d.vdb --time 0" ;; vsv-query) args="--cell 1,1,1" ;;
    esac
    expect "$tool on a .vsv cut while it reads it exits 1" 1 env LD_PRELOAD="$(pwd)/$B/tests/libcutmap.so" \
        VSV_TEST_CUT="$T/trunc/a.vsv" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0" \
        "$B/$tool" "$T/trunc/a.vsv" $args
    has "$tool says it was truncated while reading" "$T/err" "$tool: $T/trunc/a.vsv: truncated while reading"
done
[ ! -e "$T/trunc/a.png" ] && [ ! -e "$T/trunc/a_0.vdb" ] && pass "nothing written from a cut file" || fail "nothing written from a cut file" "$(ls "$T/trunc")"
# model inputs cut the same way while vsv-convert reads them (issue 33:
# SIGBUS in the MM5 reader; zeros read as a CAMx file's values)
for input in samples/mm5/MMOUT_DOMAIN1_CROP tests/data/camx/test.uamiv; do
    cp "$input" "$T/trunc/in"
    expect "vsv-convert on ${input##*/} cut while it reads it exits 1" 1 env LD_PRELOAD="$(pwd)/$B/tests/libcutmap.so" \
        VSV_TEST_CUT="$T/trunc/in" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0" \
        "$B/vsv-convert" "$T/trunc/in" -o "$T/trunc/in.vsv"
    has "vsv-convert says ${input##*/} was truncated while reading" "$T/err" "vsv-convert: $T/trunc/in: truncated while reading (the file shrank after it was opened)"
    [ ! -e "$T/trunc/in.vsv" ] && pass "nothing written from a cut ${input##*/}" || fail "nothing written from a cut ${input##*/}" "$(ls "$T/trunc")"
done
rm -rf "$T/trunc"

# netCDF-4/HDF5 files that crash libhdf5 (one flipped bit in a deflated
# chunk; ncdump dies too): read in a child first, so an error naming the file
expect "a netCDF-4 file that segfaults libhdf5 exits 1" 1 "$B/vsv-info" tests/corpus/netcdf/hdf5-segv.nc
has "the crash is an error naming the file" "$T/err" "vsv-info: tests/corpus/netcdf/hdf5-segv.nc: damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it"
expect "a netCDF-4 file that aborts libhdf5 exits 1" 1 "$B/vsv-info" tests/corpus/netcdf/hdf5-abort.nc
has "the abort is an error naming the file" "$T/err" "vsv-info: tests/corpus/netcdf/hdf5-abort.nc: damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it"
expect "vsv-convert on it exits 1" 1 "$B/vsv-convert" --vertical even tests/corpus/netcdf/hdf5-segv.nc -o "$T/hdf5.vsv"
has "vsv-convert names the input" "$T/err" "vsv-convert: tests/corpus/netcdf/hdf5-segv.nc: damaged netCDF-4/HDF5 file"
[ ! -e "$T/hdf5.vsv" ] && pass "nothing written for it" || fail "nothing written for it" "$T/hdf5.vsv exists"
expect "a WRF file whose XLAT chunk segfaults libhdf5 exits 1" 1 "$B/vsv-info" tests/corpus/netcdf/wrf-xlat-segv.nc
has "the WRF crash is an error naming the file" "$T/err" "vsv-info: tests/corpus/netcdf/wrf-xlat-segv.nc: damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it"
# the check runs in an exec'd helper (vsv-nc-check), never a fork of a tool
# that may have threads (issue 18)
execs_only "the netCDF-4 check is an exec'd helper, not a fork" "$B/vsv-info" tests/corpus/netcdf/hdf5-segv.nc
mkdir -p "$T/nohelper" "$T/fakehelper"
expect "no helper program: exit 1" 1 env VSV_HELPER_DIR="$T/nohelper" "$B/vsv-info" tests/corpus/netcdf/hdf5-segv.nc
has "the missing helper is named" "$T/err" "vsv-info: tests/corpus/netcdf/hdf5-segv.nc: cannot check the netCDF-4/HDF5 file: cannot find the helper program vsv-nc-check"
printf '#!/bin/sh\nexit 7\n' > "$T/fakehelper/vsv-nc-check"
chmod +x "$T/fakehelper/vsv-nc-check"
expect "a helper failing without a word: exit 1" 1 env VSV_HELPER_DIR="$T/fakehelper" "$B/vsv-info" tests/corpus/netcdf/hdf5-segv.nc
has "its status is reported" "$T/err" "the HDF5 library failed reading it (its checker exited with status 7)"

# a classic netCDF (CMAQ) file with one damaged byte: a global attribute's
# count made 1.8e9 doubles. libnetcdf allocated and copied 14 GB through
# its header buffer for 55 s before failing; the header is walked first now
C=tests/corpus/netcdf/cmaq-attr-count.nc
expect "a CMAQ file whose attribute count overruns the file exits 1" 1 "$B/vsv-convert" --vertical even "$C" -o "$T/cmaq.vsv"
has "the attribute, its offset and the file size are named" "$T/err" "vsv-convert: $C: netCDF header: attribute \"P_BET\" of the file at offset 328 declares 1811939329 values of 8 bytes, past the end of the file (2412 bytes)"
[ ! -e "$T/cmaq.vsv" ] && pass "no output is left" || fail "no output is left" "$T/cmaq.vsv exists"
expect "vsv-info on it exits 1" 1 "$B/vsv-info" "$C"
has "vsv-info names it" "$T/err" "vsv-info: $C: netCDF header: attribute \"P_BET\""
# a WRF file whose record count (16.7 million) overruns the file: refused
# from the header, before libnetcdf reads Times record by record (found by
# fuzz_netcdf as a 20 s input; tests/FUZZING.md)
C=tests/corpus/netcdf/records-past-end.nc
expect "a netCDF file whose record count overruns the file exits 1" 1 "$B/vsv-info" "$C"
has "the record count, the record size and the file size are named" "$T/err" "vsv-info: $C: netCDF header: the file declares 16712706 records of at least 5732 bytes from offset 6288, past the end of the file (17752 bytes)"
# found by the fuzz campaign: the record count 0xFFFFFFFF (the format's
# "streaming" value), taken by libnetcdf as 4294967295 records (81 GB of
# WRF times asked for; "vsv-info: " and no message)
C=tests/corpus/netcdf/records-streaming.nc
expect "a netCDF file whose streaming record count overruns the file exits 1" 1 "$B/vsv-info" "$C"
has "the streaming count is named" "$T/err" "vsv-info: $C: netCDF header: the file declares 4294967295 records of at least 5732 bytes from offset 6288, past the end of the file (17177 bytes)"
# a classic netCDF file cut inside its data (its last record): libnetcdf
# reads the missing bytes as zeros without an error, so a CMAQ file cut
# 2 bytes short converted with exit 0 and zeros in its last step; the
# header's variables are held to the file's size (CDF-1 and CDF-2)
head -c 2410 tests/corpus/netcdf/ioapi-cmaq.nc > "$T/cut-cmaq.nc"
expect "a CMAQ file cut inside its last record exits 1" 1 "$B/vsv-convert" "$T/cut-cmaq.nc" -o "$T/cut-cmaq.vsv"
has "the cut, its record and the sizes are named" "$T/err" "vsv-convert: $T/cut-cmaq.nc: netCDF: the file is cut short: record 2 of 2 (variable \"PM25\") ends at byte 2412, the file has 2410"
[ ! -e "$T/cut-cmaq.vsv" ] && pass "no output is left from the cut file" || fail "no output is left from the cut file" "$T/cut-cmaq.vsv exists"
head -c $(($(wc -c < tests/corpus/netcdf/wrf-crop.nc) - 1000)) tests/corpus/netcdf/wrf-crop.nc > "$T/cut-wrf.nc"
expect "a WRF file (64-bit offsets) cut 1000 bytes short exits 1" 1 "$B/vsv-info" "$T/cut-wrf.nc"
has "vsv-info says it is cut short" "$T/err" "vsv-info: $T/cut-wrf.nc: netCDF: the file is cut short: record"
head -c 25596 tests/corpus/netcdf/katrina-crop.nc > "$T/cut-fixed.nc" # (of 26596: no records, fixed sizes)
expect "a WRF file without records cut 1000 bytes short exits 1" 1 "$B/vsv-info" "$T/cut-fixed.nc"
has "the last variable and the sizes are named" "$T/err" "vsv-info: $T/cut-fixed.nc: netCDF: the file is cut short: variable \"XLONG_V\"'s data ends at byte 26596, the file has 25596"
# the sizes are the values' own, from the dimensions: one float record
# variable cut by a byte is short; a byte variable's padding is no data
if command -v ncgen > /dev/null; then
    printf 'netcdf a { dimensions: t = UNLIMITED ; x = 3 ; variables: float v(t, x) ; data: v = %s ; }\n' \
        "$(seq -s , 1 21)" > "$T/rec1.cdl"
    ncgen -k classic -o "$T/rec1.nc" "$T/rec1.cdl"
    head -c $(($(wc -c < "$T/rec1.nc") - 1)) "$T/rec1.nc" > "$T/rec1-cut.nc"
    expect "one float record variable cut by a byte exits 1" 1 "$B/vsv-info" "$T/rec1-cut.nc"
    has "... cut short, its last record named" "$T/err" "netCDF: the file is cut short: record 7 of 7 (variable \"v\") ends at byte 180, the file has 179"
    printf 'netcdf c { dimensions: t = UNLIMITED ; x = 3 ; variables: float f(t) ; byte b(t, x) ; data: f = 1,2,3 ; b = 1,2,3,4,5,6,7,8,9 ; }\n' > "$T/pad.cdl"
    ncgen -k 64-bit-offset -o "$T/pad.nc" "$T/pad.cdl"
    head -c $(($(wc -c < "$T/pad.nc") - 1)) "$T/pad.nc" > "$T/pad-1.nc"
    "$B/vsv-info" "$T/pad-1.nc" > /dev/null 2> "$T/err"
    if grep -q "cut short" "$T/err"; then fail "a byte variable's last padding byte cut is no data lost" "$(cat "$T/err")"
    else pass "a byte variable's last padding byte cut is no data lost"; fi
    head -c $(($(wc -c < "$T/pad.nc") - 2)) "$T/pad.nc" > "$T/pad-2.nc"
    expect "... but a byte of its values is" 1 "$B/vsv-info" "$T/pad-2.nc"
    has "... cut short" "$T/err" "netCDF: the file is cut short: record 3 of 3 (variable \"b\")"
else
    echo "SKIP netCDF cut by a byte: no ncgen (netcdf-bin)"
fi
# found by the fuzz campaign: a variable of type 12 (NC_STRING) in a
# 64-bit-offset file: libnetcdf divided by its 0-byte value size (SIGFPE)
C=tests/corpus/netcdf/var-type-string.nc
expect "a variable of a type the format lacks exits 1" 1 "$B/vsv-info" "$C"
has "the variable, its offset and its type are named" "$T/err" "vsv-info: $C: netCDF header: variable \"T\" at offset 248 has an unknown type 12"
# found by the fuzz campaign: an IOAPI file whose time-step count is
# 4294967295 (32 GB of times allocated: "out of memory" with an empty
# message) and a GrADS descriptor with two VARS lists (the first leaked)
C=tests/corpus/netcdf/ioapi-tstep-huge.nc
expect "an IOAPI file with more time steps than it holds exits 1" 1 "$B/vsv-info" "$C"
# (its TSTEP is the streaming record count: the header walk refuses it first)
has "the count and the file size are named" "$T/err" "vsv-info: $C: netCDF header: the file declares 4294967295 records of at least 736 bytes from offset 940, past the end of the file (1989 bytes)"
C=tests/corpus/grads/leak-vars-twice
expect "a GrADS descriptor with two VARS lists exits 1" 1 "$B/vsv-info" "$C"
has "the second is named" "$T/err" "vsv-info: $C: line 10: a second VARS"

# an output that is an input (same path, hard link, symlink) is refused
# before anything is written; the input stays intact (issue 18)
cp samples/mm5/MMOUT_DOMAIN1_CROP "$T/in.mm5"
ln "$T/in.mm5" "$T/in-hard.vsv"
ln -s "$T/in.mm5" "$T/in-sym.vsv"
for o in in.mm5 in-hard.vsv in-sym.vsv; do
    expect "vsv-convert refuses -o $o (the input)" 2 "$B/vsv-convert" --vertical even "$T/in.mm5" -o "$T/$o"
    has "the refusal names output and input" "$T/err" "vsv-convert: output $T/$o is the input $T/in.mm5 (the same file"
done
same "the model input is intact" samples/mm5/MMOUT_DOMAIN1_CROP "$T/in.mm5"
# an output that exists and is not a regular file would be replaced by the
# final rename (as root, -o /dev/null replaced the device): refused first
mkdir "$T/out-dir.vsv"
mkfifo "$T/out-fifo.vsv" "$T/out-fifo.png" "$T/out-fifo.nc"
expect "vsv-convert refuses -o an existing directory" 2 "$B/vsv-convert" --vertical even "$T/in.mm5" -o "$T/out-dir.vsv"
has "and says what it is" "$T/err" "vsv-convert: output $T/out-dir.vsv is a directory, not a regular file: refusing to replace it"
expect "vsv-convert refuses -o a FIFO" 2 "$B/vsv-convert" --vertical even "$T/in.mm5" -o "$T/out-fifo.vsv"
expect "vsv-render refuses -o a FIFO" 2 "$B/vsv-render" "$T/a.vsv" -o "$T/out-fifo.png" --time 0
expect "vsv-export refuses --netcdf a FIFO" 2 "$B/vsv-export" "$T/a.vsv" --netcdf "$T/out-fifo.nc"
has "naming it" "$T/err" "vsv-export: output $T/out-fifo.nc is a FIFO, not a regular file: refusing to replace it"
[ -d "$T/out-dir.vsv" ] && [ -p "$T/out-fifo.vsv" ] && [ -p "$T/out-fifo.png" ] && [ -p "$T/out-fifo.nc" ] &&
    pass "the directory and the FIFOs are still there" || fail "the directory and the FIFOs are still there" "one was replaced"
# frames finer than the model's stream through two passes with no spool:
# the bundled crop every 10 s is 1,081 steps, 1.3 GB of raw floats, which
# the writer used to keep beside the output (and 1 s on the MM5 run, 254 GB,
# was refused); now a few steps in memory, the same bytes as the pipeline
if [ -x /usr/bin/time ]; then
    expect "vsv-convert --time-res 10s of the crop streams" 0 /usr/bin/time -f "maxrss %M" \
        "$B/vsv-convert" --vertical even -q --time-res 10s samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/c10s.vsv"
    rss=$(sed -n 's/^maxrss //p' "$T/err")
    if [ -n "${SANFLAGS:-}" ]; then
        pass "... its memory: not measured under the sanitizers (their shadow memory)"
    elif [ -n "$rss" ] && [ "$rss" -lt 150000 ]; then
        pass "... within 150 MB of memory ($rss kB; raw steps 1.3 GB)"
    else
        fail "... within 150 MB of memory" "$rss kB"
    fi
fi
"$B/vsv-info" "$T/c10s.vsv" > "$T/out"
has "... 1081 steps every 10 s" "$T/out" "1081 steps, 1995-10-24T00:00:00Z .. 1995-10-24T03:00:00Z, every 10 s"
"$B/vsv-convert" --vertical even -q --time-res 5m --vars CLW,Q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/c5m.vsv"
"$B/vsv-extract" --vertical even --vars CLW,Q samples/mm5/MMOUT_DOMAIN1_CROP | "$B/vsv-interp" --time-res 5m | "$B/vsv-pack" -q -o "$T/p5m.vsv"
same "streamed (5m from hourly) is byte for byte extract | interp | pack (spooled)" "$T/c5m.vsv" "$T/p5m.vsv"
# a conversion at the model's own steps (or coarser) still spools them, and
# is refused before it reads when they cannot fit: shown on a 2 MB tmpfs
# (mounting needs root; skipped with a note where it is not allowed)
mkdir -p "$T/small"
if mount -t tmpfs -o size=2m tmpfs "$T/small" 2> /dev/null; then
    expect "vsv-convert onto 2 MB: refused, the spool does not fit" 1 \
        "$B/vsv-convert" --vertical even samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/small/x.vsv"
    has "saying how much it needs and has" "$T/err" "4 steps of 1.9 MB are kept beside it until they are encoded: 7.8 MB, and its file system has 2.1 MB free"
    [ -z "$(ls "$T/small")" ] && pass "nothing is left beside it" || fail "nothing is left beside it" "$(ls "$T/small")"
    umount "$T/small"
else
    echo "note: the spool-space refusal not tested (mounting a tmpfs is not allowed here)"
fi
if mknod "$T/null" c 1 3 2> /dev/null; then
    expect "vsv-convert refuses -o a character device (as root)" 2 "$B/vsv-convert" --vertical even "$T/in.mm5" -o "$T/null"
    [ -c "$T/null" ] && pass "the device is still a device" || fail "the device is still a device" "replaced"
fi
cp "$T/a.vsv" "$T/keep.vsv"
ln "$T/a.vsv" "$T/a-hard.png"
expect "vsv-render refuses -o a hard link of its input" 2 "$B/vsv-render" "$T/a.vsv" -o "$T/a-hard.png" --time 0
has "vsv-render names both" "$T/err" "vsv-render: output $T/a-hard.png is the input $T/a.vsv (the same file, through a link)"
expect "vsv-render refuses --movie onto its input" 2 "$B/vsv-render" "$T/a.vsv" --movie "$T/a.vsv"
ln "$T/a.vsv" "$T/a-hard.vdb"
expect "vsv-export refuses --vdb onto its input" 2 "$B/vsv-export" "$T/a.vsv" --vdb "$T/a-hard.vdb" --time 0
has "vsv-export names both" "$T/err" "vsv-export: output $T/a-hard.vdb is the input $T/a.vsv"
same "the .vsv input is intact" "$T/keep.vsv" "$T/a.vsv"
rm -f "$T/a-hard.png" "$T/a-hard.vdb"

# inputs that are not regular files: refused at open, never a hang (issue 18)
mkfifo "$T/fifo.vsv"
for tool in vsv-info vsv-convert vsv-render vsv-export; do
    case $tool in
    vsv-info) args="$T/fifo.vsv" ;; vsv-convert) args="$T/fifo.vsv -o $T/fifo-out.vsv" ;;
    vsv-render) args="$T/fifo.vsv -o $T/fifo-out.png" ;; vsv-export) args="$T/fifo.vsv --vdb $T/fifo-out%d.vdb" ;;
    esac
    CMD_TIMEOUT=20 expect "$tool refuses a FIFO input (no hang)" 1 "$B/$tool" $args
    has "$tool names the FIFO" "$T/err" "$tool: $T/fifo.vsv: a FIFO, not a regular file: refused"
done
expect "vsv-info refuses a character device" 1 "$B/vsv-info" /dev/zero
has "the device is named" "$T/err" "vsv-info: /dev/zero: a character device, not a regular file: refused"
mkdir -p "$T/adir.vsv"
expect "vsv-info refuses a directory" 1 "$B/vsv-info" "$T/adir.vsv"
has "the directory is named" "$T/err" "a directory, not a regular file: refused"
echo "just some text" > "$T/text.vsv"
expect "vsv-info on a text file exits 1" 1 "$B/vsv-info" "$T/text.vsv"
has "text file is not a .vsv file" "$T/err" "vsv-info: $T/text.vsv: not a .vsv file"
has "... nor a model file" "$T/err" "vsv-info: $T/text.vsv: not a .vsv file; not an MM5 v3 file, nor another format Vesuvius reads"
expect "vsv-convert given a .vsv file exits 1" 1 "$B/vsv-convert" -q "$T/a.vsv" -o "$T/again.vsv"
has "... saying it is a .vsv already" "$T/err" "vsv-convert: $T/a.vsv: a .vsv file already, not model output"
[ ! -e "$T/again.vsv" ] && pass "... writing nothing" || fail "... writing nothing" "again.vsv exists"
expect "vsv-info -f of a field a model file lacks exits 2" 2 "$B/vsv-info" -f nope samples/mm5/MMOUT_DOMAIN1_CROP
has "... saying so" "$T/err" "vsv-info: -f nope: no such field"
expect "vsv-info -f on a model file: grid, times and fields" 0 "$B/vsv-info" -f grid.nz -f times.3 -f fields.4.name \
    -f fields.4.volume -f projection.name samples/mm5/MMOUT_DOMAIN1_CROP
printf "15\n1995-10-24T03:00:00Z\nCLW\ntrue\nlcc\n" > "$T/want"
same "... each its value" "$T/out" "$T/want"
if command -v ncgen > /dev/null; then
    printf 'netcdf other { dimensions: x = 2 ; variables: float a(x) ; data: a = 1, 2 ; }\n' > "$T/other.cdl"
    ncgen -o "$T/other.nc" "$T/other.cdl"
    expect "vsv-info on a netCDF file of no known kind exits 1" 1 "$B/vsv-info" "$T/other.nc"
    has "... saying what it is not" "$T/err" "other.nc: not a .vsv file; a netCDF file that is none of WRF output"
fi
expect "vsv-info on a missing file exits 1" 1 "$B/vsv-info" "$T/missing.vsv"

# bad streams leave nothing behind
head -c 300000 "$T/stream" > "$T/cut"
expect "vsv-pack on a truncated stream exits 1" 1 "$B/vsv-pack" -o "$T/cut.vsv" "$T/cut"
has "truncated stream is named with its offset" "$T/err" "truncated in frame data at byte"
if [ ! -e "$T/cut.vsv" ] && ! ls "$T" | grep -q -e '\.tmp\.' -e '\.spool\.'; then pass "failed pack leaves no output and no temporaries"; else fail "failed pack leaves no output and no temporaries" "$(ls "$T")"; fi
expect "vsv-pack on a .vsv instead of a stream exits 1" 1 "$B/vsv-pack" -o "$T/x.vsv" "$T/a.vsv"
has "wrong input kind is named" "$T/err" "not a field stream"
expect "vsv-pack --bits 12 exits 2" 2 "$B/vsv-pack" --bits 12 -o "$T/x.vsv" "$T/stream"
for d in 0 -1 30.5 nan; do
    expect "vsv-pack --log-decades $d exits 2" 2 "$B/vsv-pack" --scale log --log-decades $d -o "$T/x.vsv" "$T/stream"
done
has "... naming the range, (0, 30]" "$T/err" "--log-decades nan: must be a number in (0, 30]"
expect "vsv-pack with an unknown species exits 2" 2 "$B/vsv-pack" --scale NOPE=log -o "$T/x.vsv" "$T/stream"
has "unknown species is named" "$T/err" "no species named 'NOPE'"
expect "vsv-pack per-species options" 0 "$B/vsv-pack" -q --bits 8 --scale Q=log --brick 16 --keyframe 2 --codec zstd:9 -o "$T/c.vsv" "$T/stream"
"$B/vsv-info" -f species.4.scale "$T/c.vsv" > "$T/out"
has "per-species scale recorded" "$T/out" "log"
"$B/vsv-info" -f keyframe_interval "$T/c.vsv" > "$T/out"
has "keyframe interval recorded" "$T/out" "2"
expect "8-bit file checks" 0 "$B/vsv-info" --check "$T/c.vsv"

# extract options
expect "vsv-extract --vars with an unknown name exits 1" 1 "$B/vsv-extract" --vertical even --vars T,NOPE "$CTL"
has "unknown variable lists the available ones" "$T/err" "available: PS, U, V, Z, T, Q, TS, P"
"$B/vsv-extract" --vertical even --vars T --times 1:2 "$CTL" | "$B/vsv-pack" -q -o "$T/d.vsv"
"$B/vsv-info" -f times "$T/d.vsv" > "$T/out"
has "--times 1:2 selects two steps" "$T/out" '["1987-01-03T00:00:00Z", "1987-01-04T00:00:00Z"]'
"$B/vsv-extract" --vertical even --vars T --times 1987-01-05: "$CTL" | "$B/vsv-pack" -q -o "$T/e.vsv"
"$B/vsv-info" -f times "$T/e.vsv" > "$T/out"
has "--times with an ISO start" "$T/out" '["1987-01-05T00:00:00Z", "1987-01-06T00:00:00Z"]'
expect "vsv-extract on a non-model file exits 1" 1 "$B/vsv-extract" --vertical even "$T/text.vsv"
has "non-model file is named" "$T/err" "not an MM5 v3 file"
exit 0
