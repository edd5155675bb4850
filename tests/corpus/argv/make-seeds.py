#!/usr/bin/python3
"""make-seeds.py — writes the seeds of the argv fuzz target
(tests/fuzz_argv.c) and its libFuzzer dictionary (tests/fuzz_argv.dict:
every long option in the tools' option tables, the short ones, the
fixtures' names, species, times and edge values; each word ends with the
NUL that ends an argument): one file per typical command line per tool, a first
byte naming the tool (the harness's table order), then the arguments, each
ended by a NUL. The names are the harness's fixtures (a.vsv: the golden
small.vsv; b.vsv: the MM5 sample converted; m.mm5, w.nc (WRF), c.uamiv
(CAMx), q.nc (CMAQ), t.tf, s.vsvs (a field stream)). Images stay small:
each seed runs in `make test`. Run from the top of the tree:
    /usr/bin/python3 tests/corpus/argv/make-seeds.py"""
import os
import re

TOOLS = ["vsv-info", "vsv-query", "vsv-render", "vsv-plot", "vsv-export",
         "vsv-convert", "vsv-extract", "vsv-interp", "vsv-pack"]

SEEDS = {
    "info-text": ("vsv-info", "a.vsv"),
    "info-json-field": ("vsv-info", "--json", "-f", "species.CLW.max_abs_error", "a.vsv"),
    "info-check-stats": ("vsv-info", "--check", "--stats", "b.vsv"),
    "info-models": ("vsv-info", "m.mm5", "w.nc", "c.uamiv", "q.nc"),
    "query-cell": ("vsv-query", "a.vsv", "--cell", "3,4,2", "--times", "1:3"),
    "query-at-json": ("vsv-query", "a.vsv", "--at", "31.5,-106,900", "--interp", "--json"),
    "query-profile-csv": ("vsv-query", "b.vsv", "--profile", "46.5,-124.6", "--csv", "-s", "CLW"),
    "render-png": ("vsv-render", "a.vsv", "-o", "o.png", "--size", "64x48", "-t", "2", "--threads", "1"),
    "render-seq": ("vsv-render", "a.vsv", "-o", "f%02d.png", "--size", "40x30", "--times", "0:1",
                   "--view", "plan", "--no-annotate", "-r", "shearwarp"),
    "render-exr-tf": ("vsv-render", "a.vsv", "-o", "o.exr", "--size", "32x32", "--tf", "t.tf", "--light",
                      "--slice", "z=900", "--range", "CLW:0:0.001", "--log", "O3", "--stereo"),
    "render-movie": ("vsv-render", "a.vsv", "--movie", "o.mp4", "--size", "32x24", "--fps", "5"),
    "plot-section": ("vsv-plot", "a.vsv", "-o", "p.png", "--section", "30.5,-107:32.5,-104.5", "--size", "200x150"),
    "plot-series": ("vsv-plot", "a.vsv", "-o", "p.svg", "--series", "31.5,-106", "--csv", "p.csv", "--log"),
    "plot-profile": ("vsv-plot", "b.vsv", "-o", "p.pdf", "--profile", "46.5,-124.6", "--title", "T"),
    "export-vdb": ("vsv-export", "a.vsv", "--vdb", "o_%04d.vdb", "--times", "0:1", "-s", "CLW"),
    "export-netcdf": ("vsv-export", "a.vsv", "--netcdf", "o.nc", "-t", "1"),
    "convert-mm5": ("vsv-convert", "m.mm5", "-o", "o.vsv", "-q", "--bits", "8"),
    "convert-res": ("vsv-convert", "m.mm5", "-o", "o.vsv", "-r", "30m", "--times", "1:3", "--brick", "8"),
    "convert-wrf": ("vsv-convert", "w.nc", "-o", "o.vsv", "--vars", "QVAPOR,T", "--scale", "log",
                    "--codec", "zstd:5"),
    "convert-camx": ("vsv-convert", "c.uamiv", "-o", "o.vsv", "--range", "0:1", "--keyframe", "1"),
    "convert-cmaq": ("vsv-convert", "q.nc", "-o", "o.vsv", "--threshold", "1e-9"),
    "extract-list": ("vsv-extract", "--list", "m.mm5", "w.nc"),
    "extract-winds": ("vsv-extract", "-w", "-t", "0:1", "m.mm5"),
    "interp-stream": ("vsv-interp", "--time-res", "30m", "s.vsvs"),
    "interp-advect": ("vsv-interp", "-r", "1h", "-i", "advect", "-j", "1", "s.vsvs"),
    "pack-stream": ("vsv-pack", "-o", "o.vsv", "--bits", "16", "s.vsvs"),
    "pack-stdin": ("vsv-pack", "-o", "o.vsv"),
}

here = os.path.dirname(os.path.abspath(__file__))
for name, (tool, *args) in SEEDS.items():
    with open(os.path.join(here, name), "wb") as f:
        f.write(bytes([TOOLS.index(tool)]) + b"".join(a.encode() + b"\0" for a in args))

# the dictionary
SOURCES = ["convert/vsv-info.c", "convert/vsv_convert_cli.c", "convert/vsv-extract.c", "convert/vsv-interp.c",
           "format/vsv-query.c", "format/vsv-pack.c", "interop/vsv-export.c", "render/vsv-render.c",
           "render/vsv-plot.c", "cli/vsv_cli.h", "convert/vsv_convert.h", "convert/vsv_source_reader.h",
           "convert/vsv_convert_cli.h"]
top = os.path.dirname(os.path.dirname(os.path.dirname(here)))
longs = set()
for src in SOURCES:
    path = os.path.join(top, src)
    if os.path.exists(path):
        text = open(path).read()
        longs |= set(re.findall(r'\{"([a-z][a-z0-9-]*)",\s*(?:no|required|optional)_argument', text))
EXTRA = ["-o", "-t", "-s", "-q", "-h", "-V", "-r", "-i", "-v", "-j", "-f", "-c", "-x", "-l", "-w",
         "a.vsv", "b.vsv", "m.mm5", "w.nc", "c.uamiv", "q.nc", "t.tf", "s.vsvs", "o.vsv", "o.png", "o.exr",
         "f%04d.png", "o.mp4", "o.nc", "p.svg", "p.pdf", "p.csv", "-",
         "CLW", "T", "O3", "QVAPOR", "NO2", "PM25", "Q",
         "0", "1", "-1", ":", "0:1", "1:", "2001-09-09T02:06:40Z", "1995-10-24T01:00Z", "10m", "1h", "30s", "1d",
         "PT1H30M", "1e308", "-1e308", "nan", "inf", "99999999999", "-9223372036854775808", "9223372036854775807",
         "4294967296", "2147483648", "64x48", "0x0", "16384x16384", "1,2,3", "31.5,-106", "46.5,-124.6", "z=900",
         "lat=31", "lon=-106", "line=31,-107:32,-105", "linear", "log", "advect", "wind", "zstd:3", "none", "plan",
         "south", "west", "oblique", "raycast", "shearwarp", "viridis", "clouds", "time,bars", "%s%n", "%d", "%%"]
with open(os.path.join(top, "tests/fuzz_argv.dict"), "w") as f:
    f.write("# fuzz_argv.dict — the argv fuzz target's libFuzzer dictionary, written by\n"
            "# tests/corpus/argv/make-seeds.py (run it again when an option is added)\n")
    for w in sorted("--" + o for o in longs) + EXTRA:
        f.write('"%s\\x00"\n' % w.replace("\\", "\\\\").replace('"', '\\"'))
