#!/bin/sh
# demo.sh — the main job end to end on the bundled sample (no ../shared needed):
# real MM5 output → field stream → 10-minute frames → .vsv → vsv-info.
set -eu
B=${B:-build}
OUT=${OUT:-demo-out}
MM5=samples/mm5/MMOUT_DOMAIN1_CROP
mkdir -p "$OUT"
step() { printf '\n\033[1m== %s\033[0m\n$ %s\n' "$1" "$2"; }

step "The sample: real MM5 v3 output (a 40x40 crop of a 3-hour forecast)" "vsv-info $MM5"
"$B/vsv-info" "$MM5"

step "What can be extracted" "vsv-extract --list $MM5"
"$B/vsv-extract" --list "$MM5"

step "Convert with the Unix tools: clouds, rain, ice, snow, moisture on the model's own 15 levels, every 10 minutes" \
     "vsv-extract $MM5 | vsv-interp --time-res 10m | vsv-pack -o $OUT/storm-pipe.vsv"
"$B/vsv-extract" "$MM5" | "$B/vsv-interp" --time-res 10m | "$B/vsv-pack" -o "$OUT/storm-pipe.vsv"

step "The same in one process (byte-identical)" "vsv-convert --time-res 10m $MM5 -o $OUT/storm.vsv"
"$B/vsv-convert" --time-res 10m "$MM5" -o "$OUT/storm.vsv"
cmp "$OUT/storm.vsv" "$OUT/storm-pipe.vsv" && echo "identical: $OUT/storm.vsv = $OUT/storm-pipe.vsv"

if [ -x "$B/vsv-convert-mpi" ] && command -v mpirun > /dev/null 2>&1; then
    step "The same on two MPI ranks (each reads and encodes half the steps; byte-identical)" \
         "mpirun -np 2 vsv-convert-mpi --stats --time-res 10m $MM5 -o $OUT/storm-mpi.vsv"
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -q --oversubscribe --mca btl self,vader \
        --mca btl_vader_single_copy_mechanism none --mca plm_rsh_agent false -np 2 \
        "$B/vsv-convert-mpi" -q --stats --time-res 10m "$MM5" -o "$OUT/storm-mpi.vsv"
    cmp "$OUT/storm.vsv" "$OUT/storm-mpi.vsv" && echo "identical: $OUT/storm-mpi.vsv = $OUT/storm.vsv"
else
    printf '\n(vsv-convert-mpi is not built: apt-get install libopenmpi-dev openmpi-bin)\n'
fi

step "Frames between the hourly outputs carried along the model's own winds (U V W) instead of cross-faded" \
     "vsv-convert --time-res 10m --interp advect $MM5 -o $OUT/moving.vsv"
"$B/vsv-convert" --time-res 10m --interp advect "$MM5" -o "$OUT/moving.vsv"
"$B/vsv-info" "$OUT/moving.vsv" | grep 'time interpolation'
echo "01:30, half way between two outputs: cross-faded $OUT/half-linear.png, carried $OUT/half-advect.png"
"$B/vsv-render" "$OUT/storm.vsv" --time 9 --species CLW:2,SNOW --size 480x360 -o "$OUT/half-linear.png"
"$B/vsv-render" "$OUT/moving.vsv" --time 9 --species CLW:2,SNOW --size 480x360 -o "$OUT/half-advect.png"

step "Inspect" "vsv-info $OUT/storm.vsv"
"$B/vsv-info" "$OUT/storm.vsv"

step "One time grammar in every tool: a range of ISO times (colons and all), regular 20-minute steps" \
     "vsv-convert --time-res 20m --times 1995-10-24T01:00:00Z:1995-10-24T03:00:00Z --vars CLW $MM5 -o $OUT/hours.vsv"
"$B/vsv-convert" -q --time-res 20m --times 1995-10-24T01:00:00Z:1995-10-24T03:00:00Z --vars CLW "$MM5" -o "$OUT/hours.vsv"
"$B/vsv-info" "$OUT/hours.vsv" | grep '  times'
echo "a time between steps takes the nearest, and says so:"
"$B/vsv-render" -q "$OUT/hours.vsv" --time 1995-10-24T01:07 --size 160x120 -o "$OUT/nearest.png"

