#!/bin/sh
# bench_format.sh — builds and runs bench_format (the .vsv file against raw
# float32, zstd -3 and netCDF-4 deflate, same data, one run).
set -eu
B=${B:-build}
SHARED=${SHARED:-../shared}
W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-bench.XXXXXX")
trap 'rm -rf "$W"' EXIT
printf 'machine: %s, %s cores; %s\n\n' "$(uname -m)" "$(nproc)" "$(date -u +%Y-%m-%d)"
"$B/bench/bench_format" "$SHARED" "$W"
