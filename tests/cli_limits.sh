#!/bin/sh
# cli_limits.sh — resources that run out (issue 33 item 11): memory
# (ulimit -v), descriptors (ulimit -n) and the disk (a full tmpfs where
# mounting one is allowed, a file size limit everywhere), each an exit 1
# whose message names the cause, never another errno's text, an empty
# message or a crash; and no tool loads OpenVDB, which aborted every tool
# that linked it before main under 155 MB of address space.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-limits.XXXXXX")
trap 'umount "$T/full" 2> /dev/null; rm -rf "$T"' EXIT
. tests/cli_lib.sh
"$B/vsv-convert" -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/a.vsv" || { fail "convert the sample" "exit $?"; exit 0; }
mkdir "$T/vdb"
"$B/vsv-export" -q "$T/a.vsv" --vdb "$T/vdb/v_%d.vdb" || { fail "export the sample as .vdb" "exit $?"; exit 0; }

# out_of NAME WANT OPT CMD... : under each limit `ulimit OPT N` for N in
# $LIMITS (set in a subshell), CMD exits 0, or 1 with WANT (an extended
# regular expression, case ignored) in its message; one PASS or FAIL line
# for them all
out_of() {
    name=$1 want=$2 how=$3
    shift 3
    bad= seen=0
    for lim in $LIMITS; do
        (ulimit "$how" "$lim" && exec "$@") < /dev/null > "$T/out" 2> "$T/err"
        rc=$?
        # (too little to load the program: the dynamic loader's, before main)
        [ $rc = 127 ] && grep -q "error while loading shared libraries" "$T/err" && continue
        [ $rc = 1 ] && seen=$((seen + 1))
        if [ $rc != 0 ] && { [ $rc != 1 ] || ! grep -qiE -- "$want" "$T/err"; }; then
            bad="$bad; at $lim: exit $rc: $(head -c 200 "$T/err" | tr '\n' ' ')"
        fi
    done
    if [ -n "$bad" ]; then
        fail "$name" "${bad#; }"
    elif [ $seen = 0 ]; then
        echo "note: $name: no limit made it fail here: not tested"
    else
        pass "$name ($seen limits failed it, each saying so)"
    fi
}

# memory: under the sanitizers (whose shadow memory is address space) not
if [ -n "${SANFLAGS:-}" ]; then
    echo "note: address-space limits not tried under the sanitizers"
