#!/bin/sh
# cli_iso.sh — vsv-export --iso and vsv-render --iso: an isosurface of the bundled MM5 sample's
# cloud water as binary PLY and glTF 2.0 (headers and JSON that parse,
# accessor counts, min and max that match the data, indices in range, unit
# normals, coordinates in the grid's projected frame), and bad arguments
# refused with "vsv-export: ..." and nothing written. Prints PASS/FAIL lines.
B=${B:-build}
SHARED=${SHARED:-../shared}
PYTHON=${PYTHON:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/vsv-cli-iso.XXXXXX")
trap 'rm -rf "$T"' EXIT
. tests/cli_lib.sh
CROP=samples/mm5/MMOUT_DOMAIN1_CROP

"$B/vsv-convert" -q "$CROP" -o "$T/a.vsv" || { fail "convert the MM5 sample" "exit $?"; exit 0; }
expect "vsv-export --help exits 0" 0 "$B/vsv-export" --help
has "--help names --iso" "$T/out" "--iso S:V[:COLOUR]"

expect "--iso CLW:5e-5 --ply at step 1" 0 "$B/vsv-export" "$T/a.vsv" --iso CLW:5e-5:cyan --ply "$T/c.ply" -t 1
has "it says how many triangles" "$T/err" "c.ply: "
expect "--iso CLW:5e-5 --gltf at step 1" 0 "$B/vsv-export" -q "$T/a.vsv" --iso CLW:5e-5:cyan --gltf "$T/c.gltf" -t 1
[ -s "$T/err" ] && fail "-q: nothing on stderr" "$(head -c 200 "$T/err")" || pass "-q: nothing on stderr"
ls "$T" | grep -q tmp && fail "no temporary left" "$(ls "$T")" || pass "no temporary left"

# the grid's projected box (cell centres) and heights, to check coordinates
if "$PYTHON" - "$T/c.ply" "$T/c.gltf" > "$T/py" 2>&1 <<'PY'
import base64, json, math, struct, sys
x0, y0, d, n = -2.4e6, 944000.0, 32000.0, 39
def inside(x, y, z):
    return (x0 - 1 <= x <= x0 + (n - 1) * d + 1 and y0 - 1 <= y <= y0 + (n - 1) * d + 1 and 0 < z < 20000)
# PLY: the header, then 27-byte vertices and 13-byte faces
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"end_header\n") + len(b"end_header\n")
head = raw[:end].decode("ascii").split("\n")
assert head[0] == "ply" and head[1] == "format binary_little_endian 1.0", head[:2]
nv = int([l for l in head if l.startswith("element vertex")][0].split()[2])
nf = int([l for l in head if l.startswith("element face")][0].split()[2])
assert nv > 0 and nf > 0 and len(raw) == end + 27 * nv + 13 * nf, (nv, nf, len(raw) - end)
V = [struct.unpack_from("<6f3B", raw, end + 27 * i) for i in range(nv)]
assert all(inside(*v[:3]) for v in V), "a PLY vertex outside the grid"
assert all(abs(math.sqrt(v[3] ** 2 + v[4] ** 2 + v[5] ** 2) - 1) < 1e-4 for v in V), "normals not unit"
assert all(max(abs(a - b) for a, b in zip(v[6:], (76.5, 204, 229.5))) <= 1 for v in V), "colour is not cyan"
F = [struct.unpack_from("<B3I", raw, end + 27 * nv + 13 * i) for i in range(nf)]
assert all(f[0] == 3 and max(f[1:]) < nv for f in F), "a face index out of range"
# glTF: JSON, the buffer embedded, accessors that match it
g = json.load(open(sys.argv[2]))
assert g["asset"]["version"] == "2.0"
acc, views, buf = g["accessors"], g["bufferViews"], g["buffers"][0]
data = base64.b64decode(buf["uri"].split(",", 1)[1])
assert len(data) == buf["byteLength"], "buffer length"
pos, nrm, idx = acc
assert pos["count"] == nv and nrm["count"] == nv and idx["count"] == 3 * nf, (pos["count"], idx["count"], nv, nf)
assert pos["componentType"] == 5126 and idx["componentType"] == 5125 and pos["type"] == "VEC3"
pv = views[pos["bufferView"]]
P = [struct.unpack_from("<3f", data, pv["byteOffset"] + 12 * i) for i in range(pos["count"])]
f32 = lambda x: struct.unpack("<f", struct.pack("<f", x))[0]  # glTF's min and max are float32 values
for a in range(3):
    assert min(p[a] for p in P) == f32(pos["min"][a]) and max(p[a] for p in P) == f32(pos["max"][a]), "min/max %d" % a
