#!/bin/sh
# cli_deb.sh — `make test-deb`: Vesuvius installed as the field's software
# (issue 37). As root, since it changes the system, and it puts it back:
#  1. on a fresh clone of HEAD (what is not committed is not tested),
#     `make deb`: four .debs of the code's one version in build/deb/,
#     lintian with no error;
#  2. `apt-get install` of them; then, from /, every tool's --version, `man
#     vsv-info` and `man 5 vsv`, pkg-config, a C program built against the
#     installed headers and run on the shared library, the libraries'
#     helpers found, `import vesuvius` in /usr/bin/python3 reading a sample,
#     and the FreeVR back end built against the installed libvesuvius-dev
#     (the project's stand-in for FreeVR);
#  3. `apt-get remove --purge`: every file `dpkg -L` listed is gone;
#  4. `make install PREFIX=/usr/local`: /usr/bin/python3 imports the module
#     from / with no PYTHONPATH; `make uninstall` leaves /usr/local's files
#     as they were.
# VSV_DEBS=DIR tests the .debs already in DIR instead of building them.
# Not part of `make test` (CI runs it, .ci/run); skipped when not root, and
# refused where Vesuvius is installed already (packages or /usr/local).
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-deb.XXXXXX")
. tests/cli_lib.sh
TOP=$(pwd)
PKGS="vesuvius libvesuvius0 libvesuvius-dev python3-vesuvius"
V=$(sed -n 's/^#define VSV_VERSION_STRING "\(.*\)"$/\1/p' format/vsv_format.h)
PY=/usr/bin/python3
installed() { dpkg-query -W -f='${Status}\n' "$@" 2> /dev/null | grep -c ' installed$'; }
cleanup() {
    [ "$(installed $PKGS)" = 0 ] || apt-get remove -y -qq --purge $PKGS > /dev/null 2>&1
    [ -n "${LOCAL:-}" ] && make -s -C "$TOP" --no-print-directory B="$B" uninstall PREFIX=/usr/local > /dev/null 2>&1
    rm -rf "$T"
}
if [ "$(id -u)" != 0 ]; then
    skip "Debian packages and make install PREFIX=/usr/local" "not root"
    rm -rf "$T"
    exit 0
fi
if [ "$(installed $PKGS)" != 0 ] || [ -e /usr/local/bin/vsv-info ]; then
    fail "a system without Vesuvius to test on" "installed already (packages, or in /usr/local): left alone"
    rm -rf "$T"
    exit 0
fi
trap cleanup EXIT
export DEBIAN_FRONTEND=noninteractive

# 1. make deb on a fresh clone
build_debs() {
    git clone -q "$TOP" "$T/src" || return 1
    t0=$(date +%s)
    if make -C "$T/src" --no-print-directory deb > "$T/deb.log" 2>&1; then
        pass "make deb on a fresh clone ($(($(date +%s) - t0)) s)"
    else
        fail "make deb on a fresh clone" "$(tail -n 5 "$T/deb.log" | tr '\n' ' ')"
        return 1
    fi
    DEBS="$T/src/build/deb"
    nerr=$(grep -c '^E: ' "$DEBS/lintian.txt")
    nwarn=$(grep -c '^W: ' "$DEBS/lintian.txt")
    [ "$nerr" = 0 ] && pass "lintian: no errors ($nwarn warnings)" ||
        fail "lintian: no errors" "$(grep '^E: ' "$DEBS/lintian.txt" | head -n 3 | tr '\n' ' ')"
}
if [ -n "${VSV_DEBS:-}" ]; then
    DEBS=$(cd "$VSV_DEBS" && pwd)
    git clone -q "$TOP" "$T/src"
    echo "(the .debs of $DEBS, not built here)"
else
    build_debs || exit 0
fi
for p in $PKGS; do
    f="$DEBS/${p}_${V}_$(dpkg --print-architecture).deb"
    v=$(dpkg-deb -f "$f" Version 2> /dev/null)
    [ "$v" = "$V" ] && pass "$p $V built (the version of format/vsv_format.h)" || fail "$p $V built" "'$v' in $f"
done

