#!/usr/bin/pvpython
"""Renders a run's snapshot as ParaView shows it (its default Xdmf3 reader
on snapshots.xdmf and bodies.xdmf, nothing chosen by hand): particles as
points coloured by a field, the projectile and walls as grey surfaces.

usage: pvpython tools/render_snapshot.py RUN_FOLDER OUT.png [--field NAME]
           [--time T] [--look x|y|z|-x|-y|-z]

Needs Debian's python3-paraview; without a display run it under xvfb-run
(xvfb-run -a pvpython tools/render_snapshot.py ...). The camera looks along
--look (default +z: a 3-D half or quarter model with the symmetry plane
z = 0 then shows its section through the shot line in front).
"""
import argparse
import os

from paraview import simple as pv


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("out")
    ap.add_argument("--field", default="von_mises_stress")
    ap.add_argument("--time", type=float, help="simulated time, s (default: the last snapshot)")
    ap.add_argument("--look", default="z", choices=["x", "y", "z", "-x", "-y", "-z"])
    args = ap.parse_args()
    reader = pv.OpenDataFile(os.path.join(args.run, "snapshots.xdmf"))
    times = list(reader.TimestepValues)
    time = times[-1] if args.time is None else min(times, key=lambda t: abs(t - args.time))
    view = pv.CreateView("RenderView")
    view.ViewSize = [1000, 800]
    view.ViewTime = time
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.CameraParallelProjection = 1
    view.OrientationAxesVisibility = 1
    view.OrientationAxesLabelColor = [0.0, 0.0, 0.0]
    display = pv.Show(reader, view)
    pv.ColorBy(display, ("POINTS", args.field))
    display.Representation = "Points"
    display.PointSize = 4
    display.RescaleTransferFunctionToDataRange(True)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(pv.GetColorTransferFunction(args.field), view)
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.Title = args.field
    bar.ComponentTitle = ""
    bodies = os.path.join(args.run, "bodies.xdmf")
    if os.path.exists(bodies):
        solid = pv.Show(pv.OpenDataFile(bodies), view)
        solid.AmbientColor = solid.DiffuseColor = [0.5, 0.5, 0.5]
    sign = -1.0 if args.look.startswith("-") else 1.0
    axis = "xyz".index(args.look[-1])
    position = [0.0, 0.0, 0.0]
    position[axis] = -sign  # the camera stands behind the direction it looks along
    view.CameraPosition = position
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 0.0, 1.0] if axis == 1 else [0.0, 1.0, 0.0]
    view.ResetCamera()
    pv.SaveScreenshot(args.out, view)
    print(f"{args.out}: t = {time:.4g} s, {args.field}")


if __name__ == "__main__":
    main()
