#!/usr/bin/python3
"""bench_vtk_peer.py DIR — VTK's vtkFixedPointVolumeRayCastMapper as a peer of
bench/bench_peers.py: the volume and scene bench_rc_peer wrote into DIR, the
same commands on standard input (see bench_rc_peer.c):
  time THREADS SIZE         every view rendered once, each frame's seconds
                            by VTK's own timer: the mapper's TimeToDraw
                            (ray casting and drawing the image into the
                            window; Python and the window's buffer swap are
                            outside it), then " | " and Render()'s wall time
  image THREADS SIZE V OUT  view V as 8-bit RGB, row 0 at the top, to OUT
Matched settings (bench_peers.py prints them):
  - the same decoded float volume, rows south to north: vtkImageReader2 with
    SetFileLowerLeft(1) (its default flips the rows);
  - the same camera (position, direction, up, vertical angle), image size,
    sample distance (automatic adjustment off, image sample distance 1);
  - the same opacity per unit length. Vesuvius's extinction at value v is
    sigma(v) = k a(v) per world unit (a: the transfer function's opacity
    curve, k = 3 / min(dx, dy)), so a step of length s has opacity
    1 - exp(-sigma(v) s). VTK's scalar opacity o(v) holds for a length D (the
    scalar opacity unit distance) and becomes 1 - (1 - o(v))^(s / D) for a
    step s. The two agree for every s when
        o(v) = 1 - exp(-k a(v) D),
    here with D = min(dx, dy): o(v) = 1 - exp(-3 a(v)), given at each of the
    transfer function's 1024 table entries (colour likewise), and 0 below
    the range (Vesuvius leaves such samples out);
  - early termination: VTK ends a ray when its remaining opacity is below
    255/32767; bench_rc_peer gives Vesuvius the same threshold."""
import math
import sys
import time

import vtk


def scene(path):
    s = {}
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        w = lines[i].split()
        i += 1
        if not w:
            continue
        if w[0] == "lut":
            n = int(w[1])
            s["lut"] = [tuple(float(x) for x in lines[i + k].split()) for k in range(n)]
            i += n
        elif w[0] == "views":
            n = int(w[1])
            s["views"] = [tuple(float(x) for x in lines[i + k].split()) for k in range(n)]
            i += n
        else:
            s[w[0]] = w[1:]
    return s


def main():
    d = sys.argv[1]
    s = scene(d + "/scene.txt")
    nx, ny, nz = (int(v) for v in s["dims"])
    origin = [float(v) for v in s["origin"]]
    spacing = [float(v) for v in s["spacing"]]
    k, unit = float(s["sigma"][0]), float(s["unit"][0])
    reader = vtk.vtkImageReader2()
    reader.SetFileName(d + "/volume.f32")
    reader.SetDataScalarTypeToFloat()
    reader.SetDataByteOrderToLittleEndian()
    reader.SetFileDimensionality(3)
    reader.SetFileLowerLeft(1)  # row j = 0 of the file is the southernmost
    reader.SetDataExtent(0, nx - 1, 0, ny - 1, 0, nz - 1)
    reader.SetDataSpacing(*spacing)
    reader.SetDataOrigin(*origin)
    reader.Update()
    colour = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    lut, lo = s["lut"], float(s["lo"][0])
    vmin = reader.GetOutput().GetScalarRange()[0]
    if vmin < lo:  # below the range: nothing (Vesuvius skips such samples)
        opacity.AddPoint(vmin, 0)
        opacity.AddPoint(math.nextafter(lo, -math.inf), 0)
    for v, r, g, b, a in lut:
        colour.AddRGBPoint(v, r, g, b)
        opacity.AddPoint(v, 1 - math.exp(-k * max(a, 0) * unit))
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetSampleDistance(float(s["step"][0]))
    mapper.SetAutoAdjustSampleDistances(0)
    mapper.SetImageSampleDistance(1.0)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    ren = vtk.vtkRenderer()
    ren.SetBackground(0, 0, 0)
    ren.AddVolume(volume)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.AddRenderer(ren)
    cam = ren.GetActiveCamera()

    def look(v, size):
        if win.GetSize()[0] != size:
            win.SetSize(size, size)
        px, py, pz, dx, dy, dz, ux, uy, uz, fov = v
        cam.SetPosition(px, py, pz)
        cam.SetFocalPoint(px + dx, py + dy, pz + dz)
        cam.SetViewUp(ux, uy, uz)
        cam.SetViewAngle(fov)
        ren.ResetCameraClippingRange()

    warm = set()
    print("ready", flush=True)
    for line in sys.stdin:
        w = line.split()
        if not w or w[0] == "quit":
            break
        threads, size = int(w[1]), int(w[2])
        mapper.SetNumberOfThreads(threads)
        if w[0] == "time":
            if (threads, size) not in warm:
                look(s["views"][0], size)
                win.Render()
                warm.add((threads, size))
            own, wall = [], []
            for v in s["views"]:
                look(v, size)
                t0 = time.perf_counter()
                win.Render()
                wall.append(time.perf_counter() - t0)
                own.append(mapper.GetTimeToDraw())
            print(" ".join("%.6f" % t for t in own), "|", " ".join("%.6f" % t for t in wall), flush=True)
        elif w[0] == "image":
            look(s["views"][int(w[3])], size)
            win.Render()
            px = vtk.vtkUnsignedCharArray()
            win.GetPixelData(0, 0, size - 1, size - 1, 1, px, 0)
            raw = bytes(memoryview(px))  # rows from the bottom
            row = 3 * size
            with open(w[4], "wb") as f:
                for y in range(size - 1, -1, -1):
                    f.write(raw[y * row:(y + 1) * row])
            print("ok", flush=True)


main()
