#!/bin/sh
# cli_mpi.sh — vsv-convert-mpi under mpirun: byte for byte vsv-convert's file
# on 1 to 4 ranks, for the MM5 run cut into its periods (the bundled crop,
# and the whole domain from ../shared) and for a WRF run cut by time; a
# damaged input read by one rank stops every rank with one message naming
# the rank and the file, exit 1, nothing left behind; a run interrupted by a
# signal leaves no temporary; help and misuse.
# Skipped, with a note, where vsv-convert-mpi is not built (no Open MPI).
B=${B:-build}
SHARED=${SHARED:-../shared}
if [ ! -x "$B/vsv-convert-mpi" ] || ! command -v mpirun > /dev/null 2>&1; then
    echo "  (skipped: vsv-convert-mpi is not built; apt-get install libopenmpi-dev openmpi-bin)"
    exit 0
fi
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-mpi.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
mpi_env
# the ranks' spool files go here, so "nothing left behind" can be seen
mkdir "$T/spool"
export TMPDIR="$T/spool"
MPI="$B/vsv-convert-mpi"

expect "vsv-convert-mpi --help exits 0" 0 $MPIRUN -np 2 "$MPI" --help
has "vsv-convert-mpi --help prints usage" "$T/out" "Usage: mpirun -np N vsv-convert-mpi"
n=$(grep -c "^Usage:" "$T/out")
[ "$n" = 1 ] && pass "--help printed once on 2 ranks" || fail "--help printed once on 2 ranks" "$n times"
has "--help lists vsv-convert's options" "$T/out" "--time-res D"
has "--help lists --stats" "$T/out" "--stats"
expect "vsv-convert-mpi --version exits 0" 0 $MPIRUN -np 2 "$MPI" --version
has "--version names the tool" "$T/out" "vsv-convert-mpi (Vesuvius"
expect "a bad option exits 2" 2 $MPIRUN -np 2 "$MPI" --bogus -o "$T/x.vsv" samples/mm5/MMOUT_DOMAIN1_CROP
n=$(grep -c "unrecognized option" "$T/err")
[ "$n" = 1 ] && pass "the usage error is said once" || fail "the usage error is said once" "$n times: $(cat "$T/err")"
cp samples/mm5/MMOUT_DOMAIN1_CROP "$T/in.mm5"
expect "an output that is an input exits 2" 2 $MPIRUN -np 2 "$MPI" "$T/in.mm5" -o "$T/in.mm5"
same "... and the input is intact" samples/mm5/MMOUT_DOMAIN1_CROP "$T/in.mm5"
expect "vsv-convert has no --stats" 2 "$B/vsv-convert" --stats -o "$T/x.vsv" samples/mm5/MMOUT_DOMAIN1_CROP

# ranks against vsv-convert: NAME REF "NP..." ARGS...
identical() {
    what=$1 ref=$2 nps=$3
    shift 3
    "$B/vsv-convert" -q "$@" -o "$T/$ref.vsv"
    for np in $nps; do
        rm -f "$T/mpi.vsv"
        expect "$what: np $np converts" 0 $MPIRUN -np $np "$MPI" -q "$@" -o "$T/mpi.vsv"
        same "$what: np $np is byte-identical to vsv-convert" "$T/$ref.vsv" "$T/mpi.vsv"
    done
}

# the bundled MM5 crop cut into its four periods: 19 frames of 10 min
/usr/bin/python3 tests/mm5_split.py samples/mm5/MMOUT_DOMAIN1_CROP "$T/crop" > "$T/n"
has "the crop is cut into 4 one-period files" "$T/n" "4"
identical "MM5 crop, 4 files, --time-res 10m" crop "1 2 3 4" --time-res 10m "$T"/crop_0?
# a grid of 25 min: the model's hours fall between its steps, so a rank's
# share must keep to the grid of the run's first time, not its own first frame
identical "MM5 crop, 4 files, --time-res 25m" crop25 "2 3" --time-res 25m "$T"/crop_0?
identical "MM5 crop, --times 00:40..02:20 of the 25m steps" crop25w "2 3" --time-res 25m \
    --times 1995-10-24T00:40Z:1995-10-24T02:20Z "$T"/crop_0?