step "Verify every checksum and decode everything" "vsv-info --check $OUT/storm.vsv"
"$B/vsv-info" --check "$OUT/storm.vsv"

step "For scripts: one value of the JSON description" "vsv-info -f corners.0 $OUT/storm.vsv"
"$B/vsv-info" -f corners.0 "$OUT/storm.vsv"

step "Cloud water through the three hours" "vsv-info --stats $OUT/storm.vsv (CLW rows)"
"$B/vsv-info" --stats "$OUT/storm.vsv" | grep -E '^ +(species|CLW) '
step "Ask for numbers: cloud and snow over Idaho at 3000 m (the on-the-hour rows)" \
     "vsv-query $OUT/storm.vsv --at 46,-116,3000 --species CLW,SNOW | awk 'NR == 1 || /:00:00Z/'"
"$B/vsv-query" "$OUT/storm.vsv" --at 46,-116,3000 --species CLW,SNOW | awk 'NR == 1 || /:00:00Z/'
step "... and the column above it at 02:00, as CSV" \
     "vsv-query $OUT/storm.vsv --profile 46,-116 --species SNOW --time 1995-10-24T02:00:00Z --csv"
"$B/vsv-query" "$OUT/storm.vsv" --profile 46,-116 --species SNOW --time 1995-10-24T02:00:00Z --csv | sed -n '1p;9,18p'
step "Plots with axes, as NCL and GrADS draw them: cloud water in a cross-section from the coast to the Rockies at 03:00" \
     "vsv-plot $OUT/storm.vsv --section 45,-125:52,-115 --species CLW --top 6000 --time 1995-10-24T03:00:00Z -o $OUT/section.svg"
"$B/vsv-plot" "$OUT/storm.vsv" --section 45,-125:52,-115 --species CLW --top 6000 --time 1995-10-24T03:00:00Z \
    -o "$OUT/section.svg"
"$B/vsv-plot" "$OUT/storm.vsv" --section 45,-125:52,-115 --species CLW --top 6000 --time 1995-10-24T03:00:00Z \
    -o "$OUT/section.png"
echo "$OUT/section.svg, $OUT/section.png; what the SVG says (its <text> elements, by class):"
/usr/bin/python3 tests/svgtext.py "$OUT/section.svg" | awk -F '\t' '/^(title|subtitle|xlabel|ylabel|cbar-label)\t/ { printf "  %-10s %s\n", $1, $2 }'
step "... a time series of cloud water and snow at 51N 126W, 2000 m (every 10-minute frame), and a profile of moisture" \
     "vsv-plot $OUT/storm.vsv --series 51,-126,2000 --species CLW,SNOW -o $OUT/series.png; vsv-plot ... --profile 50,-120 --species Q --log -o $OUT/profile.pdf"
"$B/vsv-plot" "$OUT/storm.vsv" --series 51,-126,2000 --species CLW,SNOW -o "$OUT/series.png" && echo "$OUT/series.png"
"$B/vsv-plot" "$OUT/storm.vsv" --profile 50,-120 --species Q --log --time 1995-10-24T03:00:00Z -o "$OUT/profile.pdf" &&
    echo "$OUT/profile.pdf"
step "Hand the numbers to xarray, CDO or NCL: one CF-1.8 netCDF-4 file" \
     "vsv-export $OUT/storm.vsv --netcdf $OUT/storm.nc --species CLW,SNOW --times 1995-10-24T01:00:00Z:"
"$B/vsv-export" "$OUT/storm.vsv" --netcdf "$OUT/storm.nc" --species CLW,SNOW --times 1995-10-24T01:00:00Z:
if command -v ncdump > /dev/null; then
    ncdump -h "$OUT/storm.nc" | grep -E 'grid_mapping_name|standard_parallel|time:units|float SNOW|SNOW:(units|vsv_max)|Conventions'
fi
if ls "$B"/python/vesuvius/_vesuvius*.so > /dev/null 2>&1; then
    step "The same numbers from Python (import vesuvius)" \
         "PYTHONPATH=$B/python python3 $OUT/snow.py"
    cat > "$OUT/snow.py" <<EOP
