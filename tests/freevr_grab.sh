# freevr_grab.sh: sourced by the FreeVR tests' session scripts.
# grab DUMP COPY: a hard link to a window's dump, a snapshot that needs no
# disk space. The stand-in renames each new dump over the old one, and
# link() fails (ENOENT) when a rename replaces the name between its lookup
# and the link, which at dozens of frames a second happens: tried again.
grab() {
    _g=0
    until ln -f "$1" "$2" 2> /dev/null; do
        [ -e "$1" ] || return 1
        _g=$((_g + 1))
        [ $_g -lt 100 ] || return 1
    done
}
