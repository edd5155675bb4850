#!/usr/bin/env python3
"""make-bad.py — derives the damaged golden files in tests/golden/bad/ from
tests/golden/small.vsv, each with the message part a reader must report
(tests/golden/bad/EXPECTED). Run after regenerating small.vsv:
    VSV_REGEN_GOLDEN=1 build/tests/test_format_damage; python3 tests/golden/make-bad.py
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
cases.append(("bad-magic.vsv", flip(good, 1, 0x20), "not a .vsv file (no .vsv magic at byte 0)"))
cases.append(("truncated.vsv", good[:-500], "truncated: file has %d bytes, header says %d" % (len(good) - 500, len(good))))
cases.append(("header.vsv", flip(good, 20), "header checksum mismatch (bytes 0-127)"))
cases.append(("metadata.vsv", flip(good, 150), "metadata checksum mismatch (offset 128, %d bytes)" % meta_size))
cases.append(("toc.vsv", flip(good, toc_off + 30), "table of contents checksum mismatch (offset %d)" % toc_off))
cases.append(("end-marker.vsv", flip(good, len(good) - 1), "end marker damaged at offset %d" % (len(good) - 32)))
cases.append(("extra-bytes.vsv", good + b"\0" * 64, "64 unexpected bytes after the end marker (file %d bytes, header says %d)" % (len(good) + 64, len(good))))
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

# ---- valid checksums, invalid structure: each file's CRCs are recomputed
# after the change, so only the structure checks can catch it.
def crc32c(data, crc=0):
    crc ^= 0xFFFFFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 & -(crc & 1))
    return crc ^ 0xFFFFFFFF

def reseal(b, chunks=()):
    """Recomputes every CRC of file b (bytearray): the given chunks' index
    CRCs, then metadata, TOC, header and end marker."""
    for c in chunks:
        ib = struct.unpack_from("<I", b, c + 16)[0]
        struct.pack_into("<I", b, c + 28, crc32c(bytes(b[c + 32:c + 32 + ib]), crc32c(bytes(b[c:c + 28]))))
    msize, toff, tsize = struct.unpack_from("<Q", b, 32)[0], struct.unpack_from("<Q", b, 48)[0], struct.unpack_from("<Q", b, 56)[0]
    struct.pack_into("<I", b, 40, crc32c(bytes(b[128:128 + msize])))
    tcrc = crc32c(bytes(b[toff:toff + tsize]))
    struct.pack_into("<I", b, 64, tcrc)
    struct.pack_into("<I", b, 124, crc32c(bytes(b[0:124])))
    n = len(b)
    struct.pack_into("<QQI", b, n - 24, toff, n, tcrc)
    struct.pack_into("<I", b, n - 4, crc32c(bytes(b[n - 32:n - 4])))
    return bytes(b)

assert crc32c(b"123456789") == 0xE3069283
g = bytearray(good)
struct.pack_into("<q", g, toc_off + 24 + 16, toc[0][2])
cases.append(("s-toc-time.vsv", reseal(g), "table of contents entry 1: time does not increase"))
g = bytearray(good)
at = good.index(b"CLW", 128, 128 + meta_size)  # the first species' name in its VAR record
g[at] = 0xFF
cases.append(("s-name-utf8.vsv", reseal(g), "metadata: variable 0: its name, units or description is not UTF-8 text (or holds control characters)"))
g = bytearray(good)
struct.pack_into("<q", g, toc_off + 16, -2 ** 63)
cases.append(("s-toc-time-min.vsv", reseal(g), "table of contents entry 0: time -9223372036854775808 is outside the years 1..9999"))
g = bytearray(good)
struct.pack_into("<Q", g, toc_off + 24, toc[1][0] + 64)
cases.append(("s-toc-entry.vsv", reseal(g), "table of contents entry 1: chunk at %d (%d bytes) out of place" % (toc[1][0] + 64, toc[1][1])))
g = bytearray(good)
struct.pack_into("<I", g, 72, nx + 1)
cases.append(("s-header-dims.vsv", reseal(g), "header dimensions disagree with the metadata"))
g = bytearray(good)
struct.pack_into("<Q", g, 32, meta_size - 4)
cases.append(("s-meta-size.vsv", reseal(g), "metadata section (offset 128, %d bytes) outside the file or not a multiple of 8" % (meta_size - 4)))
# chunk 1's first stored brick: its payload offset moved by 64
g = bytearray(good)
e = c1 + 32 + s * S + O + 24 * b
struct.pack_into("<Q", g, e + 8, struct.unpack_from("<Q", g, e + 8)[0] + 64)
cases.append(("s-brick-offset.vsv", reseal(g, [c1]), "chunk 1, species %d, brick %d (offset %d): invalid brick entry" % (s, b, e)))
# chunk 2 claims to be step 7
g = bytearray(good)
struct.pack_into("<I", g, c2 + 4, 7)
cases.append(("s-chunk-step.vsv", reseal(g, [c2]), "chunk 2 (offset %d): bad chunk header" % c2))
# an EMPTY brick of keyframe chunk 0 marked UNCHANGED
c0 = toc[0][0]
g = bytearray(good)
for sp in range(nspec):
    done = False
    for br in range(nb):
        e0 = c0 + 32 + sp * S + O + 24 * br
        if g[e0] == 0:
            g[e0] = 1
            done = True
            break
    if done:
        break
cases.append(("s-keyframe-kind.vsv", reseal(g, [c0]), "chunk 0, species %d, brick %d (offset %d): invalid brick entry" % (sp, br, e0)))
# the octree's level-0 maximum of chunk 1's stored brick off by one
g = bytearray(good)
on = c1 + 32 + s * S + 4 * b + 2
struct.pack_into("<H", g, on, struct.unpack_from("<H", g, on)[0] ^ 1)
cases.append(("s-octree.vsv", reseal(g, [c1]), "chunk 1, species %d, brick %d: decoded codes disagree with the octree" % (s, b)))
# chunk 1's first stored brick with a reserved byte set: in the u8[3] after
# the kind, then in the u32 at entry byte 20
for name, at in (("s-brick-reserved.vsv", 2), ("s-brick-reserved20.vsv", 21)):
    g = bytearray(good)
    g[e + at] = 1
    cases.append((name, reseal(g, [c1]), "chunk 1, species %d, brick %d (offset %d): invalid brick entry" % (s, b, e)))
# an EMPTY brick of chunk 0 with a payload CRC (0 unless a kind with a payload)
g = bytearray(good)
e0 = c0 + 32 + sp * S + O + 24 * br
assert g[e0] == 0
struct.pack_into("<I", g, e0 + 4, 0x1234)
cases.append(("s-empty-crc.vsv", reseal(g, [c0]), "chunk 0, species %d, brick %d (offset %d): invalid brick entry" % (sp, br, e0)))
# the first node above level 0 of chunk 1's species 0: its minimum off by one
assert nb > 1
g = bytearray(good)
on = c1 + 32 + 4 * nb
struct.pack_into("<H", g, on, struct.unpack_from("<H", g, on)[0] ^ 1)
cases.append(("s-octree-upper.vsv", reseal(g, [c1]), "chunk 1, species 0: octree node %d disagrees with its children" % nb))
# header fields out of range, CRCs intact
g = bytearray(good)
struct.pack_into("<H", g, 8, 9)
cases.append(("s-version.vsv", reseal(g), "format version 9.%d is not readable by this version (1.x to 4.x)" % struct.unpack_from("<H", good, 10)[0]))
g = bytearray(good)
g[100] = 1
cases.append(("s-reserved.vsv", reseal(g), "header has unknown size or non-zero reserved fields"))
g = bytearray(good)
struct.pack_into("<I", g, 84, 12)
cases.append(("s-brick-size.vsv", reseal(g), "header: brick 12, keyframe %d or codec %d invalid" % (u32(88), u32(92))))
# the header's step count one more than the table of contents holds
g = bytearray(good)
struct.pack_into("<I", g, 44, nsteps + 1)
cases.append(("s-toc-steps.vsv", reseal(g), "table of contents (offset %d, %d steps) does not fit the file" % (toc_off, nsteps + 1)))
# the end marker's file size one block larger, its own CRC recomputed
g = bytearray(reseal(bytearray(good)))
n = len(g)
struct.pack_into("<Q", g, n - 16, n + 64)
struct.pack_into("<I", g, n - 4, crc32c(bytes(g[n - 32:n - 4])))
cases.append(("s-end-size.vsv", bytes(g), "end marker disagrees with the header"))
# the last chunk 64 bytes shorter in the table of contents: a gap before it
g = bytearray(good)
last = toc_off + 24 * (nsteps - 1)
struct.pack_into("<Q", g, last + 8, toc[nsteps - 1][1] - 64)
cases.append(("s-gap.vsv", reseal(g), "64 unaccounted bytes before the table of contents"))
# the first metadata record's length past the end of the metadata
g = bytearray(good)
struct.pack_into("<I", g, 132, meta_size)
cases.append(("s-meta-record.vsv", reseal(g), "metadata: metadata record 'GRID' at byte 0 overruns the section"))
# The table of contents inside the metadata (issue 18, found by fuzzing):
# one step; an unknown metadata record covers everything up to the TOC,
# whose last 8 bytes (the time) double as the END record; chunk 0 "starts"
# past the end of the file with a size that wraps back to the TOC.
recs = good[128:128 + meta_size - 8]
assert good[128 + meta_size - 8:128 + meta_size] == b"END \0\0\0\0"
R = 128 + len(recs)
n = R + 8 + 8 + 56
n += (56 - n) % 64
g = bytearray(n)
g[0:128] = good[0:128]
g[128:R] = recs
toff = n - 56
struct.pack_into("<4sI", g, R, b"XPAD", n - 48 - R)
struct.pack_into("<QQ", g, toff, n + 8, (toff - (n + 8)) % (1 << 64))
g[n - 40:n - 32] = b"END \0\0\0\0"
g[n - 32:n - 24] = good[len(good) - 32:len(good) - 24]
struct.pack_into("<Q", g, 16, n)
struct.pack_into("<Q", g, 32, n - 32 - 128)
struct.pack_into("<I", g, 44, 1)
struct.pack_into("<QQ", g, 48, toff, 24)
cases.append(("s-toc-in-meta.vsv", reseal(g), "table of contents (offset %d) overlaps the metadata and its padding (offsets 128 to %d)" % (toff, n + 8)))

with open(os.path.join(out, "EXPECTED"), "w") as f:
    f.write("# file<TAB>the exact message vsv-info --check prints after \"vsv-info: FILE: \"\n")
    for name, data, msg in cases:
        open(os.path.join(out, name), "wb").write(data)
        f.write("%s\t%s\n" % (name, msg))
print("wrote %d damaged files" % len(cases))