import vesuvius
f = vesuvius.open("$OUT/storm.vsv")
snow = f.read("SNOW", time="1995-10-24T02:00:00Z")      # float32 (nz, ny, nx)
print(f.times[0], "..", f.times[-1], "| SNOW", snow.shape, "max %.3g kg/kg" % snow.max(),
      "| at 46N 116W 3017.5 m: %.6g" % snow[8, 3, 30])
EOP
    cat "$OUT/snow.py"
    PYTHONPATH="$B/python" /usr/bin/python3 "$OUT/snow.py"
else
    printf '\n(the Python module is not built: apt-get install python3-dev python3-numpy)\n'
fi
step "Render the last frame: clouds, rain, ice, snow and moisture over the terrain, from the south-west" \
     "vsv-render $OUT/storm.vsv -o $OUT/storm.png"
"$B/vsv-render" "$OUT/storm.vsv" -o "$OUT/storm.png"

step "A map (plan view, north up): the sea and lakes from the model's own land use" \
     "vsv-render $OUT/storm.vsv --view plan -o $OUT/map.png"
"$B/vsv-render" -q "$OUT/storm.vsv" --view plan -o "$OUT/map.png" && echo "$OUT/map.png"

step "What a frame says about itself: time and run, colour bars with units and range, vertical exaggeration, scale bar, graticule, GSHHG coasts, lakes and borders (gmt-gshhg-low); --no-annotate for the bare frame" \
     "vsv-render $OUT/storm.vsv --species CLW,SNOW --view plan -o $OUT/annotated.png; ... --no-annotate -o $OUT/bare.png"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --view plan -o "$OUT/annotated.png" && echo "$OUT/annotated.png"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --view plan --no-annotate -o "$OUT/bare.png" && echo "$OUT/bare.png"

step "The model's own levels (the default) beside even heights (--vertical even: resampled, a peak between two levels lost, and the file says so)" \
     "vsv-convert --vertical even $MM5 -o $OUT/even.vsv; vsv-info both; vsv-render $OUT/native.vsv --view south --no-terrain"
"$B/vsv-convert" -q --vars CLW,ICE,SNOW "$MM5" -o "$OUT/native.vsv"
"$B/vsv-convert" -q --vertical even --vars CLW,ICE,SNOW "$MM5" -o "$OUT/even.vsv"
"$B/vsv-info" "$OUT/native.vsv" | grep -A1 "vertical"
"$B/vsv-info" "$OUT/even.vsv" | grep "CLW\|resampled"
"$B/vsv-info" "$OUT/native.vsv" | grep "CLW"
"$B/vsv-render" -q "$OUT/native.vsv" --view south --no-terrain -x 60 -o "$OUT/native.png" && echo "$OUT/native.png"

step "Lit clouds (gradient shading, a sun in the north-west) over a section of moisture at 1500 m" \
     "vsv-render $OUT/storm.vsv --species CLW,SNOW --light --slice z=1500 --slice-species Q"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --light --slice z=1500 --slice-species Q --size 480x360 \
    -o "$OUT/lit.png" && echo "$OUT/lit.png"

step "Isosurfaces at the model's own heights: cloud water at 0.05 g/kg, snow at 0.02 g/kg (lit, opaque; the volumes of rain and ice through them), and the cloud's surface as glTF 2.0 for Blender or three.js" \
     "vsv-render $OUT/storm.vsv --species RNW,ICE --iso CLW:5e-5:white --iso SNOW:2e-5:cyan --light; vsv-export ... --iso CLW:5e-5 --gltf $OUT/cloud.gltf"
"$B/vsv-render" -q "$OUT/storm.vsv" --species RNW,ICE --iso CLW:5e-5:white --iso SNOW:2e-5:cyan --light \
    --size 480x360 -o "$OUT/iso.png" && echo "$OUT/iso.png"
"$B/vsv-export" "$OUT/storm.vsv" --iso CLW:5e-5 --gltf "$OUT/cloud.gltf"