else
    # OpenVDB's logging library (log4cplus) threw from its static
    # initialiser under 155 MB, before main, in every tool that linked
    # OpenVDB (vsv-convert, -extract, -export, -convert-mpi), whatever it
    # was asked: it is loaded by the helper vsv-vdb-reader alone
    # (vsv-convert-mpi left out: its start is Open MPI's, whose PMIx
    # shared-memory set-up failed once under this limit on a loaded machine)
    for t in vsv-info vsv-convert vsv-extract vsv-export vsv-render vsv-query vsv-pack vsv-interp; do
        [ -x "$B/$t" ] || continue
        (ulimit -v 150000 && exec "$B/$t" --version) < /dev/null > "$T/out" 2> "$T/err"
        rc=$?
        if [ $rc = 0 ] && grep -q "^$t (Vesuvius" "$T/out"; then pass "$t --version under 150 MB of address space"; else
            fail "$t --version under 150 MB of address space" "exit $rc: $(head -c 200 "$T/err")"; fi
        if ldd "$B/$t" | grep -qE 'libopenvdb|liblog4cplus'; then fail "$t does not load OpenVDB" "$(ldd "$B/$t" | grep -E 'openvdb|log4cplus')"; else
            pass "$t does not load OpenVDB"; fi
    done
    (ulimit -v 150000 && exec "$B/vsv-convert" -q --threads 2 samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/m.vsv") < /dev/null > "$T/out" 2> "$T/err"
    rc=$?
    [ $rc = 0 ] && pass "vsv-convert of the MM5 sample under 150 MB" || fail "vsv-convert of the MM5 sample under 150 MB" "exit $rc: $(head -c 200 "$T/err")"
    # the helper, which does load it, reads and writes .vdb files there too
    (ulimit -v 150000 && exec "$B/vsv-convert" -q "$T"/vdb/v_0.vdb "$T"/vdb/v_1.vdb -o "$T/v.vsv") < /dev/null > "$T/out" 2> "$T/err"
    rc=$?
    [ $rc = 0 ] && pass "vsv-convert of .vdb files under 150 MB" || fail "vsv-convert of .vdb files under 150 MB" "exit $rc: $(head -c 200 "$T/err")"
    mkdir "$T/vdb150"
    (ulimit -v 150000 && exec "$B/vsv-export" -q "$T/a.vsv" --vdb "$T/vdb150/v_%d.vdb") < /dev/null > "$T/out" 2> "$T/err"
    rc=$?
    [ $rc = 0 ] && [ "$(ls "$T/vdb150" | wc -l)" = 4 ] &&
        pass "vsv-export --vdb under 150 MB: the four files" || fail "vsv-export --vdb under 150 MB" "exit $rc: $(head -c 200 "$T/err")"
    # out of memory said as such, at every limit from what loads the program
    # to what does the work: vsv-convert said "vsv-convert: " and nothing
    # more (a model reader, the run or the writer that returned only the
    # code), "cannot map: Cannot allocate memory", zstd's "Allocation
    # error", vsv-render "render failed"
    LIMITS=$(seq 40000 1000 170000)
    out_of "vsv-convert out of memory says 'out of memory'" "out of memory" -v \
        "$B/vsv-convert" -q --threads 2 samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/m.vsv"
    # with outlines: libhdf5 crashed (SIGSEGV in H5AC_create) under about
    # 70 MB as vsv-render read the GSHHG files in-process; the helper
    # vsv-gshhg reads them now, and its failure names the file
    if [ -r /usr/share/gmt-gshhg/binned_GSHHS_c.nc ]; then
        LIMITS=$(seq 40000 2000 170000)
        out_of "vsv-render with coastlines out of memory: said, naming the GSHHG file, never a crash" \
            "out of memory|binned_(GSHHS|border)_.\.nc: " -v \
            "$B/vsv-render" -q "$T/a.vsv" -o "$T/r.png" --size 320x240 --annotate all
        LIMITS=$(seq 40000 1000 170000)
    else
        echo "note: no gmt-gshhg-low: coastlines out of memory not tried"
    fi
    # (and without outlines, every limit)
    out_of "vsv-render out of memory says 'out of memory'" "out of memory" -v \
        "$B/vsv-render" -q --threads 2 "$T/a.vsv" -o "$T/r.png" --size 320x240 --annotate time,bars,scale,graticule
fi

# descriptors: the helper programs said "Invalid argument" (F_DUPFD's
# EINVAL when the limit is at or under the lowest number asked for)
LIMITS="5 6 7 8 9 10 11 12 13 14"
out_of "vsv-export --netcdf (vsv-nc-writer) out of descriptors: 'too many open files'" "too many open files" \
    -n "$B/vsv-export" -q "$T/a.vsv" --netcdf "$T/n.nc"
out_of "vsv-convert of .vdb files (vsv-vdb-reader) out of descriptors: 'too many open files'" "too many open files" \
    -n "$B/vsv-convert" -q "$T"/vdb/v_0.vdb "$T"/vdb/v_1.vdb -o "$T/v.vsv"
out_of "vsv-convert of a netCDF-4 file (vsv-nc-check) out of descriptors: 'too many open files'" \
    "too many open files" -n "$B/vsv-convert" -q tests/data/wrf/wrf_cropped.nc -o "$T/w.vsv"

# a full disk: netCDF-4 returns EACCES for any failed H5Fcreate, and the
# export said "cannot create: Permission denied". A file size limit of 0
# (SIGXFSZ ignored: writes fail with EFBIG) fails it the same way; the
# messages go through a pipe, which the limit does not cover
( trap "" XFSZ; ulimit -f 0; "$B/vsv-export" -q "$T/a.vsv" --netcdf "$T/n.nc" < /dev/null; echo "exit $?" ) 2>&1 |
    cat > "$T/err"
has "vsv-export --netcdf, no byte may be written: exit 1" "$T/err" "exit 1"
has "saying why: 'File too large'" "$T/err" "vsv-export: $T/n.nc: cannot create: File too large"
# images: libpng printed "libpng error: Write Error" and the tool "PNG
# encoding failed", OpenEXR its own line and "EXR writing failed: Error
# writing to stream": neither said why
for ext in png exr; do
    ( trap "" XFSZ; ulimit -f 0; "$B/vsv-render" -q "$T/a.vsv" -o "$T/f.$ext" --size 320x240 < /dev/null; echo "exit $?" ) 2>&1 |
        cat > "$T/err"
    has "vsv-render $ext, no byte may be written: exit 1" "$T/err" "exit 1"
    [ "$(head -n 1 "$T/err")" = "vsv-render: $T/f.$ext: cannot write: File too large" ] &&
        pass "one line, the tool's, saying why" || fail "one line, the tool's, saying why" "$(head -c 300 "$T/err")"
done
mkdir "$T/full"
if mount -t tmpfs -o size=64k tmpfs "$T/full" 2> /dev/null; then
    dd if=/dev/zero of="$T/full/fill" bs=1k count=1024 2> /dev/null
    expect "vsv-export --netcdf on a full disk exits 1" 1 "$B/vsv-export" -q "$T/a.vsv" --netcdf "$T/full/n.nc"
    has "saying 'No space left on device'" "$T/err" "vsv-export: $T/full/n.nc: cannot create: No space left on device"
    expect "vsv-export --vdb on a full disk exits 1" 1 "$B/vsv-export" -q "$T/a.vsv" --vdb "$T/full/v.vdb" -t 0
    has "saying 'No space left on device'" "$T/err" "vsv-export: $T/full/v.vdb: cannot write: No space left on device"
    for ext in png exr; do
        expect "vsv-render $ext on a full disk exits 1" 1 "$B/vsv-render" -q "$T/a.vsv" -o "$T/full/f.$ext" --size 320x240
        [ "$(cat "$T/err")" = "vsv-render: $T/full/f.$ext: cannot write: No space left on device" ] &&
            pass "one line, saying 'No space left on device'" || fail "one line, saying 'No space left on device'" "$(head -c 300 "$T/err")"
    done
    [ "$(ls "$T/full")" = fill ] && pass "nothing left on the full disk" || fail "nothing left on the full disk" "$(ls "$T/full")"
    umount "$T/full"
else
    echo "note: a full tmpfs not tried (mounting one is not allowed here)"
fi
