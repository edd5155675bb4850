#!/bin/sh
# cli_interop.sh — vsv-export (OpenVDB out) and vsv-extract on .vdb sequences
# (OpenVDB in): options, errors, and the tools on the real MM5 sample.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-interop.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
"$B/vsv-convert" --vertical even -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/crop.vsv"
expect "vsv-export --help exits 0" 0 "$B/vsv-export" --help
has "the help names --vdb" "$T/out" "--vdb OUT"
expect "vsv-export without --vdb exits 2" 2 "$B/vsv-export" "$T/crop.vsv"
expect "several steps without %04d exit 2" 2 "$B/vsv-export" "$T/crop.vsv" --vdb "$T/one.vdb"
expect "an unknown species exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --vdb "$T/x%d.vdb" --species NOPE
expect "a list ending in a comma exits 2" 2 "$B/vsv-export" "$T/crop.vsv" --vdb "$T/x%d.vdb" --species CLW,
has "and says the name is empty" "$T/err" "vsv-export: --species CLW,: an empty species name"
expect "a damaged .vsv exits 1" 1 "$B/vsv-export" tests/golden/bad/payload.vsv --vdb "$T/bad%d.vdb"
has "naming the damage" "$T/err" "checksum"
expect "every step of two species" 0 "$B/vsv-export" -q "$T/crop.vsv" --vdb "$T/s_%04d.vdb" --species CLW,SNOW
n=$(ls "$T"/s_*.vdb | wc -l)
[ "$n" = 4 ] && pass "one .vdb per step (4)" || fail "one .vdb per step (4)" "$n"
timeout 120 vdb_print "$T/s_0003.vdb" < /dev/null > "$T/print" 2>&1
has "vdb_print reads it: the CLW grid" "$T/print" "CLW"
has "and the SNOW grid" "$T/print" "SNOW"
timeout 120 vdb_print -m "$T/s_0003.vdb" < /dev/null > "$T/meta" 2>&1
has "model time as ISO 8601 metadata" "$T/meta" "1995-10-24T03:00:00Z"
has "the projection as metadata" "$T/meta" "lcc lat0=38"
expect "one step with --time" 0 "$B/vsv-export" -q "$T/crop.vsv" --vdb "$T/t1.vdb" --time 1995-10-24T01:00:00Z
# a step where CLW is 0 everywhere (nothing active: OpenVDB keeps an empty
# tree) reads alone, on the whole grid vsv-export records (it was refused:
# "no float grid with active voxels in the sequence")
expect "an all-zero step exported alone" 0 "$B/vsv-export" -q "$T/crop.vsv" --vdb "$T/zero.vdb" --time 0 --species CLW
expect "... converts back" 0 "$B/vsv-convert" -q "$T/zero.vdb" -o "$T/zero.vsv"
"$B/vsv-info" -f grid.nx -f grid.ny -f grid.nz "$T/crop.vsv" > "$T/dims.want"
"$B/vsv-info" -f grid.nx -f grid.ny -f grid.nz "$T/zero.vsv" > "$T/dims.got"
same "... on the model's whole grid" "$T/dims.want" "$T/dims.got"
expect "vsv-extract --list on a .vdb" 0 "$B/vsv-extract" --list "$T/t1.vdb"
has "lists its grids" "$T/out" "CLW"
has "at its time" "$T/out" "1995-10-24T01:00:00Z"
timeout 120 "$B/vsv-extract" --vertical even "$T"/s_*.vdb | timeout 120 "$B/vsv-pack" -q -o "$T/back.vsv"
expect "a .vdb sequence packs back into a .vsv" 0 "$B/vsv-info" "$T/back.vsv"
has "with the four steps" "$T/out" "4 steps, 1995-10-24T00:00:00Z"
# files with their own times: --time-step would replace them, so it is refused
expect "--time-step on .vdb files with times exits 1" 1 "$B/vsv-extract" --vertical even --time-step 10m --time-start 2020-06-01T12:00:00Z "$T"/s_*.vdb
has "--time-step refusal names the file and its time" "$T/err" "s_0000.vdb: has its own time 1995-10-24T00:00:00Z (\"time\" metadata); --time-step would replace it"
expect "--time-step without --time-start exits 2" 2 "$B/vsv-extract" --vertical even --time-step 10m "$T"/s_*.vdb
has "no silent start in 2000" "$T/err" "--time-step needs --time-start"
head -c 3000 "$T/s_0001.vdb" > "$T/cut.vdb"
expect "a truncated .vdb exits 1" 1 "$B/vsv-extract" --vertical even "$T/cut.vdb"
# (OpenVDB's reading of a cut stream depends on memory it never filled: it
# throws, or under the sanitizers' allocator may loop until the time limit)
grep -qE "cut.vdb: (not a readable OpenVDB file|damaged OpenVDB file \(reading it took over)" "$T/err" &&
    pass "with a clear message" || fail "with a clear message" "$(head -c 300 "$T/err")"
