#!/usr/bin/env python3
"""svgtext.py FILE.svg: what a plot says, read back from its SVG with
xml.etree (tests/cli_plot.sh). Prints "size W H" (the root's width and
height), "images N" (embedded raster images), "paths N", then one line per
<text> element in document order: its class, a tab, its text. Exit 1 (and
the parser's message) when the file is not well-formed XML or not SVG."""
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
try:
    root = ET.parse(sys.argv[1]).getroot()
except (ET.ParseError, OSError) as e:
    print("not XML: %s" % e, file=sys.stderr)
    sys.exit(1)
if root.tag != SVG + "svg":
    print("not SVG: root %s" % root.tag, file=sys.stderr)
    sys.exit(1)
print("size", root.get("width"), root.get("height"))
print("images", sum(1 for _ in root.iter(SVG + "image")))
print("paths", sum(1 for _ in root.iter(SVG + "path")))
for e in root.iter(SVG + "text"):
    print("%s\t%s" % (e.get("class", ""), "".join(e.itertext())))
