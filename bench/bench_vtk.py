#!/usr/bin/env python3
"""bench_vtk.py — the peer of bench_render: VTK's vtkFixedPointVolumeRayCastMapper
(Debian python3-vtk9, offscreen under Xvfb) on the same decoded volume, the same
camera and image size, a similar colour map and opacity ramp; 8 orbiting frames
(4 at 1024x1024), the fastest of 3 passes, as bench_render.
Usage: bench_vtk.py RAW 'geometry ...' (the line bench_render prints)"""
import math, sys, time
import vtk

raw, geo = sys.argv[1], sys.argv[2].split()[1:]
nx, ny, nz = (int(v) for v in geo[:3])
ox, oy, oz, dx, dy, dz, cx, cy, cz, lo, hi, top = (float(v) for v in geo[3:])
reader = vtk.vtkImageReader2()
reader.SetFileName(raw)
reader.SetDataScalarTypeToFloat()
reader.SetDataByteOrderToLittleEndian()
reader.SetFileDimensionality(3)
reader.SetDataExtent(0, nx - 1, 0, ny - 1, 0, nz - 1)
reader.SetDataSpacing(dx, dy, dz)
reader.SetDataOrigin(ox, oy, oz)
reader.Update()
colour = vtk.vtkColorTransferFunction()
for i, rgb in enumerate([(0.27, 0.0, 0.33), (0.19, 0.41, 0.56), (0.21, 0.72, 0.47), (0.99, 0.91, 0.15)]):
    colour.AddRGBPoint(lo + (hi - lo) * i / 3, *rgb)
opacity = vtk.vtkPiecewiseFunction()
for t, a in [(0, 0), (0.25, 0.05), (0.5, 0.2), (0.75, 0.45), (1, 0.8)]:
    opacity.AddPoint(lo + (hi - lo) * t, a * top / 0.8)
prop = vtk.vtkVolumeProperty()
prop.SetColor(colour)
prop.SetScalarOpacity(opacity)
prop.SetScalarOpacityUnitDistance(min(dx, dy))
prop.SetInterpolationTypeToLinear()
prop.ShadeOff()
mapper = vtk.vtkFixedPointVolumeRayCastMapper()
mapper.SetInputConnection(reader.GetOutputPort())
mapper.SetSampleDistance(0.5 * min(dx, dy, dz))
mapper.SetAutoAdjustSampleDistances(0)
volume = vtk.vtkVolume()
volume.SetMapper(mapper)
volume.SetProperty(prop)
ren = vtk.vtkRenderer()
ren.AddVolume(volume)
win = vtk.vtkRenderWindow()
win.SetOffScreenRendering(1)
win.AddRenderer(ren)
centre = (ox + dx * (nx - 1) / 2, oy + dy * (ny - 1) / 2, oz + 0.3 * dz * (nz - 1))
print("| image | threads | frames/s | ms/frame |")
print("|---|---|---|---|")
for size, frames in [(512, 8), (1024, 4)]:
    win.SetSize(size, size)
    for threads in (1, 2):
        mapper.SetNumberOfThreads(threads)
        cam = ren.GetActiveCamera()
        cam.SetViewAngle(35)
        cam.SetViewUp(0, 0, 1)
        cam.SetFocalPoint(*centre)
        r = math.dist((cx, cy, cz), centre)
        cam.SetPosition(cx, cy, cz)
        ren.ResetCameraClippingRange()
        win.Render()  # warm-up
        dt = math.inf
        for _ in range(3):
            t0 = time.time()
            for k in range(frames):
                a = math.radians(225 + 45 * k)
                e = math.radians(30)
                cam.SetPosition(centre[0] + r * math.sin(a) * math.cos(e), centre[1] + r * math.cos(a) * math.cos(e),
                                centre[2] + r * math.sin(e))
                ren.ResetCameraClippingRange()
                win.Render()
            dt = min(dt, (time.time() - t0) / frames)
        print("| %dx%d | %d | %.2f | %.0f |" % (size, size, threads, 1 / dt, 1000 * dt))
        sys.stdout.flush()