# 2. installed by apt with their dependencies, used from /
if apt-get install -y -qq "$DEBS"/*.deb > "$T/apt.log" 2>&1 && [ "$(installed $PKGS)" = 4 ]; then
    pass "apt-get install ./build/deb/*.deb: the four packages and their dependencies"
else
    fail "apt-get install ./build/deb/*.deb" "$(tail -n 5 "$T/apt.log" | tr '\n' ' ')"
    exit 0
fi
dpkg -L $PKGS | sort -u > "$T/listed"
expect "vsv-info --version from /" 0 env -C / vsv-info --version
has "says the version" "$T/out" "vsv-info (Vesuvius $V) format "
bad=""
for t in $(dpkg -L vesuvius | grep '^/usr/bin/'); do
    case $(env -C / "$t" --version 2>&1) in "${t##*/} (Vesuvius $V) format "*) ;; *) bad="$bad ${t##*/}" ;; esac
done
[ -z "$bad" ] && pass "every packaged tool's --version says $V" || fail "every packaged tool's --version says $V" "$bad"
expect "man vsv-info" 0 env -C / MANPAGER=cat MANWIDTH=80 man vsv-info
has "shows the installed page" "$T/out" "vsv-info"
expect "man 5 vsv (the format)" 0 env -C / MANPAGER=cat MANWIDTH=80 man 5 vsv
expect "pkg-config --cflags --libs vesuvius" 0 env -C / pkg-config --cflags --libs vesuvius
has "names the library" "$T/out" "-lvesuvius"

cat > "$T/hello.c" <<'EOC'
#include <stdio.h>
#include <vesuvius/vsv_format.h>
int main(int argc, char **argv)
{
    vsv_file *f = NULL;
    if (argc < 2 || vsv_file_open(argv[1], &f)) {
        fprintf(stderr, "%s\n", f ? vsv_file_error(f) : "usage");
        return 1;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    printf("%s %d steps %d species\n", VSV_VERSION_STRING, info.nsteps, info.nspecies);
    vsv_file_free(f);
    return 0;
}
EOC
expect "the packaged vsv-convert converts the bundled MM5 sample" 0 \
    env -C / vsv-convert -q "$TOP/samples/mm5/MMOUT_DOMAIN1_CROP" -o "$T/crop.vsv"
expect "a C program builds against the installed headers and library" 0 \
    env -C / sh -c "cc -o '$T/hello' '$T/hello.c' \$(pkg-config --cflags --libs vesuvius)"
expect "and reads the sample" 0 env -C / "$T/hello" "$T/crop.vsv"
has "with the installed version" "$T/out" "$V 4 steps 8 species"
lib=$(ldd "$T/hello" | sed -n 's/.*libvesuvius.so.0 => \([^ ]*\).*/\1/p')
case $lib in /usr/lib/*/libvesuvius.so.0 | /lib/*/libvesuvius.so.0) pass "linked to the packaged $lib" ;;
*) fail "linked to the packaged libvesuvius.so.0" "'$lib'" ;; esac
expect "the packaged tools find the libraries' helpers (a libhdf5 crash is an error)" 1 \
    env -C / vsv-info "$TOP/tests/corpus/netcdf/hdf5-segv.nc"
has "naming the file" "$T/err" "damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it"
expect "/usr/bin/python3 -c 'import vesuvius' from / reads the sample" 0 env -C / -i PATH=/usr/bin:/bin $PY -c \
    'import sys, numpy, vesuvius; f = vesuvius.open(sys.argv[1]); c = f.read("CLW", 3)
print(vesuvius.__file__, vesuvius.version, len(f.times), len(f.species), c.shape, numpy.nanmax(c) > 0)' "$T/crop.vsv"
has "the packaged module, 4 steps, 8 species (five and the wind)" "$T/out" "/usr/lib/python3/dist-packages/vesuvius/__init__.py $V 4 8"
has "and cloud water in it" "$T/out" "True"

