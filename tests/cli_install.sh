#!/bin/sh
# cli_install.sh — `make install` into a staging root: tools, each library
# static and shared (versioned soname) with its pkg-config file, headers
# under include/vesuvius/, man pages, the default transfer functions, bash
# completion; then small C programs built against the installed tree with
# pkg-config alone (`#include <vesuvius/vsv_format.h>`), run against the
# shared libraries.
B=${B:-build}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-install.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
R="$T/root"
P=/opt/vesuvius
if make -s --no-print-directory B="$B" install PREFIX=$P DESTDIR="$R" > "$T/log" 2>&1; then
    pass "make install PREFIX=$P DESTDIR=... succeeds"
else
    fail "make install PREFIX=$P DESTDIR=... succeeds" "$(tail -c 400 "$T/log")"
    exit 0
fi
for f in bin/vsv-info bin/vsv-render bin/vsv-plot lib/libvesuvius.a lib/libvesuvius.so lib/libvesuvius.so.0 \
    lib/libvesuvius-convert.so.0 lib/libvesuvius-render.so.0 lib/libvesuvius-interop.so.0 \
    lib/libvesuvius-convert.a lib/libvesuvius-render.a lib/libvesuvius-interop.a \
    include/vesuvius/vsv_format.h include/vesuvius/vsv_time.h include/vesuvius/vsv_vector.h include/vesuvius/vsv_output.h include/vesuvius/vsv_traj.h include/vesuvius/vsv_render.h include/vesuvius/vsv_flow.h include/vesuvius/vsv_pager.h \
    include/vesuvius/vsv_convert.h include/vesuvius/vsv_vdb.h \
    lib/pkgconfig/vesuvius.pc lib/pkgconfig/vesuvius-convert.pc lib/pkgconfig/vesuvius-render.pc \
    lib/pkgconfig/vesuvius-interop.pc share/man/man1/vsv-play.1 share/man/man1/vsv-info.1 share/man/man1/vsv-plot.1 share/man/man5/vsv.5 \
    share/vesuvius/transfer-functions.tf share/bash-completion/completions/vsv-render \
    share/bash-completion/completions/vsv-plot; do
    [ -e "$R$P/$f" ] && pass "installed: $f" || fail "installed: $f" "missing"
done
soname=$(readelf -d "$R$P/lib/libvesuvius.so" 2>/dev/null | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
[ "$soname" = libvesuvius.so.0 ] && pass "the shared library's soname is libvesuvius.so.0" ||
    fail "the shared library's soname is libvesuvius.so.0" "'$soname'"
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
export PKG_CONFIG_PATH="$R$P/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$R"
if cc $SANFLAGS -o "$T/hello" "$T/hello.c" $(pkg-config --cflags --libs vesuvius) > "$T/cc" 2>&1; then
    pass "a C program builds against the installed tree with pkg-config alone"
else
    fail "a C program builds against the installed tree with pkg-config alone" "$(head -c 400 "$T/cc")"
fi
"$B/vsv-convert" --vertical even -q samples/mm5/MMOUT_DOMAIN1_CROP -o "$T/crop.vsv"
expect "and runs on the installed shared library" 0 env LD_LIBRARY_PATH="$R$P/lib" "$T/hello" "$T/crop.vsv"
has "reading a real converted file (5 species and the wind's 3)" "$T/out" "4 steps 8 species"
ldd_out=$(LD_LIBRARY_PATH="$R$P/lib" ldd "$T/hello" 2>&1 | grep libvesuvius)
case $ldd_out in *"$R$P/lib/libvesuvius.so.0"*) pass "linked to libvesuvius.so.0 (shared)" ;;
*) fail "linked to libvesuvius.so.0 (shared)" "$ldd_out" ;; esac
# the core library loads neither OpenVDB, netCDF nor OpenEXR
core=$(ldd "$R$P/lib/libvesuvius.so.0" 2>&1)
case $core in *openvdb* | *netcdf* | *OpenEXR* | *png* | *glfw*) fail "libvesuvius.so loads no OpenVDB, netCDF, OpenEXR" "$core" ;;
*libzstd*) pass "libvesuvius.so loads no OpenVDB, netCDF, OpenEXR" ;; *) fail "libvesuvius.so loads no OpenVDB, netCDF, OpenEXR" "$core" ;; esac
# a program over the other layers: convert and render, each
# through its own .pc, headers as <vesuvius/...>
cat > "$T/layers.c" <<'EOC'
#include <stdio.h>
#include <vesuvius/vsv_convert.h>
#include <vesuvius/vsv_render.h>
int main(void)
{
    vsv_proj p = {VSV_PROJ_LCC, 40, -100, 30, 60, 0};
    double lat, lon;
    vsv_render_opts o;
    vsv_source_opts so;
    vsv_render_opts_init(&o);
    vsv_source_opts_init(&so);
    if (vsv_proj_inverse(&p, 0, 0, &lat, &lon))
        return 1;
    /* (the default vertical grid: the model's own levels) */
    printf("%.1f %.1f %s %d %s\n", lat, lon, o.kind == VSV_RENDER_RAYCAST ? "raycast" : "?", so.vertical == VSV_VERT_NATIVE,
           vsv_plot_format("x.SVG") == VSV_PLOT_SVG ? "svg" : "?");
    return 0;
}
EOC
if cc $SANFLAGS -o "$T/layers" "$T/layers.c" $(pkg-config --cflags --libs vesuvius-convert vesuvius-render) > "$T/cc" 2>&1; then
    pass "a program over convert and render builds with their .pc files"
