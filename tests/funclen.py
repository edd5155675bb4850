#!/usr/bin/env python3
"""funclen.py LIMIT: lists the C and C++ functions of the repository (git
ls-files) longer than LIMIT lines, from the first line of the signature to
the closing brace, as "LINES FILE NAME"; exit 1 if there is one. Reads the
layout .clang-format gives: a function's braces alone in column 0."""
import re
import subprocess
import sys

limit = int(sys.argv[1])
files = subprocess.run(["git", "ls-files", "*.c", "*.cc"], capture_output=True, text=True).stdout.split()
long = []
for path in files:
    with open(path, errors="replace") as fh:
        lines = fh.read().split("\n")
    start = None
    for i, line in enumerate(lines):
        if line == "{" and i > 0:
            j = i - 1  # back to the signature's first line
            while j > 0 and lines[j][:1] in (" ", "\t"):
                j -= 1
            start = j
        elif line.startswith("}") and not line.startswith("};") and start is not None:
            m = re.search(r"(\w+)\s*\(", lines[start])
            n = i - start + 1
            if n > limit:
                long.append((n, path, m.group(1) if m else lines[start][:40]))
            start = None
for n, path, name in sorted(long, reverse=True):
    print(n, path, name)
sys.exit(1 if long else 0)
