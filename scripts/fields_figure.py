#!/usr/bin/python3
"""One PNG per field of a run's fields.xdmf (fsiopt -write_fields), drawn off-screen by VTK
at one written time, so a run can be looked at without ParaView.

usage: scripts/fields_figure.py [--time T] [--out DIR] [--size WxH] OUTPUT_DIR

Reads OUTPUT_DIR/fields.xdmf with VTK's XDMF reader (PyPI's vtk, which `make deps` puts
into .deps/venv; this script finds it there) at the written time nearest T (default: the
last), and writes DIR/<grid>_<field>.png (DIR defaults to OUTPUT_DIR/figures) for every
field of every grid: the fluid on its moving mesh, the structure on its deformed mesh,
the walls. A scalar is coloured by its value, a vector by its magnitude, a tensor by its
Frobenius norm; the colour bar is titled with the field's name and the unit the file gives
it. Prints the files it wrote, one per line. A missing or unreadable file, or a time outside
the run's, is one line on stderr and exit 1."""
import argparse
import glob
import os
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
for site in sorted(glob.glob(os.path.join(ROOT, ".deps", "venv", "lib", "python3*", "site-packages"))):
    if os.path.isdir(os.path.join(site, "vtkmodules")) and site not in sys.path:
        sys.path.append(site)
# off-screen: no X display on a batch node
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def fail(message):
    print("fields_figure: %s" % message, file=sys.stderr)
    sys.exit(1)


def units(xdmf):
    """{(grid, field): unit} from the XDMF's <Information Name="unit"> of each attribute"""
    got = {}
    for grid in ET.parse(xdmf).getroot().iter("Grid"):
        name = grid.get("Name", "")
        if "_step_" not in name:
            continue
        base = name.rsplit("_step_", 1)[0]
        for attribute in grid.findall("Attribute"):
            info = attribute.find("Information[@Name='unit']")
            got[(base, attribute.get("Name"))] = info.get("Value") if info is not None else ""
    return got


def blocks(reader, t):
    """[(grid name, dataset)] of the reader's output at time t"""
    reader.UpdateTimeStep(t)
    data = reader.GetOutputDataObject(0)
    out = []
    for b in range(data.GetNumberOfBlocks()):
        name = data.GetMetaData(b).Get(data.NAME()) if data.HasMetaData(b) else "grid%d" % b
        out.append((name.rsplit("_step_", 1)[0], data.GetBlock(b)))
    return out


