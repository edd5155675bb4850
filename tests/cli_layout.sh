#!/bin/sh
# cli_layout.sh — the house rules of DESIGN.md §1 that a compiler alone does
# not keep: every #include follows the arrows (a folder sees its own headers
# and the public headers of the layers under it; libraries never see the
# programs' cli/; each layer includes only its own dependencies' headers), no
# source file is over 700 lines, no build output is committed, and the code,
# debian/changelog and NEWS hold one version. A copy of the tree with bad
# includes planted in it must fail the same check.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-layout.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh

# The public headers: what `make install` installs (PUBLIC_H in the Makefile).
# common/ (the internal helpers, one archive) is under every library: its
# headers are seen by all and installed by none.
public=$(awk '/^PUBLIC_H *=/ { on = 1; sub(/^PUBLIC_H *= */, "") }
              on { c = sub(/\\$/, ""); printf "%s ", $0; if (!c) on = 0 }' Makefile)
installed=$public

# sees DIR TOOL: the folders whose headers a file of DIR may include
sees() {
    case $1 in
    common) s="common format" ;; # (format's public header only: checked below)
    format) s="format" ;;
    stream) s="stream format" ;;
    convert) s="convert format" ;;
    render) s="render format" ;;
    gl) s="gl render format" ;; # render/gl/: the GPU raycaster, a library above render/
    interop) s="interop convert format" ;;
    cli) s="cli format" ;;
    viewer) s="viewer gl render stream format" ;;
    python) s="python format" ;;
    esac
    [ "$2" = 1 ] && s="$s cli"
    echo "$s common"
}
# the other libraries' headers a layer must not include (its dependencies only)
foreign() {
    case $1 in
    common | format | stream | cli) echo 'netcdf\.h|openvdb/|png\.h|openexr\.h|Imf|GLFW/|GL/|ft2build\.h|fontconfig/|curl/' ;;
    http) echo 'netcdf\.h|openvdb/|png\.h|openexr\.h|Imf|GLFW/|GL/|ft2build\.h|fontconfig/' ;; # format/http/: libcurl
    convert) echo 'openvdb/|png\.h|openexr\.h|Imf|GLFW/|GL/|ft2build\.h|fontconfig/' ;;
    render) echo 'GeographicLib/|openvdb/|GLFW/|GL/|fontconfig/|epoxy/' ;;
    gl) echo 'GeographicLib/|openvdb/|GLFW/|GL/|fontconfig/|png\.h|openexr\.h|netcdf\.h' ;; # epoxy/ only
    interop) echo 'png\.h|openexr\.h|GLFW/|GL/|ft2build\.h|fontconfig/' ;;
    viewer) echo 'netcdf\.h|GeographicLib/|openvdb/' ;;
    python) echo 'netcdf\.h|GeographicLib/|openvdb/|png\.h|openexr\.h|Imf|GLFW/|GL/|ft2build\.h|fontconfig/' ;;
    esac
}

