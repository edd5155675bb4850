#!/usr/bin/python3
"""freevr_shot.py - what a FreeVR stand-in window dump (PPM, see
tests/freevr-standin/freevr_render.c) shows, for tests/cli_freevr.sh.

  freevr_shot.py scene FILE.ppm      the share of pixels of the rendered scene
                                     (terrain: green above blue), 0..1
  freevr_shot.py shown FILE.ppm      the share of pixels that are not the
                                     background (the most common colour), 0..1
  freevr_shot.py centre FILE.ppm     the mean x and y (pixels) of those
  freevr_shot.py eyes dualvp|anaglyphic FILE.ppm
                                     a stereo frame's two eyes (the window's
                                     halves; the red and the green channel):
                                     the share of each that is not background,
                                     and whether they differ ("same"/"differ")
  freevr_shot.py magenta FILE.ppm    the share of magenta pixels (an isosurface
                                     drawn #ff00ff: nothing else is), 0..1
  freevr_shot.py frame FILE.ppm      the frame number the stand-in wrote
  freevr_shot.py same A.ppm B.ppm    exit 0 when the pixels are identical
  freevr_shot.py png OUT.png A.ppm... the dumps side by side in one PNG

The background (slate blue), the status text (grey on a dark box) and the
simulator's own drawing (grey lines, a small brown cube) are not scene: a
wall that shows none of the volume scores near 0."""
import struct
import sys
import zlib


def read(path):
    data = open(path, 'rb').read()
    fields, i, frame = [], 0, -1
    while len(fields) < 4:
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b'#':
            end = data.index(b'\n', i)
            words = data[i + 1:end].split()
            if len(words) == 2 and words[0] == b'frame':
                frame = int(words[1])
            i = end
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    w, h = int(fields[1]), int(fields[2])
    return w, h, frame, data[i + 1:i + 1 + w * h * 3]


def png(out, paths):
    shots = [read(p) for p in paths]
    height = max(s[1] for s in shots)
    width = sum(s[0] for s in shots) + 4 * (len(shots) - 1)
    rows = []
    for y in range(height):
        row = b'\0'
        for k, (w, h, _, px) in enumerate(shots):
            row += px[y * w * 3:(y + 1) * w * 3] if y < h else bytes(w * 3)
            row += b'\xff' * 12 if k + 1 < len(shots) else b''
        rows.append(row)

    def chunk(kind, data):
        return (struct.pack('>I', len(data)) + kind + data +
                struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff))
    with open(out, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0)) +
                chunk(b'IDAT', zlib.compress(b''.join(rows))) + chunk(b'IEND', b''))


def main():
    what = sys.argv[1]
    if what == 'scene':
        w, h, _, px = read(sys.argv[2])
        g, b = px[1::3], px[2::3]
        print('%.4f' % (sum(1 for k in range(w * h) if g[k] > b[k] + 10) / (w * h)))
    elif what == 'magenta':
        w, h, _, px = read(sys.argv[2])
        r, g, b = px[0::3], px[1::3], px[2::3]
        print('%.4f' % (sum(1 for k in range(w * h) if r[k] > 60 and b[k] > 60 and g[k] < 0.6 * min(r[k], b[k])) /
                        (w * h)))
    elif what in ('shown', 'centre'):
        w, h, _, px = read(sys.argv[2])
        counts = {}
        for k in range(0, w * h * 3, 3):
            counts[px[k:k + 3]] = counts.get(px[k:k + 3], 0) + 1
        bg = max(counts, key=counts.get)
        far = [k for k in range(w * h) if sum(abs(px[3 * k + i] - bg[i]) for i in range(3)) > 24]
        if what == 'shown':
            print('%.4f' % (len(far) / (w * h)))
        elif far:
            print('%.2f %.2f' % (sum(k % w for k in far) / len(far), sum(k // w for k in far) / len(far)))
    elif what == 'eyes':
        w, h, _, px = read(sys.argv[3])
        if sys.argv[2] == 'dualvp':
            half = w // 2
            eyes = [[px[3 * (y * w + x + o):3 * (y * w + x + o) + 3] for y in range(h) for x in range(half)]
                    for o in (0, half)]
        else:
            eyes = [[px[3 * k + c:3 * k + c + 1] for k in range(w * h)] for c in (0, 1)]
        out = []
        for e in eyes:
            counts = {}
            for v in e:
                counts[v] = counts.get(v, 0) + 1
            bg = max(counts, key=counts.get)
            out.append(sum(n for v, n in counts.items() if sum(abs(v[i] - bg[i]) for i in range(len(v))) > 24)
                       / len(e))
        print('%.4f %.4f %s' % (out[0], out[1], 'same' if eyes[0] == eyes[1] else 'differ'))
    elif what == 'frame':
        print(read(sys.argv[2])[2])
    elif what == 'png':
        png(sys.argv[2], sys.argv[3:])
    elif what == 'same':
        return 0 if read(sys.argv[2])[3] == read(sys.argv[3])[3] else 1
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


sys.exit(main())