def draw(dataset, field, title, path, size):
    from vtkmodules.vtkCommonCore import vtkLookupTable
    from vtkmodules.vtkFiltersCore import vtkArrayCalculator
    from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
    from vtkmodules.vtkRenderingCore import (vtkActor, vtkDataSetMapper, vtkRenderer, vtkRenderWindow,
                                             vtkWindowToImageFilter)
    from vtkmodules.vtkIOImage import vtkPNGWriter
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the rendering backend)
    import vtkmodules.vtkRenderingFreeType  # noqa: F401 (the colour bar's text)

    array = dataset.GetPointData().GetArray(field)
    components = array.GetNumberOfComponents()
    shown, label = field, title
    if components > 1:   # colour by the magnitude (vectors) or the Frobenius norm (tensors)
        calc = vtkArrayCalculator()
        calc.SetInputData(dataset)
        calc.SetAttributeTypeToPointData()
        calc.AddScalarArrayName(field) if components == 1 else calc.AddVectorArrayName(field)
        if components == 3:
            calc.SetFunction("mag(%s)" % field)
        else:
            for k in range(components):
                calc.AddScalarVariable("c%d" % k, field, k)
            calc.SetFunction("sqrt(" + "+".join("c%d*c%d" % (k, k) for k in range(components)) + ")")
        shown = field + "_norm"
        calc.SetResultArrayName(shown)
        calc.Update()
        dataset = calc.GetOutput()
        label = ("|%s|" if components == 3 else "||%s||") % title
    lo, hi = dataset.GetPointData().GetArray(shown).GetRange()
    if hi <= lo:
        hi = lo + (abs(lo) or 1.0) * 1e-12
    table = vtkLookupTable()
    table.SetHueRange(0.667, 0.0)
    table.SetTableRange(lo, hi)
    table.Build()
    mapper = vtkDataSetMapper()
    mapper.SetInputData(dataset)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(shown)
    mapper.SetScalarRange(lo, hi)
    mapper.SetLookupTable(table)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetLineWidth(4)
    bar = vtkScalarBarActor()
    bar.SetLookupTable(table)
    bar.SetTitle(label)
    bar.SetNumberOfLabels(5)
    bar.SetOrientationToHorizontal()
    bar.SetPosition(0.1, 0.02)
    bar.SetWidth(0.8)
    bar.SetHeight(0.14)
    for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        text.SetColor(0, 0, 0)
        text.SetFontSize(14)
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    renderer.AddActor(actor)
    renderer.AddViewProp(bar)
    renderer.SetViewport(0, 0, 1, 1)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    x0, x1, y0, y1, z0, z1 = dataset.GetBounds()
    renderer.ResetCamera()
    if z1 - z0 < 1e-12 * max(x1 - x0, y1 - y0, 1e-300):   # 2D: seen from +z, the bar below
        camera.ParallelProjectionOn()
        width, height = x1 - x0, y1 - y0
        scale = max(height * 0.65, width / 2 * size[1] / size[0] * 1.1)
        fx, fy, fz = camera.GetFocalPoint()
        px, py, pz = camera.GetPosition()
        down = 0.25 * scale   # room for the colour bar
        camera.SetFocalPoint(fx, fy - down, fz)
        camera.SetPosition(px, py - down, pz)
        camera.SetParallelScale(scale)
    else:
        camera.Azimuth(30)
        camera.Elevation(25)
        renderer.ResetCamera()
    renderer.ResetCameraClippingRange()
    window.Render()
    image = vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("output_dir")
    ap.add_argument("--time", type=float, default=None)
    ap.add_argument("--out", default=None)
    ap.add_argument("--size", default="900x450")
    a = ap.parse_args()
    xdmf = os.path.join(a.output_dir, "fields.xdmf")
    if not os.path.isfile(xdmf):
        fail("%s: no such file (a run with -write_fields that completed writes it)" % xdmf)
    try:
        size = tuple(int(v) for v in a.size.lower().split("x"))
        assert len(size) == 2 and min(size) >= 100
    except (ValueError, AssertionError):
        fail("--size %s: expected WIDTHxHEIGHT, each at least 100" % a.size)
    try:
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    except ImportError:
        fail("no VTK XDMF reader: `make deps` puts PyPI's vtk into .deps/venv")
    try:
        unit = units(xdmf)
    except ET.ParseError as e:
        fail("%s: not valid XML: %s" % (xdmf, e))
    reader = vtkXdmfReader()
    reader.SetFileName(xdmf)
    reader.UpdateInformation()
    times = list(reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS()) or [])
    if not times:
        fail("%s: no written time" % xdmf)
    if a.time is not None and not times[0] - 1e-12 <= a.time <= times[-1] + 1e-12:
        fail("--time %g: the run wrote times %g to %g" % (a.time, times[0], times[-1]))
    t = times[-1] if a.time is None else min(times, key=lambda s: abs(s - a.time))
    out = a.out or os.path.join(a.output_dir, "figures")
    os.makedirs(out, exist_ok=True)
    for grid, dataset in blocks(reader, t):
        fields = dataset.GetPointData()
        for k in range(fields.GetNumberOfArrays()):
            field = fields.GetArrayName(k)
            u = unit.get((grid, field), "")
            title = "%s %s at t = %.6g%s" % (grid, field, t, " [%s]" % u if u and u != "nondimensional" else "")
            path = os.path.join(out, "%s_%s.png" % (grid, field))
            draw(dataset, field, title, path, size)
            print(path)


if __name__ == "__main__":
    main()