else
    fail "a program over convert and render builds with their .pc files" "$(head -c 400 "$T/cc")"
fi
expect "and runs: the projection's origin is (lat0, lon0)" 0 env LD_LIBRARY_PATH="$R$P/lib" "$T/layers"
has "and prints it (the plots' API too)" "$T/out" "40.0 -100.0 raycast 1 svg"
# the static archive, with the libraries the .pc names as private (shared ones:
# Debian's netCDF has no static HDF5 on the default path)
deps=$(pkg-config --print-requires-private vesuvius | awk '{print $1}')
private=$(sed -n 's/^Libs.private: //p' "$R$P/lib/pkgconfig/vesuvius.pc")
if cc $SANFLAGS -o "$T/hello-static" "$T/hello.c" $(pkg-config --cflags vesuvius) "$R$P/lib/libvesuvius.a" \
    $(pkg-config --libs $deps) $private > "$T/cc" 2>&1 &&
    "$T/hello-static" "$T/crop.vsv" > /dev/null; then
    pass "and statically (libvesuvius.a with the .pc's private requirements)"
else
    fail "and statically (libvesuvius.a with the .pc's private requirements)" "$(head -c 400 "$T/cc")"
fi
# every tool: --version names the tool, the project and the format
tools="vsv-pack vsv-info vsv-extract vsv-interp vsv-convert vsv-render vsv-export vsv-query vsv-plot"
[ "${VIEWER:-1}" = 1 ] && tools="$tools vsv-play"
for t in $tools; do
    v=$("$R$P/bin/$t" --version 2>&1)
    case $v in "$t (Vesuvius "*") format "[0-9]*.[0-9]*) pass "$t --version: $v" ;; *) fail "$t --version" "$v" ;; esac
done
# every tool's installed manual names every long option of its --help, as
# a whole name (\-\-time is not found in \-\-times nor \-\-time\-res)
end='([^a-z0-9\]|\\f|$)'
for t in $tools; do
    n=0 miss=""
    for o in $("$R$P/bin/$t" --help 2>&1 | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u); do
        n=$((n + 1))
        pat=$(printf '%s' "$o" | sed 's/-/\\\\-/g')
        grep -qE -- "$pat$end" "$R$P/share/man/man1/$t.1" 2> /dev/null || miss="$miss $o"
    done
    [ -z "$miss" ] && [ $n -ge 3 ] && pass "$t(1) names every option of --help ($n)" ||
        fail "$t(1) names every option of --help" "$n options; missing:$miss"
done
# the private helpers in lib/vesuvius/, found by the installed tools (the
# library's isolation of libhdf5 and OpenVDB; issue 18)
for h in vsv-nc-check vsv-vdb-reader vsv-nc-writer vsv-gshhg; do
    [ -x "$R$P/lib/vesuvius/$h" ] && pass "installed: lib/vesuvius/$h" || fail "installed: lib/vesuvius/$h" "missing"
done
expect "an installed tool finds its helper: a libhdf5 crash is an error" 1 "$R$P/bin/vsv-info" tests/corpus/netcdf/hdf5-segv.nc
has "naming the file" "$T/err" "tests/corpus/netcdf/hdf5-segv.nc: damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it"
# the installed transfer functions parse, block by block
expect "the installed transfer functions render" 0 "$R$P/bin/vsv-render" "$T/crop.vsv" -o "$T/tf.png" \
    --tf "$R$P/share/vesuvius/transfer-functions.tf" --size 64x48
# bash completion: options from --help, species from the file
if command -v bash > /dev/null; then
    out=$(PATH="$R$P/bin:$PATH" bash -c ". '$R$P/share/bash-completion/completions/vsv-render'
        COMP_WORDS=(vsv-render --mov); COMP_CWORD=1; _vsv_complete; echo \"\${COMPREPLY[*]}\"
        COMP_WORDS=(vsv-render '$T/crop.vsv' --species CLW:2,SN); COMP_CWORD=3; _vsv_complete; echo \"\${COMPREPLY[*]}\"")
    case $out in *--movie*CLW:2,SNOW*) pass "bash completion: options and species names" ;;
    *) fail "bash completion: options and species names" "$out" ;; esac
fi
make -s --no-print-directory B="$B" uninstall PREFIX=$P DESTDIR="$R" > "$T/log" 2>&1
left=$(find "$R" -type f | wc -l)
[ "$left" -eq 0 ] && pass "make uninstall removes every installed file" || fail "make uninstall removes every installed file" "$left left: $(find "$R" -type f | head -3)"