# the FreeVR back end against the installed libvesuvius-dev (README,
# "FreeVR"): the player core compiled from the clone, the libraries the
# package's archives; the project's stand-in in place of FreeVR
freevr_check() {
    fb="$T/src/build-fvr"
    sdir="$fb/tests/freevr-standin"
    libdir=$(pkg-config --variable=libdir vesuvius)
    if make -C "$T/src" -s --no-print-directory B=build-fvr "build-fvr/tests/freevr-standin/lib/libfreevr.a" \
        "build-fvr/tests/freevr-standin/include/freevr.h" > "$T/fvr.log" 2>&1 &&
        make -C "$T/src" -s --no-print-directory B=build-fvr freevr FREEVR_DIR="$sdir" VSV_LIBDIR="$libdir" \
            >> "$T/fvr.log" 2>&1; then
        pass "make freevr FREEVR_DIR=... VSV_LIBDIR=$libdir (the stand-in for FreeVR)"
    else
        fail "make freevr against the installed libvesuvius-dev" "$(tail -n 5 "$T/fvr.log" | tr '\n' ' ')"
        return
    fi
    ls "$fb"/libvesuvius*.a > /dev/null 2>&1 && fail "no library of the clone built" "$(ls "$fb"/libvesuvius*.a)" ||
        pass "no library of the clone built: the installed archives linked"
    expect "vsv-play-freevr --version" 0 "$fb/vsv-play-freevr" --version
    has "says $V" "$T/out" "vsv-play-freevr (Vesuvius $V)"
}
if pkg-config --exists glfw3 gl freetype2 fontconfig; then freevr_check; else
    skip "the FreeVR back end against libvesuvius-dev" "the viewer's libraries are missing"; fi

# 3. removed and purged: nothing of theirs left
if apt-get remove -y -qq --purge $PKGS > "$T/apt.log" 2>&1 && [ "$(installed $PKGS)" = 0 ]; then
    pass "apt-get remove --purge of the four packages"
else
    fail "apt-get remove --purge of the four packages" "$(tail -n 3 "$T/apt.log" | tr '\n' ' ')"
fi
left=$(while read -r f; do [ -e "$f" ] && [ ! -d "$f" ] && echo "$f"; done < "$T/listed")
n=$(grep -c . "$T/listed")
[ -z "$left" ] && pass "none of the $n paths dpkg -L listed is left but shared folders" ||
    fail "none of the paths dpkg -L listed is left" "$(echo "$left" | head -n 3 | tr '\n' ' ')"
gone=""
for d in /usr/lib/python3/dist-packages/vesuvius /usr/include/vesuvius /usr/share/vesuvius /usr/share/doc/vesuvius \
    "$(dirname "$lib")/vesuvius"; do
    [ -e "$d" ] && gone="$gone $d"
done
[ -z "$gone" ] && pass "their own folders are gone (module, headers, data, docs, helpers)" ||
    fail "their own folders are gone" "$gone"

# 4. make install PREFIX=/usr/local: python3 finds the module with no
# PYTHONPATH; make uninstall puts /usr/local's files back as they were
snap() { find /usr/local -xdev \( -type f -o -type l \) | sort; }
snap > "$T/before"
LOCAL=1
if make -s -C "$TOP" --no-print-directory B="$B" install PREFIX=/usr/local > "$T/install.log" 2>&1; then
    pass "make install PREFIX=/usr/local"
else
    fail "make install PREFIX=/usr/local" "$(tail -n 5 "$T/install.log" | tr '\n' ' ')"
fi
d=$($PY "$TOP/tools/pydir.py" /usr/local)
expect "/usr/bin/python3 -c 'import vesuvius' from / with no PYTHONPATH reads the sample" 0 env -C / -i PATH=/usr/bin:/bin \
    $PY -c 'import sys, vesuvius; f = vesuvius.open(sys.argv[1]); print(vesuvius.__file__, len(f.times), len(f.species))' \
    "$T/crop.vsv"
has "the module installed in $d" "$T/out" "$d/vesuvius/__init__.py 4 8"
expect "/usr/local/bin/vsv-info --version" 0 env -C / /usr/local/bin/vsv-info --version
has "says $V" "$T/out" "vsv-info (Vesuvius $V)"
make -s -C "$TOP" --no-print-directory B="$B" uninstall PREFIX=/usr/local > "$T/install.log" 2>&1
LOCAL=
snap > "$T/after"
extra=$(comm -13 "$T/before" "$T/after")
[ -z "$extra" ] && pass "make uninstall PREFIX=/usr/local: /usr/local's files as before" ||
    fail "make uninstall PREFIX=/usr/local leaves nothing" "$(echo "$extra" | head -n 3 | tr '\n' ' ')"
