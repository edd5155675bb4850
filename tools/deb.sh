#!/bin/sh
# deb.sh — `make deb`: the Debian packages of debian/ (vesuvius,
# libvesuvius0, libvesuvius-dev, python3-vesuvius), built the Debian way:
# dpkg-buildpackage on a copy of this tree in $B/deb/src/ (it writes the
# packages beside the tree it builds, so never beside the checkout), the
# .debs moved to $B/deb/, then lintian on them (errors fail; the warnings
# are argued in README.md, "Debian packages").
#   1. the one version: VSV_VERSION_STRING (format/vsv_format.h), the first
#      entry of debian/changelog and the first heading of NEWS must agree;
#   2. what the build needs: tools/deps.sh --install and --install-deb (as
#      root it installs what is missing, else prints the apt-get line).
set -eu
B=${B:-build}
OUT="$B/deb"
die() { echo "make deb: $*" >&2; exit 1; }

V=$(sed -n 's/^#define VSV_VERSION_STRING "\(.*\)"$/\1/p' format/vsv_format.h)
[ -n "$V" ] || die "no VSV_VERSION_STRING in format/vsv_format.h"
C=$(sed -n '1s/^vesuvius (\([^)]*\)).*/\1/p' debian/changelog)
N=$(sed -n 's/^## \([0-9][0-9.]*\)\( .*\)\{0,1\}$/\1/p' NEWS | head -n 1)
[ "$C" = "$V" ] || die "debian/changelog says $C, format/vsv_format.h $V: add a changelog entry for $V (dch -v $V)"
[ "$N" = "$V" ] || die "NEWS's first version is '$N', format/vsv_format.h says $V"

sh tools/deps.sh --install
sh tools/deps.sh --install-deb

# the tree as git sees it (tracked and untracked files, not what .gitignore
# names: no build output), or, outside a checkout, all but the build folders
src="$OUT/src/vesuvius-$V"
rm -rf "$OUT/src"
mkdir -p "$src"
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
    git ls-files -z --cached --others --exclude-standard |
        tar --null -T - --ignore-failed-read -cf - 2> /dev/null | tar -xf - -C "$src"
else
    tar --exclude=./build --exclude='./build-*' --exclude=./demo-out -cf - . | tar -xf - -C "$src"
fi

log="$OUT/dpkg-buildpackage.log"
echo "make deb: dpkg-buildpackage -b in $src (log: $log)"
jobs=$(nproc 2> /dev/null || echo 2)
if ! (cd "$src" && DEB_BUILD_OPTIONS="noddebs parallel=$jobs ${DEB_BUILD_OPTIONS:-}" \
    dpkg-buildpackage -b -us -uc) > "$log" 2>&1; then
    tail -n 30 "$log" >&2
    die "dpkg-buildpackage failed (whole log: $log)"
fi
grep -E '(warning|error):' "$log" | grep -v '^dpkg-' | sort -u | head -n 20 | sed 's/^/make deb: compiler: /'

rm -f "$OUT"/*.deb "$OUT"/*.buildinfo "$OUT"/*.changes
mv "$OUT"/src/*.deb "$OUT"/src/*.buildinfo "$OUT"/src/*.changes "$OUT"/
rm -rf "$OUT/src"
ls -1 "$OUT"/*.deb

# lintian: every tag at warning level or above is printed; an error fails
# (its note that it runs as root is not about the packages)
rc=0
lintian --fail-on error --tag-display-limit 0 "$OUT"/*.deb > "$OUT/lintian.all" 2>&1 || rc=$?
grep -v '^running with root privileges' "$OUT/lintian.all" > "$OUT/lintian.txt" || true
rm -f "$OUT/lintian.all"
if [ $rc != 0 ]; then
    cat "$OUT/lintian.txt"
    die "lintian found errors"
fi
if [ -s "$OUT/lintian.txt" ]; then
    echo "make deb: lintian, no errors (README.md argues each warning):"
    sed 's/^/  /' "$OUT/lintian.txt"
else
    echo "make deb: lintian: nothing to report"
fi
