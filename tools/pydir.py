"""pydir.py PREFIX — where the running interpreter looks for modules installed
under PREFIX (the Makefile's PYDIR), asked of the interpreter itself.

Debian's python3 adds two schemes of its own: 'deb_system' for packages of
the distribution under /usr (/usr/lib/python3/dist-packages) and
'posix_local' for local installs under /usr/local
(/usr/local/lib/python3.X/dist-packages); both folders are on its sys.path.
Any other prefix takes the upstream 'posix_prefix' layout
(PREFIX/lib/python3.X/site-packages), which needs PYTHONPATH.
"""
import os
import sys
import sysconfig


def platlib(prefix):
    prefix = prefix.rstrip("/") or "/"
    base = sys.base_prefix
    schemes = sysconfig.get_scheme_names()
    if prefix == base and "deb_system" in schemes:
        scheme = "deb_system"
    elif prefix == base.rstrip("/") + "/local" and "posix_local" in schemes:
        # posix_local's paths are {base}/local/...: base stays the interpreter's
        scheme, prefix = "posix_local", base
    else:
        scheme = "posix_prefix"
    path = sysconfig.get_path("platlib", scheme, vars={"base": prefix, "platbase": prefix})
    return "/" + os.path.normpath(path).lstrip("/")


if __name__ == "__main__":
    if len(sys.argv) != 2 or not sys.argv[1].startswith("/"):
        sys.exit("usage: pydir.py PREFIX (an absolute path)")
    print(platlib(sys.argv[1]))