# check ROOT: one line per include against the arrows in the tree at ROOT
check() {
    root=$1
    for f in $(cd "$root" && ls -d common/* format/* format/http/* stream/* convert/* render/* render/gl/* interop/* cli/* viewer/*.[ch] python/*.c 2>/dev/null); do
        case $f in *.c | *.h | *.cc) ;; *) continue ;; esac
        dir=${f%%/*}
        base=${f#*/}
        case $f in render/gl/*) dir=gl base=${f#render/gl/} ;; esac
        tool=0
        case $base in vsv-*.c | vsv_*_cli.[ch]) tool=1 ;; esac # programs, and code their tools share
        folders=$(sees "$dir" $tool)
        # vsv-extract, vsv-convert (and -mpi) and vsv-info read .vdb files through interop/
        case $f in convert/vsv-extract.c | convert/vsv-convert.c | convert/vsv-convert-mpi.c | convert/vsv-info.c)
            folders="$folders interop" ;;
        render/vsv-render.c) folders="$folders gl" ;; # --renderer gl
        interop/vsv-export.c) folders="$folders render" ;; # --iso: the isosurfaces render/ extracts
        esac
        bad=$(foreign "$dir")
        case $f in format/http/*) bad=$(foreign http) ;; esac
        grep -n '^[[:space:]]*#[[:space:]]*include' "$root/$f" | while IFS= read -r line; do
            n=${line%%:*}
            h=$(echo "$line" | sed -n 's/.*include[[:space:]]*"\([^"]*\)".*/\1/p')
            if [ -z "$h" ]; then
                sys=$(echo "$line" | sed -n 's/.*include[[:space:]]*<\([^>]*\)>.*/\1/p')
                if [ -n "$sys" ] && echo "$sys" | grep -Eq "^($bad)"; then
                    echo "$f:$n: <$sys>: not a dependency of $dir/"
                fi
                continue
            fi
            dpath=$dir
            [ "$dir" = gl ] && dpath=render/gl
            [ -e "$root/$dpath/$h" ] && continue # its own folder
            [ -e "$root/$dir/freevr/$h" ] && continue
            owner="" opath=""
            for d in common format stream convert render render/gl interop cli viewer python; do
                [ -e "$root/$d/$h" ] && opath=$d owner=${d#render/}
            done
            [ -z "$owner" ] && continue # not ours
            ok=0
            for d in $folders; do [ "$d" = "$owner" ] && ok=1; done
            if [ $ok = 0 ]; then
                echo "$f:$n: \"$h\": $dir/ does not see $owner/"
                continue
            fi
            case " $public " in
            *" $opath/$h "*) ;;
            *) [ "$owner" = cli ] || [ "$owner" = common ] || echo "$f:$n: \"$h\": private to $opath/" ;;
            esac
        done
    done
}

check . > "$T/found"
if [ -s "$T/found" ]; then
    fail "every #include follows DESIGN.md's arrows" "$(head -c 600 "$T/found")"
else
    pass "every #include follows DESIGN.md's arrows ($(echo $public | wc -w) public headers)"
fi

# the arrows between libraries point one way (ARCHITECTURE.md): interop
# stands on convert (its OpenVDB reader is a source), so no library file of
# convert/ includes an interop/ header (its programs may: they are above both)
back=$(for f in convert/vsv_*.c convert/vsv_*.h; do
    case $f in *_cli.[ch]) continue ;; esac
    sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f" | while read -r h; do
        [ -e "interop/$h" ] && echo "$f: $h"
    done
done)
[ -z "$back" ] && pass "convert/'s library includes nothing of interop/ (the arrow is one way)" ||
    fail "convert/'s library includes nothing of interop/ (the arrow is one way)" "$back"
# each source is compiled into one library: the static archives share no
# member (common/'s helpers are compiled once, into common/libvsv-common.a,
# which the core's archive carries and each shared library links privately)
dups=$(for a in "$B"/libvesuvius.a "$B"/libvesuvius-convert.a "$B"/libvesuvius-render.a "$B"/libvesuvius-gl.a \
    "$B"/libvesuvius-interop.a "$B"/libvesuvius-http.a; do ar t "$a" 2> /dev/null; done | sort | uniq -d | tr '\n' ' ')
n=$(for a in "$B"/libvesuvius*.a; do ar t "$a" 2> /dev/null; done | wc -l)
[ "$n" -gt 0 ] && [ -z "$dups" ] && pass "no object is in two libraries ($n objects in the static archives)" ||
    fail "no object is in two libraries" "${dups:-no archives in $B}"

# the check itself: a copy of the sources with four bad includes planted
mkdir -p "$T/tree"
cp -r common format stream convert render interop cli viewer python Makefile "$T/tree/"
echo '#include "vsv_render.h"' >> "$T/tree/convert/vsv_interp.c"
echo '#include "vsv_format_internal.h"' >> "$T/tree/render/vsv_tf.c"
echo '#include <netcdf.h>' >> "$T/tree/format/vsv_crc.c"
echo '#include "vsv_cli.h"' >> "$T/tree/convert/vsv_source.c"
(cd "$T/tree" && check .) > "$T/planted"
has "a planted include of render/ in convert/ is found" "$T/planted" '"vsv_render.h": convert/ does not see render/'
has "a planted include of format's internals in render/ is found" "$T/planted" '"vsv_format_internal.h": private to format/'
has "a planted <netcdf.h> in format/ is found" "$T/planted" '<netcdf.h>: not a dependency of format/'
has "a planted include of cli/ in a library is found" "$T/planted" '"vsv_cli.h": convert/ does not see cli/'
n=$(wc -l < "$T/planted")
[ "$n" = 4 ] && pass "and nothing else" || fail "and nothing else" "$(cat "$T/planted")"