# glTF's axes: +Y up, +Z south: the PLY's (x, z, -y)
assert all(abs(p[0] - v[0]) < 1e-3 and p[1] == v[2] and p[2] == -v[1] for p, v in zip(P, V)), "axes"
iv = views[idx["bufferView"]]
I = struct.unpack_from("<%dI" % idx["count"], data, iv["byteOffset"])
assert max(I) < pos["count"] and list(I) == [i for f in F for i in f[1:]], "indices"
mat = g["materials"][g["meshes"][0]["primitives"][0]["material"]]
assert abs(mat["pbrMetallicRoughness"]["baseColorFactor"][2] - 0.9) < 1e-6
print("%d vertices, %d triangles" % (nv, nf))
PY
then pass "PLY and glTF parse and agree: $(cat "$T/py")"; else fail "PLY and glTF parse and agree" "$(tail -n 3 "$T/py")"; fi

# bad arguments: an error naming the tool, and nothing written
bad() { # NAME CODE TEXT ARGS...: exits CODE saying TEXT, writes no x.*
    n=$1 c=$2 t=$3; shift 3
    expect "$n exits $c" "$c" "$B/vsv-export" "$T/a.vsv" "$@"
    if head -n 1 "$T/err" | grep -q '^vsv-export: ' && grep -qF -- "$t" "$T/err"; then pass "$n: says 'vsv-export: ...$t'"
    else fail "$n: says 'vsv-export: ...$t'" "$(head -c 300 "$T/err")"; fi
    ls "$T" | grep -q '^x\.' && fail "$n: nothing written" "$(ls "$T")" || pass "$n: nothing written"
}
bad "an unknown species" 2 "--iso NOPE:1e-5: no species NOPE (the file has Q, CLW, RNW, ICE, SNOW, wind_east, wind_north, wind_up)" \
    --iso NOPE:1e-5 --ply "$T/x.ply"
bad "a value that is no number" 2 "--iso CLW:lots: the value must be a finite number" --iso CLW:lots --ply "$T/x.ply"
bad "no value" 2 "--iso CLW: expected SPECIES:VALUE[:COLOUR]" --iso CLW --ply "$T/x.ply"
bad "an infinite value" 2 "--iso CLW:inf: the value must be a finite number" --iso CLW:inf --gltf "$T/x.gltf"
bad "an unknown colour" 2 "--iso CLW:5e-5:mauve: colour mauve" --iso CLW:5e-5:mauve --ply "$T/x.ply"
bad "no output" 2 "--iso needs --ply OUT.ply or --gltf OUT.gltf" --iso CLW:5e-5
bad "both outputs" 2 "--ply and --gltf exclude each other" --iso CLW:5e-5 --ply "$T/x.ply" --gltf "$T/x.gltf"
bad "--ply without --iso" 2 "give --iso SPECIES:VALUE" --ply "$T/x.ply"
bad "--iso with --vdb" 2 "--iso takes one step" --iso CLW:5e-5 --ply "$T/x.ply" --vdb "$T/x.vdb"
bad "a value above the data" 1 "no surface: CLW = 1 kg/kg" --iso CLW:1 --ply "$T/x.ply"
bad "a step outside the file" 1 "--time 9: step 9 is out of range" --iso CLW:5e-5 --ply "$T/x.ply" -t 9
bad "a folder that is not there" 1 "$T/none/x.ply: cannot create" --iso CLW:5e-5 --ply "$T/none/x.ply"

# vsv-render --iso: the surface drawn, the same pixels from either renderer
# (such frames are raycast), and the same bad arguments refused
expect "vsv-render --iso (raycast)" 0 "$B/vsv-render" -q "$T/a.vsv" --iso CLW:5e-5:orange -t 1 --size 320x240 \
    --light -o "$T/rc.png"
expect "vsv-render --iso (shear-warp)" 0 "$B/vsv-render" -q "$T/a.vsv" --iso CLW:5e-5:orange -t 1 --size 320x240 \
    --light -r shearwarp -o "$T/sw.png"
