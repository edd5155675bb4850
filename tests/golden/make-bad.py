#!/usr/bin/env python3
"""make-bad.py — derives the damaged golden files in tests/golden/bad/ from
tests/golden/small.vsv, each with the message part a reader must report
(tests/golden/bad/EXPECTED). Run after regenerating small.vsv:
    VSV_REGEN_GOLDEN=1 build/tests/test_format; python3 tests/golden/make-bad.py
Offsets follow format/SPEC.md."""
import os, struct

here = os.path.dirname(os.path.abspath(__file__))
good = open(os.path.join(here, "small.vsv"), "rb").read()
out = os.path.join(here, "bad")
os.makedirs(out, exist_ok=True)

u32 = lambda o: struct.unpack_from("<I", good, o)[0]
u64 = lambda o: struct.unpack_from("<Q", good, o)[0]
meta_size, toc_off, nsteps = u64(32), u64(48), u32(44)
toc = [struct.unpack_from("<QQq", good, toc_off + 24 * t) for t in range(nsteps)]
nspec, nx, ny, nz, B = u32(68), u32(72), u32(76), u32(80), u32(84)

def nodes():
    d = [(nx + B - 1) // B, (ny + B - 1) // B, (nz + B - 1) // B]
    n = 0
    while True:
        n += d[0] * d[1] * d[2]
        if d == [1, 1, 1]:
            return n
        d = [(x + 1) // 2 for x in d]

nb = ((nx + B - 1) // B) * ((ny + B - 1) // B) * ((nz + B - 1) // B)
O = (4 * nodes() + 7) // 8 * 8
S = O + 24 * nb

def flip(data, at, bit=1):
    b = bytearray(data)
    b[at] ^= bit
    return bytes(b)

cases = []
cases.append(("bad-magic.vsv", flip(good, 1, 0x20), "not a .vsv file"))
cases.append(("truncated.vsv", good[:-500], "truncated: file has %d bytes, header says %d" % (len(good) - 500, len(good))))
cases.append(("header.vsv", flip(good, 20), "header checksum mismatch"))
cases.append(("metadata.vsv", flip(good, 150), "metadata checksum mismatch"))
cases.append(("toc.vsv", flip(good, toc_off + 30), "table of contents checksum mismatch"))
cases.append(("end-marker.vsv", flip(good, len(good) - 1), "end marker damaged"))
cases.append(("extra-bytes.vsv", good + b"\0" * 64, "unexpected bytes after the end marker"))
# chunk 2's index
c2 = toc[2][0]
cases.append(("index.vsv", flip(good, c2 + 40), "chunk 2 (offset %d): index checksum mismatch" % c2))
# the first stored payload of chunk 1
c1 = toc[1][0]
found = None
for s in range(nspec):
    for b in range(nb):
        e = c1 + 32 + s * S + O + 24 * b
        if good[e] in (2, 3):
            found = (s, b, c1 + struct.unpack_from("<Q", good, e + 8)[0])
            break
    if found:
        break
s, b, p = found
cases.append(("payload.vsv", flip(good, p + 3), "chunk 1, species %d, brick %d (offset %d): payload checksum mismatch" % (s, b, p)))
# padding between the metadata and chunk 0
pad = 128 + meta_size
if pad < toc[0][0]:
    cases.append(("padding.vsv", flip(good, pad), "non-zero padding after the metadata at offset %d" % pad))

with open(os.path.join(out, "EXPECTED"), "w") as f:
    f.write("# file<TAB>part of the message vsv-info --check must print\n")
    for name, data, msg in cases:
        open(os.path.join(out, name), "wb").write(data)
        f.write("%s\t%s\n" % (name, msg))
print("wrote %d damaged files" % len(cases))
