#!/bin/sh
# cli_deps.sh — the dependency step a fresh machine goes through (issue #17),
# without removing packages: stand-ins for dpkg-query, apt-get, id and
# pkg-config on PATH report two packages absent and record what would be
# installed. As a user, `make demo` prints the one apt-get line naming just
# those packages and stops before building anything; as root, tools/deps.sh
# --install runs apt-get install for exactly them; a plain `make` whose
# pkg-config lacks netCDF stops with a message naming it and the apt-get line.
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-deps.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
mkdir "$T/bin"
cat > "$T/bin/dpkg-query" <<'EOS'
#!/bin/sh
for a; do case $a in libglfw3-dev | libnetcdf-dev) exit 1 ;; esac; done
exec /usr/bin/dpkg-query "$@"
EOS
cat > "$T/bin/apt-get" <<EOS
#!/bin/sh
echo "apt-get \$*" >> "$T/apt.log"
EOS
cat > "$T/bin/id" <<'EOS'
#!/bin/sh
[ "$1" = -u ] && { echo "$FAKE_UID"; exit 0; }
exec /usr/bin/id "$@"
EOS
cat > "$T/bin/pkg-config" <<'EOS'
#!/bin/sh
[ "$1" = --exists ] && for a; do [ "$a" = netcdf ] && exit 1; done
exec /usr/bin/pkg-config "$@"
EOS
chmod +x "$T/bin"/*
mkdir "$T/bin2" # the same without the dpkg-query stand-in: nothing missing
ln -s "$T/bin/apt-get" "$T/bin/id" "$T/bin2/"
P="$T/bin:$PATH"
# the make of `make test` hands its flags down: these makes start afresh
unset MAKEFLAGS MFLAGS MAKELEVEL

# a user: the line to run, nothing built, nothing installed
expect "make demo as a user stops at the dependency step" 2 \
    env PATH="$P" FAKE_UID=1000 make --no-print-directory demo B="$T/build"
has "it names the missing packages in one apt-get line" "$T/err" "sudo apt-get install -y libnetcdf-dev libglfw3-dev"
if [ -e "$T/build" ] || [ -e "$T/apt.log" ]; then
    fail "nothing built or installed before the step" "$(ls "$T")"
else
    pass "nothing built or installed before the step"
fi

# root: apt-get installs exactly the missing ones
expect "deps.sh --install as root" 0 env PATH="$P" FAKE_UID=0 sh tools/deps.sh --install
has "apt-get is asked for the missing packages" "$T/apt.log" "apt-get install -y -qq libnetcdf-dev libglfw3-dev"
has "and the lists refreshed first" "$T/apt.log" "apt-get update -qq"
rm -f "$T/apt.log"

# nothing missing: silent, nothing run
expect "deps.sh --install with everything there" 0 env PATH="$T/bin2:$PATH" FAKE_UID=0 sh tools/deps.sh --install
if [ -e "$T/apt.log" ]; then fail "no apt-get when nothing is missing" "$(cat "$T/apt.log")"; else pass "no apt-get when nothing is missing"; fi

# a build goal, pkg-config without netCDF: the library named, the line given
expect "make with netCDF missing stops" 2 env PATH="$P" make --no-print-directory -n all B="$T/build"
has "the message names the missing library" "$T/err" "missing libraries (pkg-config): netcdf;"
has "and gives the apt-get line" "$T/err" "sudo apt-get install -y build-essential"
