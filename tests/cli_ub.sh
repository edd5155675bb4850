#!/bin/sh
# cli_ub.sh — crafted model inputs that were undefined behaviour (issue 18):
# sizes and times that overflowed 64-bit arithmetic (the sanitizer build
# aborted on them), and a NaN hour taken as a time. Each is now exit 1 with
# a message naming the file and the place.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-ub.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

# GrADS: 2e9 x 2e9 cells (nx*ny*4*levels wrapped int64)
: > "$T/x.bin"
cat > "$T/huge.ctl" <<EOC
DSET ^x.bin
XDEF 2000000000 LINEAR 0 1
YDEF 2000000000 LINEAR 0 1
ZDEF 1 LEVELS 1000
TDEF 1 LINEAR 00Z01JAN2000 1hr
VARS 1
A 0 99 a field
ENDVARS
EOC
expect "GrADS XDEF of 2e9 cells exits 1" 1 "$B/vsv-info" "$T/huge.ctl"
has "the dimension is named, with the line" "$T/err" "vsv-info: $T/huge.ctl: line 2: XDEF 2000000000: more than 16384 cells"
# GrADS: 16384^2 x 16384 levels x 1000 variables x 10^7 steps (bytes wrapped)
{
    echo "DSET ^x.bin"; echo "XDEF 16384 LINEAR 0 1"; echo "YDEF 16384 LINEAR 0 1"
    echo "ZDEF 64 LINEAR 0 1"; echo "TDEF 10000000 LINEAR 00Z01JAN2000 1mn"; echo "VARS 1000"
    i=0; while [ $i -lt 1000 ]; do echo "V$i 64 99 v"; i=$((i + 1)); done; echo ENDVARS
} > "$T/bytes.ctl"
expect "GrADS data of more than 2^63 bytes exits 1" 1 "$B/vsv-info" "$T/bytes.ctl"
has "the size is named" "$T/err" "more than 2^63 bytes"
# GrADS: a monthly increment of 999999999 years (the calendar overflowed)
sed 's/^TDEF.*/TDEF 3 LINEAR 00Z01JAN2000 999999999yr/; s/^XDEF.*/XDEF 4 LINEAR 0 1/; s/^YDEF.*/YDEF 4 LINEAR 0 1/' \
    "$T/huge.ctl" > "$T/years.ctl"
expect "GrADS time increment of 1e9 years exits 1" 1 "$B/vsv-info" "$T/years.ctl"
has "the increment is named" "$T/err" "line 5: bad time increment 999999999yr"

# UAM-IV: hour 0 begins at a NaN hour (was a time of nothing)
cp tests/corpus/uamiv/test.uamiv "$T/nan.uamiv"
printf '\177\300\000\000' | dd of="$T/nan.uamiv" bs=1 seek=1260 conv=notrunc 2> /dev/null
expect "a UAM-IV file whose hour is NaN exits 1" 1 "$B/vsv-info" "$T/nan.uamiv"
has "the hour and its record are named" "$T/err" "vsv-info: $T/nan.uamiv: hour 0: begins at date 2154, hour nan: not a time"
expect "vsv-convert on it exits 1" 1 "$B/vsv-convert" -q "$T/nan.uamiv" -o "$T/nan.vsv"
[ ! -e "$T/nan.vsv" ] && pass "nothing written for it" || fail "nothing written for it" "$T/nan.vsv exists"