# every installed header gives C++ callers C linkage (extern "C"): a C++
# file taking the address of every function a header declares must refer to
# them by their C names; a header without the guard leaves mangled _Z names
linkage() { # ROOT: one line per installed header whose functions get C++ linkage
    for h in $installed; do
        names=$(grep -E '^[A-Za-z].*[ *]vsv_[a-z0-9_]+\(' "$1/$h" | sed -E 's/^[^(]*[ *](vsv_[a-z0-9_]+)\(.*/\1/' | sort -u)
        { echo "#include \"$h\""; echo "void *probe[] = {"; for n in $names; do echo "(void *)&$n,"; done; echo "};"; } > "$T/probe.cc"
        if ! (cd "$1" && c++ -c -I. -Iformat -Istream -Iconvert -Irender -Iinterop -o "$T/probe.o" "$T/probe.cc") > "$T/cxx.err" 2>&1; then
            echo "$h: does not compile as C++: $(head -c 300 "$T/cxx.err")"
            continue
        fi
        n=$(nm -u "$T/probe.o" | grep -c ' _Z.*vsv_')
        [ "$n" = 0 ] || echo "$h: $n functions with C++ linkage (no extern \"C\")"
    done
}
if command -v c++ > /dev/null 2>&1; then
    linkage . > "$T/linkage"
    [ -s "$T/linkage" ] && fail "every installed header declares C linkage for C++" "$(cat "$T/linkage")" ||
        pass "every installed header declares C linkage for C++ ($(echo $installed | wc -w) headers)"
    sed -e '/^extern "C" {$/d' -e '/^}$/d' stream/vsv_clock.h > "$T/tree/stream/vsv_clock.h" # the guard's braces
    linkage "$T/tree" > "$T/linkage"
    has "a copy of vsv_clock.h without its guard is found" "$T/linkage" 'stream/vsv_clock.h: 15 functions with C++ linkage'
else
    fail "every installed header declares C linkage for C++" "no C++ compiler (c++)"
fi

# and the compiler agrees: convert/'s include path has no render/
if cc -fsyntax-only -Iconvert -Iformat -x c - < /dev/null > /dev/null 2>&1 &&
    ! printf '#include "vsv_render.h"\n' | cc -fsyntax-only -Iconvert -Iformat -x c - > /dev/null 2>&1; then
    pass "an include of render/ does not compile on convert/'s include path"
else
    fail "an include of render/ does not compile on convert/'s include path" "it compiled"
fi
inc=$(make -s --no-print-directory -pn B="$B" help 2>/dev/null |
    awk -v t="$B/convert/%.o :" '$0 == t { on = 1; next } on && /^# INC :?= / { sub(/^# INC :?= /, ""); print; exit }')
[ "$inc" = "-Iconvert -Iformat -Icommon" ] && pass "the Makefile gives convert/ that include path" ||
    fail "the Makefile gives convert/ that include path" "'$inc'"

# no source over ~700 lines (750 at most): libraries, programs, tests, the
# FreeVR stand-in, benchmarks, scripts (data and tables are not sources)
long=$(git ls-files 2>/dev/null | grep -E '\.(c|cc|h|py|sh)$' |
    xargs wc -l 2>/dev/null | awk '$2 != "total" && $1 > 750 { print $2 " " $1 }')
[ -z "$long" ] && pass "no source file over ~700 lines" || fail "no source file over ~700 lines" "$long"
# functions one screen long (STYLE.md; issue 34): none over 150 lines
long=$(/usr/bin/python3 tests/funclen.py 150 2> /dev/null)
[ -z "$long" ] && pass "no function over 150 lines (tests/funclen.py)" ||
    fail "no function over 150 lines (tests/funclen.py)" "$(echo "$long" | head -n 5 | tr '\n' ';')"
