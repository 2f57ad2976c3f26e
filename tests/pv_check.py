"""Open an MBSPH XDMF index in ParaView and report what ParaView sees, as JSON.

Run with ParaView's python (Debian package paraview), headless under Xvfb:

    xvfb-run -a pvpython tests/pv_check.py OUT/particles.xmf pressure [--time T] [--screenshot F.png]

or simply `tools/pv_probe.sh OUT/particles.xmf pressure`. It reads the file with the
reader "Xdmf3ReaderS", goes to the last time step (or to the step nearest --time T) and prints
one JSON object on the last line of stdout:

    {"file": ..., "reader": "Xdmf3ReaderS", "n_timesteps": 2, "times": [0.0, 0.25],
     "time": 0.25, "n_points": 50, "n_cells": 50, "point_arrays": {"velocity": 2, "pressure": 1, ...},
     "array": "pressure", "range": [1000.0, 5900.0], "bounds": [xmin, xmax, ymin, ymax, zmin, zmax]}

point_arrays maps each point array to its number of components. With --screenshot it also
renders the points (coloured by the array) to a PNG. Exit status 1 when the file does not load,
has no points, or lacks the array.
"""
import argparse
import json
import os
import sys


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("xmf", help="path to OUT/particles.xmf")
    ap.add_argument("array", help="point array whose (min, max) to report, e.g. pressure")
    ap.add_argument("--time", type=float, default=None,
                    help="go to the time step nearest this time instead of the last")
    ap.add_argument("--screenshot", default=None, help="also render the points to this PNG")
    args = ap.parse_args(argv)

    if not os.path.isfile(args.xmf):
        print(json.dumps({"file": args.xmf, "error": "no such file"}), flush=True)
        return 1

    try:  # a malformed file makes the XDMF library abort the process: say why first
        import xml.etree.ElementTree as ET
        ET.parse(args.xmf)
    except ET.ParseError as e:
        print(json.dumps({"file": args.xmf, "error": "not well-formed XML: %s" % e}), flush=True)
        return 1

    from paraview import servermanager
    from paraview.simple import Xdmf3ReaderS

    # an absolute path: given a bare "particles.xmf", the XDMF library looks for the HDF5 files
    # at "particles.xmfsnap_00000.h5" and aborts
    reader = Xdmf3ReaderS(FileName=[os.path.abspath(args.xmf)])
    reader.UpdatePipelineInformation()
    tv = reader.TimestepValues  # a list, but a bare number when there is one time step
    if tv is None:
        times = []
    elif hasattr(tv, "__len__"):
        times = [float(x) for x in tv]
    else:
        times = [float(tv)]
    if args.time is not None and times:
        t = min(times, key=lambda x: abs(x - args.time))
    else:
        t = times[-1] if times else 0.0
    reader.UpdatePipeline(t)

    data = servermanager.Fetch(reader)
    if data is None:
        print(json.dumps({"file": args.xmf, "error": "ParaView could not read it"}), flush=True)
        return 1
    if data.IsA("vtkCompositeDataSet"):  # a spatial collection comes as a multiblock
        from paraview.vtk.vtkFiltersCore import vtkAppendFilter  # noqa: E402 (pvpython only)
        app = vtkAppendFilter()
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            app.AddInputData(it.GetCurrentDataObject())
            it.GoToNextItem()
        app.Update()
        data = app.GetOutput()

    pd = data.GetPointData()
    arrays = {pd.GetArrayName(i): pd.GetArray(i).GetNumberOfComponents()
              for i in range(pd.GetNumberOfArrays())}
    result = {
        "file": args.xmf,
        "reader": "Xdmf3ReaderS",
        "n_timesteps": len(times),
        "times": times,
        "time": t,
        "n_points": data.GetNumberOfPoints(),
        "n_cells": data.GetNumberOfCells(),
        "point_arrays": arrays,
        "array": args.array,
        "range": None,
        "bounds": list(data.GetBounds()) if data.GetNumberOfPoints() else None,
    }
    arr = pd.GetArray(args.array)
    if arr is not None:
        # component -1: magnitude for a vector, the value itself for a scalar
        result["range"] = list(arr.GetRange(-1 if arr.GetNumberOfComponents() > 1 else 0))

    if args.screenshot:
        from paraview.simple import (ColorBy, GetActiveViewOrCreate, ResetCamera,
                                     SaveScreenshot, Show)
        view = GetActiveViewOrCreate("RenderView")
        view.ViewTime = t
        disp = Show(reader, view)
        disp.SetRepresentationType("Points")
        disp.PointSize = 6.0
        if arr is not None:
            ColorBy(disp, ("POINTS", args.array))
            disp.RescaleTransferFunctionToDataRange(True, False)
        view.InteractionMode = "2D"
        ResetCamera(view)
        SaveScreenshot(args.screenshot, view, ImageResolution=[800, 600])
        result["screenshot"] = args.screenshot

    print(json.dumps(result), flush=True)
    ok = result["n_points"] > 0 and result["range"] is not None
    return 0 if ok else 1


if __name__ == "__main__":
    status = main(sys.argv[1:])
    # Close the session before the interpreter ends: left to Python's teardown, a render view
    # made inside main() dies with "X Error ... GLXBadContext" and exit status 1 under Xvfb.
    from paraview.simple import Disconnect
    Disconnect()
    sys.exit(status)