identical "MM5 crop, 4 files, --interp advect" advect "2 3" --time-res 20m --interp advect "$T"/crop_0?
identical "MM5 crop, keyframe 3, 8 bits, log CLW, native levels" crop2 "2 3" --time-res 20m --keyframe 3 --bits 8 \
    --scale CLW=log --vertical native "$T"/crop_0?

# --stats: one row a rank
expect "--stats on 3 ranks" 0 $MPIRUN -np 3 "$MPI" -q --stats --time-res 10m "$T"/crop_0? -o "$T/mpi.vsv"
n=$(grep -cE "^ +[0-9]+ +[0-9]+ +[0-9.]+ +[0-9.]+ +[0-9.]+$" "$T/out")
[ "$n" = 3 ] && pass "--stats has a row for each of 3 ranks" || fail "--stats has a row for each of 3 ranks" "$(cat "$T/out")"
has "--stats sums up the steps" "$T/out" "19 steps on 3 ranks"
# a --range the values go beyond: the note once, from rank 0 (as vsv-convert's)
expect "--range narrower than the data on 2 ranks" 0 $MPIRUN -np 2 "$MPI" --vars CLW --range CLW=0:1e-4 "$T"/crop_0? -o "$T/clip.vsv"
n=$(grep -c "note: CLW: values up to 0.000596868 lie above --range's top, 0.0001, and are stored as it" "$T/err")
[ "$n" = 1 ] && pass "... noted once" || fail "... noted once" "$n times: $(head -c 300 "$T/err")"

# the real MM5 run (143x208, 4 periods of 60 min) cut into its periods
MMOUT=$(data mm5/run1/MMOUT_DOMAIN1)
if ! absent "MM5 run, 4 files" mm5/run1/MMOUT_DOMAIN1; then
    /usr/bin/python3 tests/mm5_split.py "$MMOUT" "$T/mm" > /dev/null
    identical "MM5 run, 4 files, 30-min frames, CLW and Q" mm "1 2 3 4" --time-res 30m --vars CLW,Q --nz 20 \
        "$T"/mm_0?
    rm -f "$T"/mm_0?
fi

# a multi-file WRF run: the 4 times of a real WRF file, one file each
WRF=$(data wrf/wrf_d01_allvars_cropped.nc)
if ! absent "WRF run, 4 files" wrf/wrf_d01_allvars_cropped.nc; then
    for i in 0 1 2 3; do "$B/tests/ncsplit" "$WRF" "$T/wrf_$i.nc" $i 1; done
    identical "WRF run, 4 files, 30-min frames" wrf "1 2 3 4" --time-res 30m "$T"/wrf_?.nc
fi