step "The wind: the air's paths from every 6th column at 1500 m (lit tubes drawn up to the frame's time, an arrowhead where the air is then) and wind arrows at 3000 m (an arrow as long as their spacing is 20 m/s)" \
     "vsv-render $OUT/storm.vsv --species CLW,SNOW --view plan --seed-slice 1500:6 --barbs 3000:3; ... --light (oblique); ... --streamlines --traj-for 8h; vsv-query ... --trajectory 50,-125,1500 --for 3h --every 1h --csv"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --view plan --seed-slice 1500:6 --barbs 3000:3 --size 480x360 \
    -o "$OUT/wind-map.png" && echo "$OUT/wind-map.png"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --light --seed-slice 1500:6 --size 480x360 \
    -o "$OUT/paths.png" && echo "$OUT/paths.png"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --light --seed-slice 1500:6 --streamlines --traj-for 8h --size 480x360 \
    -o "$OUT/streamlines.png" && echo "$OUT/streamlines.png (streamlines of the 03Z wind, 8 h of travel)"
"$B/vsv-query" "$OUT/storm.vsv" --trajectory 50,-125,1500 --for 3h --every 1h --csv

step "The same lit frame raycast on the GPU (OpenGL 3.3 through EGL, no display; here Mesa's llvmpipe, a CPU: slow)" \
     "vsv-render $OUT/storm.vsv --species CLW,SNOW --light --slice z=1500 --slice-species Q --renderer gl"
if "$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --light --slice z=1500 --slice-species Q --size 320x240 \
    --renderer gl -o "$OUT/lit-gl.png" && "$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --light \
    --slice z=1500 --slice-species Q --size 320x240 -o "$OUT/lit-cpu.png"; then
    echo "$OUT/lit-gl.png"
    /usr/bin/python3 tests/imgcmp.py "$OUT/lit-gl.png" "$OUT/lit-cpu.png" 2> /dev/null |
        awk '{ print "  against the CPU raycaster: " $2 " dB PSNR" }'
fi

step "One colour scale for several files: --range" \
     "vsv-render $OUT/storm.vsv --species CLW,SNOW --range CLW=0:0.0006 --range SNOW=0:0.0005"
"$B/vsv-render" -q "$OUT/storm.vsv" --species CLW,SNOW --range CLW=0:0.0006 --range SNOW=0:0.0005 --size 480x360 \
    -o "$OUT/range.png" && echo "$OUT/range.png"

step "Render every 30 minutes, cloud water and snow only, higher cloud opacity" \
     "vsv-render $OUT/storm.vsv --times 0: --species CLW:2,SNOW -o $OUT/frame%04d.png --size 480x360"
"$B/vsv-render" "$OUT/storm.vsv" --times 0: --species CLW:2,SNOW --size 480x360 -o "$OUT/frame%04d.png"
ls "$OUT"/frame*.png | head -3

if command -v ffmpeg > /dev/null; then
    step "A movie of the three hours (every 10-minute frame) through ffmpeg" \
         "vsv-render $OUT/storm.vsv --movie $OUT/storm.mp4 --fps 8 --renderer shearwarp --size 640x480"
    "$B/vsv-render" "$OUT/storm.vsv" --movie "$OUT/storm.mp4" --fps 8 --renderer shearwarp --size 640x480
fi

step "Hand the clouds to Blender or Houdini: one OpenVDB file per step, a grid per species" \
     "vsv-export $OUT/storm.vsv --vdb $OUT/vdb/storm_%04d.vdb --species CLW,ICE,SNOW"
mkdir -p "$OUT/vdb"
"$B/vsv-export" "$OUT/storm.vsv" --vdb "$OUT/vdb/storm_%04d.vdb" --species CLW,ICE,SNOW
if command -v vdb_print > /dev/null; then
    vdb_print -l "$OUT/vdb/storm_0018.vdb" | grep -E '^(Name|time)|active voxels:' | head -8
fi
step "... and back (OpenVDB in): the sequence becomes a .vsv again" \
     "vsv-extract $OUT/vdb/storm_*.vdb | vsv-pack -o $OUT/from-vdb.vsv"
"$B/vsv-extract" "$OUT"/vdb/storm_*.vdb | "$B/vsv-pack" -o "$OUT/from-vdb.vsv"
"$B/vsv-info" "$OUT/from-vdb.vsv" | sed -n '1,3p;/times/p'