expect "a rotated or foreign file is not taken for OpenVDB" 1 "$B/vsv-extract" --vertical even "$T/crop.vsv"
expect "vsv-extract --list describes a .vdb" 0 "$B/vsv-extract" --list "$T/t1.vdb"
has "its grids" "$T/out" "CLW"
has "and its time" "$T/out" "times: 1995-10-24T01:00:00Z"
expect "vsv-info describes a .vdb (it said to ask vsv-extract, exit 1)" 0 "$B/vsv-info" "$T/t1.vdb"
has "... its grids" "$T/out" "CLW"
has "... and its time" "$T/out" "time        1995-10-24T01:00:00Z"
expect "vsv-info --json on a .vdb" 0 "$B/vsv-info" --json "$T/t1.vdb"
has "... names the format" "$T/out" '"format": "OpenVDB"'
# damaged .vdb files: OpenVDB has no checksums and can crash on them; the
# reading runs isolated, so every one is exit 0 (harmless damage) or 1 with a
# message, never a crash
timeout 120 "$B/vsv-export" -q "$T/crop.vsv" --vdb "$T/d.vdb" --time 3 --species CLW,ICE,SNOW
size=$(stat -c %s "$T/d.vdb")
bad=0
i=1
while [ $i -le 40 ]; do
    off=$(( (i * 7919 * 31) % size ))
    cp "$T/d.vdb" "$T/x.vdb"
    printf '\377' | dd of="$T/x.vdb" bs=1 seek=$off conv=notrunc 2> /dev/null
    timeout 120 "$B/vsv-extract" --vertical even "$T/x.vdb" < /dev/null > /dev/null 2> "$T/xerr"
    rc=$?
    if [ $rc -gt 1 ] || { [ $rc = 1 ] && ! grep -q "x.vdb" "$T/xerr"; }; then bad=$((bad + 1)); echo "byte $off: exit $rc: $(head -c 200 "$T/xerr")"; fi
    i=$((i + 1))
done
[ $bad = 0 ] && pass "40 damaged .vdb files: never a crash, errors name the file" || fail "40 damaged .vdb files: never a crash, errors name the file" "$bad"
# the reading runs in an exec'd helper (vsv-vdb-reader), never a fork of a
# process with threads (log4cplus starts four when OpenVDB loads; issue 18)
execs_only "reading .vdb files: exec'd helpers only, no fork" "$B/vsv-extract" --vertical even "$T/d.vdb"
mkdir -p "$T/fakehelper"
printf '#!/bin/sh\nkill -SEGV $$\n' > "$T/fakehelper/vsv-vdb-reader"
chmod +x "$T/fakehelper/vsv-vdb-reader"
expect "a reader that crashes: exit 1" 1 env VSV_HELPER_DIR="$T/fakehelper" "$B/vsv-extract" --vertical even "$T/d.vdb"
has "a crash is a damaged-file error naming it" "$T/err" "d.vdb: damaged OpenVDB file (the OpenVDB library failed reading it, signal 11)"
