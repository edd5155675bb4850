#!/bin/sh
# deps.sh — the Debian packages Vesuvius needs to build and test.
#   --names    print them
#   --install  install the missing ones (as root), or print the exact apt-get line
#   --install-test  the same, with what only `make test` needs (clang-format-14:
#              the layout check runs it); --names prints both lists
#   --bench    print the packages only `make bench` needs (its peers), and
#              --install-bench installs those (CI needs neither)
#   --fuzz     the same for `make fuzz`: Debian 12's clang, whose libFuzzer and
#              sanitizer runtimes are in libclang-rt-14-dev (--install-fuzz)
#   --deb      the same for `make deb` and `make test-deb`: Debian's packaging
#              tools (dpkg-buildpackage, debhelper, dh-python, lintian) and
#              man-db for the installed pages (--install-deb)
set -eu
PKGS="build-essential pkg-config udunits-bin python3 python3-dev python3-numpy python3-scipy python3-xarray python3-netcdf4 python3-pyproj bc libopenmpi-dev openmpi-bin libzstd-dev zstd libgeographiclib-dev libnetcdf-dev netcdf-bin libpng-dev libopenexr-dev libglfw3-dev libgl-dev libepoxy-dev libegl-dev libegl-mesa0 libfreetype-dev libfontconfig-dev libcairo2-dev fonts-dejavu-core gmt-gshhg-low xvfb xauth xdotool libx11-dev libxi-dev libopenvdb-dev libboost-dev libopenvdb-tools ffmpeg procps strace libcurl4-gnutls-dev lighttpd"
TEST_PKGS="clang-format-14 python3-hypothesis"
BENCH_PKGS="python3-vtk9 libvolpack1-dev libzfp-dev"
FUZZ_PKGS="clang libclang-rt-14-dev"
DEB_PKGS="dpkg-dev debhelper dh-python lintian man-db"
case "${1:-}" in --bench | --install-bench) [ "$1" = --bench ] && { echo $BENCH_PKGS; exit 0; }
    PKGS=$BENCH_PKGS; set -- --install ;; esac
case "${1:-}" in --fuzz | --install-fuzz) [ "$1" = --fuzz ] && { echo $FUZZ_PKGS; exit 0; }
    PKGS=$FUZZ_PKGS; set -- --install ;; esac
case "${1:-}" in --deb | --install-deb) [ "$1" = --deb ] && { echo $DEB_PKGS; exit 0; }
    PKGS=$DEB_PKGS; set -- --install ;; esac
case "${1:-}" in --names | --install-test) PKGS="$PKGS $TEST_PKGS" ;; esac
[ "${1:-}" = --install-test ] && set -- --install
missing=""
for p in $PKGS; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
case "${1:-}" in
--names) echo $PKGS ;;
--install)
    [ -z "$missing" ] && exit 0
    if [ "$(id -u)" = 0 ]; then
        echo "installing:$missing" >&2
        apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >&2
    else
        echo "missing packages; run as root:" >&2
        echo "  sudo apt-get install -y$missing" >&2
        exit 1
    fi ;;
*) echo "usage: deps.sh --names | --install | --install-test | --bench | --install-bench | --fuzz | --install-fuzz | --deb | --install-deb" >&2; exit 2 ;;
esac