# Playback: in a window when there is a display, else in a virtual one (Xvfb),
# driven by a script: play, hide the rain, fade the clouds, rewind, a map view,
# screenshots (annotated as vsv-render's frames: time, colour bars, scale,
# graticule, coasts; --no-annotate for the bare picture).
cat > "$OUT/playback.script" <<EOS
0.5 screenshot $OUT/play-start.png
0.6 play
2.0 screenshot $OUT/play-playing.png
2.1 hide RNW
2.2 opacity CLW 2
2.3 camera 200 40
2.5 screenshot $OUT/play-clouds.png
2.6 rewind
3.5 pause
3.6 screenshot $OUT/play-rewound.png
3.7 view plan
3.8 screenshot $OUT/play-map.png
4.0 quit
EOS
if [ ! -x "$B/vsv-play" ]; then
    printf '\n(vsv-play not built: VIEWER=0, or GLFW/GL/FreeType/fontconfig missing; playback skipped)\n'
elif [ -n "${DISPLAY:-}" ]; then
    step "Play it back in a window (scripted; run vsv-play $OUT/storm.vsv yourself and press h)" \
         "vsv-play $OUT/storm.vsv --script $OUT/playback.script"
    "$B/vsv-play" "$OUT/storm.vsv" --script "$OUT/playback.script"
elif command -v xvfb-run > /dev/null; then
    step "No display here: play it back in a virtual one (Xvfb), scripted" \
         "xvfb-run vsv-play $OUT/storm.vsv --script $OUT/playback.script"
    xvfb-run -a -s "-screen 0 1280x1024x24" "$B/vsv-play" "$OUT/storm.vsv" --script "$OUT/playback.script"
else
    printf '\n(no display and no xvfb-run: playback skipped; apt-get install xvfb xauth)\n'
fi