same "the two renderers' pictures with an isosurface are the same" "$T/rc.png" "$T/sw.png"
# the GPU raycaster stops its rays at the same surfaces (EGL; llvmpipe here)
if "$B/vsv-render" -q "$T/a.vsv" --iso CLW:5e-5:orange -t 1 --size 320x240 --light -r gl -o "$T/gl.png" 2> "$T/gl.err"; then
    db=$("$PYTHON" tests/imgcmp.py "$T/gl.png" "$T/rc.png" 2> /dev/null | awk '{ print $2 }')
    if awk "BEGIN { exit !(${db:-0} >= 40) }"; then pass "--renderer gl draws it as the CPU does ($db dB)"
    else fail "--renderer gl draws it as the CPU does" "PSNR ${db:-none}"; fi
else
    pass "--renderer gl: skipped ($(head -c 120 "$T/gl.err"))"
fi
"$B/vsv-render" -q "$T/a.vsv" -t 1 --size 320x240 --light -o "$T/none.png"
cmp -s "$T/rc.png" "$T/none.png" && fail "the isosurface shows" "the picture is the one without it" ||
    pass "the isosurface shows"
expect "vsv-render --iso NOPE:1 exits 2" 2 "$B/vsv-render" -q "$T/a.vsv" --iso NOPE:1 -o "$T/x.png"
has "naming the file's species" "$T/err" "vsv-render: --iso NOPE:1: no species NOPE (the file has Q, CLW"
[ -e "$T/x.png" ] && fail "vsv-render: nothing written" "x.png" || pass "vsv-render: nothing written"
# a value no cell reaches (kg/kg given as g/kg): exit 1, the species' range named
expect "vsv-render --iso beyond the data exits 1" 1 "$B/vsv-render" -q "$T/a.vsv" --iso CLW:0.05 -o "$T/x.png"
has "... no surface, the range named" "$T/err" "--iso CLW:0.05: no surface: CLW runs from 0 to 0.000596868 kg/kg in this file"
expect "vsv-render --iso below the data exits 1" 1 "$B/vsv-render" -q "$T/a.vsv" --iso CLW:-1 -o "$T/x.png"
[ -e "$T/x.png" ] && fail "... and no image" "x.png" || pass "... and no image"

# vsv-play --iso: the shared option; its screenshot is vsv-render's picture
expect "vsv-play --iso NOPE:1 exits 2" 2 "$B/vsv-play" "$T/a.vsv" --iso NOPE:1
has "in vsv-render's words" "$T/err" "--iso NOPE:1: no species NOPE (the file has Q, CLW"
expect "vsv-play --iso beyond the data exits 1" 1 "$B/vsv-play" "$T/a.vsv" --iso CLW:0.05
has "... no surface, the range named, as vsv-render" "$T/err" "vsv-play: $T/a.vsv: --iso CLW:0.05: no surface: CLW runs from 0 to 0.000596868 kg/kg in this file"
if [ -x "$B/vsv-play" ] && command -v xvfb-run > /dev/null && "$PYTHON" -c "import numpy, PIL" 2> /dev/null; then
    printf '0.2 seek 1\n0.4 screenshot %s\n0.6 quit\n' "$T/p.png" > "$T/play.script"
    ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0 \
    expect "vsv-play --iso takes a screenshot (Xvfb)" 0 xvfb-run -a -s "-screen 0 1024x768x24" "$B/vsv-play" \
        "$T/a.vsv" --size 480x320 --species RNW --iso CLW:5e-5:orange --no-annotate -r raycast -q --script "$T/play.script"
    "$B/vsv-render" -q "$T/a.vsv" -t 1 --size 480x320 --species RNW --iso CLW:5e-5:orange --no-annotate -o "$T/r.png"
    "$B/vsv-render" -q "$T/a.vsv" -t 1 --size 480x320 --species RNW --no-annotate -o "$T/r0.png"
    db=$("$PYTHON" - "$T/p.png" "$T/r.png" "$T/r0.png" << 'EOP'
import sys
import numpy as np
from PIL import Image
p, r, r0 = (np.asarray(Image.open(f).convert("RGB"), dtype=float) for f in sys.argv[1:4])
db = lambda a, b: 99.0 if ((a - b) ** 2).mean() == 0 else 10 * np.log10(255.0 ** 2 / ((a - b) ** 2).mean())
print("%.1f %.1f" % (db(p, r), db(p, r0)))
EOP
)
    set -- $db
    if awk "BEGIN { exit !($1 >= 40 && $2 < 40) }"; then
        pass "vsv-play shows the isosurface vsv-render draws ($1 dB; $2 dB against the picture without it)"
    else
        fail "vsv-play shows the isosurface vsv-render draws" "$1 dB against vsv-render, $2 dB against no isosurface"
    fi
else
    pass "vsv-play --iso picture: skipped (no vsv-play, xvfb-run or numpy/PIL)"
fi
exit 0
