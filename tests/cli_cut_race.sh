#!/bin/sh
# cli_cut_race.sh — files cut to a third at a random moment while a tool
# reads them (issue 33's truncation races: vsv-render and vsv-export crashed
# 3 of 24 and 4 of 94 times; model inputs died of SIGBUS). Every try must
# end either with exit 0 and the output the intact file gives (the tool was
# done before the cut), or exit 1 with an error naming the file, nothing
# written; never a signal, never another picture. The moment varies, the
# rule does not: no outcome depends on timing. cli_tools.sh cuts at a fixed
# point (right after the map) by a preloaded shim; this cuts anywhere.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-race.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
TRIES=${RACE_TRIES:-24}

# a millisecond count in [0, $1) from /dev/urandom
rand_ms() { echo $(($(od -An -N2 -tu2 /dev/urandom) % $1)); }

# race NAME FILE MS OUT REF CMD... : TRIES times, FILE restored from
# FILE.orig, CMD started, FILE cut to a third after a random 0..MS ms; OUT
# (the command's output) must then equal REF (exit 0) or be absent (exit 1
# with a message "TOOL: FILE: ..." naming the file cut: "truncated while
# reading", or what the reader found short when the cut came first)
race() {
    name=$1 file=$2 ms=$3 out=$4 ref=$5
    shift 5
    tag="${1##*/}: $file: "
    whole=0 cut=0 bad=""
    size=$(wc -c < "$file.orig")
    i=0
    while [ $i -lt "$TRIES" ]; do
        i=$((i + 1))
        cp "$file.orig" "$file"
        rm -f "$out"
        "$@" < /dev/null > "$T/out" 2> "$T/err" &
        pid=$!
        sleep "$(printf '%d.%03d' 0 "$(rand_ms "$ms")")"
        truncate -s $((size / 3)) "$file"
        wait $pid
        rc=$?
        if [ $rc = 0 ] && cmp -s "$out" "$ref"; then
            whole=$((whole + 1))
        elif [ $rc = 1 ] && [ "$(head -c ${#tag} "$T/err")" = "$tag" ] && [ ! -e "$out" ]; then
            cut=$((cut + 1))
        else
            bad="$bad try $i: exit $rc, $(head -c 200 "$T/err");"
        fi
    done
    if [ -z "$bad" ]; then
        pass "$name: $TRIES tries, $whole done before the cut, $cut said truncated"
    else
        fail "$name" "$bad"
    fi
}

"$B/vsv-convert" -q --vertical even samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/a.vsv.orig" || exit 1
cp "$T/a.vsv.orig" "$T/a.vsv"
set -- "$B/vsv-render" -q --threads 2 "$T/a.vsv" --size 640x480 --time 3 -o "$T/r.exr"
"$@" && mv "$T/r.exr" "$T/ref.exr" || fail "vsv-render of the intact file" "exit $?"
race "vsv-render of a .vsv cut while it renders" "$T/a.vsv" 400 "$T/r.exr" "$T/ref.exr" "$@"
set -- "$B/vsv-export" -q "$T/a.vsv" --netcdf "$T/e.nc"
cp "$T/a.vsv.orig" "$T/a.vsv"
"$@" && mv "$T/e.nc" "$T/ref.nc" || fail "vsv-export of the intact file" "exit $?"
race "vsv-export --netcdf of a .vsv cut while it exports" "$T/a.vsv" 500 "$T/e.nc" "$T/ref.nc" "$@"

TRIES=${RACE_TRIES_INPUT:-3}
cp samples/mm5/MMOUT_DOMAIN1_CROP "$T/in.orig"
cp "$T/in.orig" "$T/in"
set -- "$B/vsv-convert" -q "$T/in" -o "$T/c.vsv"
"$@" && mv "$T/c.vsv" "$T/ref.vsv" || fail "vsv-convert of the intact input" "exit $?"
race "vsv-convert of an MM5 file cut while it converts" "$T/in" 200 "$T/c.vsv" "$T/ref.vsv" "$@"