# The FreeVR back end in a four-wall CAVE, run against the project's FreeVR
# stand-in (tests/freevr-standin/, built by make demo; it is not FreeVR) in a
# virtual display: each wall's frame as the stand-in read it back, then Escape.
if [ -x "$B/tests/vsv-play-freevr" ] && command -v xvfb-run > /dev/null && command -v xdotool > /dev/null; then
    step "A four-wall CAVE (FreeVR stand-in under Xvfb): left, front, right and floor walls at one model time" \
         "FREEVR='usesystem \"cave4\"; ...' vsv-play-freevr $OUT/storm.vsv --play --loop --fps --trace cave/trace"
    mkdir -p "$OUT/cave"
    rm -f "$OUT"/cave/*.ppm
    FREEVR='usesystem "cave4";
system "cave4" = { type = "cave"; procs = "pf", "pl", "pr", "pb", "pin"; }
window "front" = { mount = "fixed"; args = "geometry=320x320+330+0"; rw2w_coords = -5,0,-5, 5,0,-5, -5,10,-5; }
window "left" = { mount = "fixed"; args = "geometry=320x320+0+0"; rw2w_coords = -5,0,5, -5,0,-5, -5,10,5; }
window "right" = { mount = "fixed"; args = "geometry=320x320+660+0"; rw2w_coords = 5,0,-5, 5,0,5, 5,10,-5; }
window "floor" = { mount = "fixed"; args = "geometry=320x320+330+330"; rw2w_coords = -5,0,5, 5,0,5, -5,0,-5; }
process "pf" = { type = visren; objects = "front"; }
process "pl" = { type = visren; objects = "left"; }
process "pr" = { type = visren; objects = "right"; }
process "pb" = { type = visren; objects = "floor"; }
process "pin" = { type = input; usecmin = 15000; objects = "xin"; }
inputdevice "xin" = { type = "xwindows"; args = "window = front;";
  input "Escape Key" = "2switch(keyboard:key[Escape])";
  input "head" = "6sensor(sim6[0])"; t2rw_translate = 0, 5.5, 0; }'
    cat > "$OUT/cave/session.sh" << 'EOS'
FREEVR_STANDIN_DUMP=$OUT/cave "$B/tests/vsv-play-freevr" "$OUT/storm.vsv" --play --loop --rate 1200 --fps \
    --trace "$OUT/cave/trace" 2> "$OUT/cave/log" &
pid=$!
end=$(($(date +%s) + 30))
while [ "$(date +%s)" -lt $end ] && kill -0 $pid 2> /dev/null; do
    n=0
    for w in left front right floor; do
        [ "$(sed -n '2s/^# frame //p;2q' "$OUT/cave/$w.ppm" 2> /dev/null)" -ge 5 ] 2> /dev/null && n=$((n + 1))
    done
    [ $n = 4 ] && { sleep 4; break; }
    sleep 0.2
done
xdotool keydown Escape; sleep 0.3; xdotool keyup Escape
wait $pid
EOS
    OUT=$OUT B=$B FREEVR=$FREEVR HOME=$OUT/cave FREEVR_HOME=$OUT/cave \
        xvfb-run -a -s "-screen 0 1024x768x24" sh "$OUT/cave/session.sh" &&
        /usr/bin/python3 tests/freevr_shot.py png "$OUT/cave.png" "$OUT"/cave/left.ppm "$OUT"/cave/front.ppm \
            "$OUT"/cave/right.ppm "$OUT"/cave/floor.ppm && echo "the four walls: $OUT/cave.png" &&
        /usr/bin/python3 tests/freevr_trace.py check "$OUT/cave/trace" 4
else
    printf '\n(the FreeVR stand-in demo needs xvfb-run and xdotool: sh tools/deps.sh --install)\n'
fi
# a web server on the loopback interface: the same picture from a URL, only
# the parts drawn fetched, the second time none
LIGHTTPD=$(command -v lighttpd 2> /dev/null || echo /usr/sbin/lighttpd)
if [ -x "$LIGHTTPD" ]; then
    W=$(mktemp -d "${TMPDIR:-/tmp}/vsv-demo-http.XXXXXX")
    mkdir -p "$W/www"
    cp "$OUT/storm.vsv" "$W/www/storm.vsv"
    touch -d '1 hour ago' "$W/www/storm.vsv" # lighttpd sends no ETag for a file written this second
    PORT=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    printf 'server.document-root = "%s/www"\nserver.bind = "127.0.0.1"\nserver.port = %s\n' "$W" "$PORT" > "$W/conf"
    printf 'server.modules = ("mod_accesslog")\naccesslog.filename = "%s/log"\naccesslog.format = "%%r %%s %%b"\n' "$W" >> "$W/conf"
    printf 'mimetype.assign = ("" => "application/octet-stream")\nserver.errorlog = "%s/err"\n' "$W" >> "$W/conf"
    "$LIGHTTPD" -D -f "$W/conf" &
    lpid=$!
    /usr/bin/python3 -c 'import socket, sys, time
for _ in range(100):
    try: socket.create_connection(("127.0.0.1", int(sys.argv[1])), 1).close(); break
    except OSError: time.sleep(0.1)' "$PORT"
    URL=http://127.0.0.1:$PORT/storm.vsv
    step "The same file from a web server (lighttpd on 127.0.0.1, range requests, a cache)" \
         "vsv-render $URL --cache-dir $W/cache -o $OUT/storm-http.png (twice)"
    "$B/vsv-render" "$URL" --cache-dir "$W/cache" -o "$OUT/storm-http.png" -q &&
        "$B/vsv-render" "$URL" --cache-dir "$W/cache" -o "$OUT/storm-http2.png" -q
    kill -INT $lpid; wait $lpid || true
    cmp "$OUT/storm-http.png" "$OUT/storm.png" && cmp "$OUT/storm-http2.png" "$OUT/storm.png" &&
        echo "identical: $OUT/storm-http.png = $OUT/storm.png"
    awk -v size="$(wc -c < "$W/www/storm.vsv")" '/^HEAD/ { runs++ } { sent[runs] += $NF }
        END { printf "body bytes the server sent: %d of the file'"'"'s %d on the first run, %d on the second\n", sent[1], size, sent[2] }' "$W/log"
    rm -rf "$W"
else
    printf '\n(the web-server demo needs lighttpd: sh tools/deps.sh --install)\n'
fi
printf '\nDone: %s/storm.vsv, storm.png, section.svg, iso.png, cloud.gltf, paths.png, streamlines.png, wind-map.png, frame*.png, storm.mp4, vdb/*.vdb, play-*.png and cave.png\n' "$OUT"