# a damaged input that only the last rank reads: the crop cut into two
# files of two periods; in the second file's second period CLW is one
# column short (a consistent record that vsv_run_open accepts, refused
# when that period is read)
/usr/bin/python3 tests/mm5_split.py samples/mm5/MMOUT_DOMAIN1_CROP "$T/two" 2 > /dev/null
/usr/bin/python3 - "$T/two_01" "$T/bad_01" <<'PY'
import struct, sys
d = open(sys.argv[1], 'rb').read()
out, at, ends, cut, done = bytearray(), 0, 0, False, False
while at < len(d):
    n = struct.unpack('>i', d[at:at + 4])[0]
    pay = bytearray(d[at + 4:at + 4 + n])
    if cut:
        pay, cut = pay[:n * 39 // 40], False
    elif n == 4 and struct.unpack('>i', pay)[0] == 2:
        ends += 1
    elif not done and n >= 152 and ends == 1 and pay[72:81].strip() == b'CLW':
        struct.pack_into('>i', pay, 20, struct.unpack('>i', pay[20:24])[0] - 1)
        cut = done = True
    out += struct.pack('>i', len(pay)) + pay + struct.pack('>i', len(pay))
    at += 8 + n
open(sys.argv[2], 'wb').write(out)
PY
expect "a damaged input: vsv-convert fails" 1 "$B/vsv-convert" -q "$T/two_00" "$T/bad_01" -o "$T/bad.vsv"
expect "a damaged input read by rank 3 of 4: exit 1" 1 $MPIRUN -np 4 "$MPI" -q "$T/two_00" "$T/bad_01" -o "$T/bad.vsv"
has "the message names rank 3 and the file" "$T/err" "vsv-convert-mpi: rank 3: $T/bad_01: record"
has "the message says what is wrong" "$T/err" "CLW (output time 1) is YXS 39x40"
n=$(grep -c "vsv-convert-mpi" "$T/err")
[ "$n" = 1 ] && pass "one message for the whole job" || fail "one message for the whole job" "$(cat "$T/err")"
left=$(ls "$T" | grep -c "^bad.vsv")
[ "$left" = 0 ] && pass "the failed job leaves no output and no temporary" || fail "the failed job leaves no output" "$(ls "$T")"
left=$(ls -A "$T/spool" | wc -l)
[ "$left" = 0 ] && pass "the failed job leaves no spool files" || fail "the failed job leaves no spool files" "$(ls -A "$T/spool")"
# interrupted runs: a scheduler's time limit (SIGTERM to mpirun), a hang-up
# (SIGHUP), Ctrl-C reaching the ranks (SIGINT to rank 0) and SIGTERM to the
# other rank: the temporary output is removed before the job dies of the
# signal, and the output from before stays (issue 33: OUT.tmp.XXXXXX was
# left after every interrupted run). A test shim stops rank 0 right after it
# made the temporary, so the signal comes there, with no timing.
cp "$T/crop.vsv" "$T/sig.vsv"
interrupt() { # NAME SIGNAL WHOM (mpirun, rank0 or rank1)
    rm -f "$T/held"
    $MPIRUN -np 2 -x LD_PRELOAD="$(pwd)/$B/tests/libholdtmp.so" -x VSV_TEST_HOLD="$T/sig.vsv.tmp." \
        -x VSV_TEST_HOLD_MARK="$T/held" -x ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0" \
        "$MPI" -q --time-res 10m "$T"/crop_0? -o "$T/sig.vsv" > "$T/out" 2> "$T/err" &
    job=$!
    i=0
    while [ ! -s "$T/held" ] && [ $i -lt 600 ] && kill -0 $job 2> /dev/null; do sleep 0.1; i=$((i + 1)); done
    if [ ! -s "$T/held" ] || ! ls "$T" | grep -q '^sig\.vsv\.tmp\.'; then
        fail "$1: rank 0 stops with its temporary made" "$(ls "$T" | grep sig) $(head -c 300 "$T/err")"
        kill -KILL $job 2> /dev/null
        wait $job
        return
    fi
    case $3 in
    mpirun) kill -$2 $job ;;
    rank0) kill -$2 "$(cat "$T/held")" ;;
    rank1) # (mpirun starts the ranks of one machine itself)
        pgrep -P $job | grep -vx "$(cat "$T/held")" | xargs kill -$2 ;;
    esac
    wait $job
    rc=$?
    [ $rc != 0 ] && pass "$1: the job fails (exit $rc)" || fail "$1: the job fails" "exit 0"
    left=$(ls "$T" | grep -c '^sig\.vsv\.')
    [ "$left" = 0 ] && pass "$1: no temporary left" || fail "$1: no temporary left" "$(ls "$T" | grep sig)"
    same "$1: the output from before is intact" "$T/crop.vsv" "$T/sig.vsv"
    left=$(ls -A "$T/spool" | wc -l)
    [ "$left" = 0 ] && pass "$1: no spool file left" || fail "$1: no spool file left" "$(ls -A "$T/spool")"
}
interrupt "SIGTERM to mpirun (a time limit)" TERM mpirun
interrupt "SIGHUP to mpirun" HUP mpirun
interrupt "SIGINT to rank 0" INT rank0
interrupt "SIGTERM to rank 1" TERM rank1

expect "an output directory that does not exist: exit 1" 1 $MPIRUN -np 2 "$MPI" -q "$T"/crop_00 -o "$T/nowhere/x.vsv"
has "... said by rank 0" "$T/err" "vsv-convert-mpi: rank 0: $T/nowhere/x.vsv: cannot create a temporary file beside it"
exit 0