# every C and C++ source is formatted as .clang-format says (STYLE.md;
# clang-format-14, installed by `make test`'s dependency step)
if command -v clang-format-14 > /dev/null 2>&1; then
    git ls-files '*.c' '*.h' '*.cc' 2> /dev/null | xargs clang-format-14 --dry-run -Werror > "$T/fmt" 2>&1
    nf=$(grep -c 'error:' "$T/fmt")
    [ "$nf" = 0 ] && pass "clang-format-14 --dry-run -Werror: every source as .clang-format says" ||
        fail "clang-format-14 --dry-run -Werror: every source as .clang-format says" \
            "$nf places, first: $(grep -m 3 'error:' "$T/fmt" | cut -c 1-160 | tr '\n' ' ')"
else
    fail "clang-format-14 --dry-run -Werror" "no clang-format-14 (sh tools/deps.sh --install-test)"
fi
# no build output committed
art=$(git ls-files 2>/dev/null | grep -E '\.(o|a|so|d)$|^build|/build/|\.so\.' | head -n 5)
[ -z "$art" ] && pass "no build output in git ls-files" || fail "no build output in git ls-files" "$art"

# each shared library exports only what its public headers declare
# (nm -D --defined-only against every vsv_ name the headers mention)
exports() { # LIB HEADER...: the exported names no header declares
    lib=$1
    shift
    cat "$@" | grep -o 'vsv_[A-Za-z0-9_]*' | sort -u > "$T/declared"
    nm -D --defined-only "$lib" 2> /dev/null | awk '{ print $NF }' | sort -u > "$T/exported"
    comm -23 "$T/exported" "$T/declared" | tr '\n' ' '
}
for spec in "vesuvius format/vsv_format.h format/vsv_time.h format/vsv_vector.h format/vsv_output.h format/vsv_traj.h stream/vsv_pager.h stream/vsv_clock.h" \
    "vesuvius-convert convert/vsv_convert.h convert/vsv_source_reader.h" \
    "vesuvius-render render/vsv_render.h render/vsv_flow.h" "vesuvius-interop interop/vsv_vdb.h interop/vsv_cf.h" \
    "vesuvius-http format/vsv_http.h"; do
    set -- $spec
    name=$1
    shift
    so=$(ls "$B"/lib$name.so.* 2> /dev/null | head -n 1)
    if [ -z "$so" ]; then
        fail "lib$name.so exports only its public API" "not built"
        continue
    fi
    n=$(nm -D --defined-only "$so" | wc -l)
    extra=$(exports "$so" "$@")
    [ -z "$extra" ] && pass "lib$name.so exports only its public API ($n names)" ||
        fail "lib$name.so exports only its public API" "also: $extra"
done

# one version (NEWS): VSV_VERSION_STRING, debian/changelog's first entry and
# NEWS's first heading agree; the library package is named after the soname
v=$(sed -n 's/^#define VSV_VERSION_STRING "\(.*\)"$/\1/p' format/vsv_format.h)
c=$(sed -n '1s/^vesuvius (\([^)]*\)).*/\1/p' debian/changelog 2> /dev/null)
n=$(sed -n 's/^## \([0-9][0-9.]*\)\( .*\)\{0,1\}$/\1/p' NEWS 2> /dev/null | head -n 1)
[ -n "$v" ] && [ "$c" = "$v" ] && [ "$n" = "$v" ] &&
    pass "one version: vsv_format.h, debian/changelog and NEWS say $v" ||
    fail "one version: vsv_format.h, debian/changelog and NEWS agree" "'$v', '$c', '$n'"
so=$(sed -n 's/^SOVERSION = //p' Makefile)
grep -q "^Package: libvesuvius$so\$" debian/control 2> /dev/null && [ -f "debian/libvesuvius$so.install" ] &&
    pass "the shared libraries' package is libvesuvius$so (SOVERSION $so)" ||
    fail "the shared libraries' package is named after SOVERSION" "no libvesuvius$so in debian/"
