#!/usr/bin/env python3
"""Checks <output_dir>/fields.xdmf against <output_dir>/fields.h5 (fsiopt -write_fields).

usage: scripts/check_fields.py [--readers auto|require|off] OUTPUT_DIR

Fails (exit 1, one line) when the XDMF does not parse, names a grid twice, lists a time
twice or out of order, refers to a dataset the HDF5 file lacks or gives it other
dimensions, declares an attribute ParaView would not colour by (not Center="Node", a
Vector without 3 components, a Tensor without 9, a Scalar with more than one) or one without
its unit (<Information Name="unit">), when a topology refers to a
vertex the geometry lacks, or when a value is not finite.
Then it opens the XDMF with the readers ParaView offers for it that this VTK has: XDMFReader
(vtkXdmfReader, Xdmf2), Xdmf3ReaderS and Xdmf3ReaderT (vtkXdmf3Reader with
FileSeriesAsTime 0 and 1), and fails unless each gives every time, each grid with its
points (the geometry), cells and attributes equal to the HDF5 datasets (1e-12). XDMFReader
comes with PyPI's vtk wheel, which `make deps` puts into .deps/venv (run this script with
PYTHONPATH=.deps/venv/lib/python3.X/site-packages), all three with Debian's python3-paraview;
without any (--readers auto) that check is skipped and the summary says so; --readers
require fails instead, off skips it.
Otherwise prints a summary: times, grids, max |velocity|, the readers' verdict."""
import argparse
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

TOLERANCE = 1e-12  # relative: the readers copy the doubles, nothing is computed


def fail(message):
    print(f"check_fields: {message}", file=sys.stderr)
    sys.exit(1)


class ArgumentParser(argparse.ArgumentParser):
    """argparse with check_fields' one-line failure (exit 1) on a wrong command line."""

    def error(self, message):
        fail(f"{message} (usage: check_fields.py [--readers auto|require|off] OUTPUT_DIR)")


def dataset(h5, item, where):
    """The array an HDF DataItem refers to, after checking its dimensions."""
    text = (item.text or "").strip()
    if item.get("Format") != "HDF" or ":" not in text:
        fail(f"{where}: expected an HDF DataItem 'file:/path', got '{text}'")
    fname, path = text.split(":", 1)
    if fname != os.path.basename(h5.filename):
        fail(f"{where}: refers to file {fname}, expected {os.path.basename(h5.filename)}")
    if path not in h5 or not isinstance(h5[path], h5py.Dataset):
        fail(f"{where}: dataset {path} missing from {h5.filename}")
    dims = tuple(int(d) for d in item.get("Dimensions", "").split())
    data = h5[path][()]
    if data.shape != dims:
        fail(f"{where}: dataset {path} has shape {data.shape}, the XDMF says {dims}")
    if data.dtype.kind == "f" and not np.all(np.isfinite(data)):
        fail(f"{where}: dataset {path} has values that are not finite")
    return data


def base_name(name):
    """fluid_step_00010 -> fluid: the grid a per-time name belongs to"""
    return re.sub(r"_step_\d+$", "", name)


def read_series(xdmf, h5name):
    """[(time, [(grid name, cells, geometry, {attribute: data})])] after the XML-vs-HDF5 checks"""
    try:
        root = ET.parse(xdmf).getroot()
    except ET.ParseError as e:
        fail(f"{xdmf}: not valid XML: {e}")
    series = root.find("Domain/Grid")
    if series is None or series.get("CollectionType") != "Temporal":
        fail(f"{xdmf}: expected Domain/Grid with CollectionType=\"Temporal\"")
    names = [g.get("Name") for g in root.iter("Grid")]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        fail(f"{xdmf}: grid names used more than once: {', '.join(map(str, twice))}")
    out = []
    with h5py.File(h5name, "r") as h5:
        for step in series.findall("Grid"):
            time = step.find("Time")
            if time is None:
                fail(f"{xdmf}: grid {step.get('Name')} has no Time")
            t = float(time.get("Value"))
            if out and t <= out[-1][0]:
                fail(f"{xdmf}: grid {step.get('Name')}: time {t} is listed after {out[-1][0]}")
            grids = []
            for grid in step.findall("Grid"):
                name = grid.get("Name")
                where = f"{step.get('Name')}/{name}"
                topology, geometry = grid.find("Topology"), grid.find("Geometry")
                if topology is None or geometry is None:
                    fail(f"{where}: needs a Topology and a Geometry")
                cells = dataset(h5, topology.find("DataItem"), where + " topology")
                if cells.shape != (int(topology.get("NumberOfElements")), int(topology.get("NodesPerElement"))):
                    fail(f"{where}: topology shape {cells.shape} disagrees with NumberOfElements/NodesPerElement")
                x = dataset(h5, geometry.find("DataItem"), where + " geometry")
                if cells.size and (cells.min() < 0 or cells.max() >= x.shape[0]):
                    fail(f"{where}: topology refers to vertices outside 0..{x.shape[0] - 1}")
                attributes = {}
                for attribute in grid.findall("Attribute"):
                    aname, kind = attribute.get("Name"), attribute.get("AttributeType")
                    a = dataset(h5, attribute.find("DataItem"), f"{where} {aname}")
                    if a.shape[0] != x.shape[0]:
                        fail(f"{where}: attribute {aname} has {a.shape[0]} values for {x.shape[0]} vertices")
                    columns = a.shape[1] if a.ndim > 1 else 1
                    if attribute.get("Center") != "Node" or \
                            (kind, columns) not in (("Scalar", 1), ("Vector", 3), ("Tensor", 9)):
                        fail(f"{where}: attribute {aname}: Center {attribute.get('Center')}, {kind} of {columns} "
                             "components; ParaView colours by Node Scalars of 1, Vectors of 3 and Tensors of 9")
                    unit = attribute.find("Information[@Name='unit']")
                    if unit is None or not unit.get("Value"):
                        fail(f"{where}: attribute {aname} has no <Information Name=\"unit\" Value=...>")
                    attributes[aname] = a
                grids.append((name, cells, x, attributes))
            out.append((t, grids))
    if not out:
        fail(f"{xdmf}: no time in the series")
    return out


def paraview_readers():
    """{ParaView's name: a function making the reader of a file} for the XDMF readers this VTK
    has (PyPI's vtk wheel has XDMFReader only; Debian's python3-paraview all three), or the
    reason there is none"""
    try:
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
    except ImportError as e:
        return None, f"no VTK XDMF reader ({e}): make deps puts PyPI's vtk into .deps/venv"

    def xdmf2(path):
        r = vtkXdmfReader()
        r.SetFileName(path)
        return r
    readers = {"XDMFReader": xdmf2}
    try:
        from vtkmodules.vtkIOXdmf3 import vtkXdmf3Reader
    except ImportError:
        return readers, None

    def xdmf3(as_time):
        def make(path):
            r = vtkXdmf3Reader()
            r.SetFileName(path)
            r.SetFileSeriesAsTime(as_time)  # what ParaView's Xdmf3ReaderS (0) and Xdmf3ReaderT (1) set
            return r
        return make
    readers.update({"Xdmf3ReaderS": xdmf3(0), "Xdmf3ReaderT": xdmf3(1)})
    return readers, None


def leaves(data):
    """[(name or None, dataset)] of a composite output, in order"""
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkDataObjectTreeIterator
    it = vtkDataObjectTreeIterator()
    it.SetDataSet(data)
    it.InitTraversal()
    found = []
    while not it.IsDoneWithTraversal():
        meta = it.GetCurrentMetaData()
        name = meta.Get(vtkCompositeDataSet.NAME()) if meta is not None and meta.Has(vtkCompositeDataSet.NAME()) else None
        found.append((name, it.GetCurrentDataObject()))
        it.GoToNextItem()
    return found


def differs(got, want):
    scale = max(1.0, float(np.abs(want).max()) if want.size else 0.0)
    return got.shape != want.shape or (want.size and float(np.abs(got - want).max()) > TOLERANCE * scale)


def check_reader(label, make, xdmf, series):
    """Every time, grid, point, cell and attribute as the HDF5 datasets have them."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    reader = make(xdmf)
    reader.UpdateInformation()
    info, key = reader.GetOutputInformation(0), vtkStreamingDemandDrivenPipeline.TIME_STEPS()
    times = list(info.Get(key)) if info.Has(key) else []
    want = [t for t, _ in series]
    if len(times) != len(want) or any(abs(a - b) > TOLERANCE * max(1.0, abs(b)) for a, b in zip(times, want)):
        fail(f"{label}: times {times}, the XDMF lists {want}")
    for t, grids in series:
        reader.UpdateTimeStep(t)
        blocks = leaves(reader.GetOutputDataObject(0))
        if len(blocks) != len(grids):
            fail(f"{label} at t = {t:g}: {len(blocks)} blocks for {len(grids)} grids")
        for (name, data), (gname, cells, x, attributes) in zip(blocks, grids):
            where = f"{label} at t = {t:g}, {gname}"
            if name is not None and name != gname:
                fail(f"{where}: the reader names the block {name}")
            if data.GetNumberOfCells() != cells.shape[0]:
                fail(f"{where}: {data.GetNumberOfCells()} cells, the HDF5 topology has {cells.shape[0]}")
            points = vtk_to_numpy(data.GetPoints().GetData())[:, :x.shape[1]] if data.GetPoints() else np.zeros((0, 3))
            if differs(points, x):
                fail(f"{where}: points differ from the HDF5 geometry ({points.shape[0]} for {x.shape[0]})")
            for aname, a in attributes.items():
                array = data.GetPointData().GetArray(aname)
                if array is None:
                    fail(f"{where}: no point array {aname}")
                if differs(vtk_to_numpy(array).reshape(a.shape), a):
                    fail(f"{where}: point array {aname} differs from the HDF5 dataset")


def main():
    ap = ArgumentParser(description=re.sub(r"\n\nusage: [^\n]*", "", __doc__),
                        usage="%(prog)s [--readers auto|require|off] OUTPUT_DIR",
                        formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", metavar="OUTPUT_DIR", help="an fsiopt -output_dir written with -write_fields")
    ap.add_argument("--readers", choices=("auto", "require", "off"), default="auto",
                    help="the ParaView readers' check: auto (run it when VTK's XDMF readers are there, else skip "
                    "it; default), require (fail without the readers), off (skip it)")
    args = ap.parse_args()
    mode, out = args.readers, args.out
    xdmf, h5name = os.path.join(out, "fields.xdmf"), os.path.join(out, "fields.h5")
    for path in (xdmf, h5name):
        if not os.path.isfile(path):
            partial = " (fields.*.partial only: the run did not complete)" if any(os.path.isfile(p + ".partial") for p in (xdmf, h5name)) else ""
            fail(f"{path}: no such file{partial}")
    series = read_series(xdmf, h5name)
    vmax, grids = {}, set()
    for _, step in series:
        for name, _, _, attributes in step:
            grids.add(base_name(name))
            if "velocity" in attributes and attributes["velocity"].size:
                v = float(np.max(np.linalg.norm(attributes["velocity"], axis=1)))
                vmax[base_name(name)] = max(vmax.get(base_name(name), 0.0), v)
    readers, why = (None, "--readers off") if mode == "off" else paraview_readers()
    if readers is None and mode == "require":
        fail(f"readers: {why}")
    if readers:
        for label, make in readers.items():
            check_reader(label, make, xdmf, series)
        verdict = f"readers {', '.join(readers)} agree with the HDF5 datasets"
    else:
        verdict = f"readers skipped: {why}"
    times = [t for t, _ in series]
    print(f"check_fields: {out}: {len(times)} times in [{times[0]:g}, {times[-1]:g}], grids {', '.join(sorted(grids))}"
          + "".join(f", max |velocity| ({g}) {v:.6e}" for g, v in sorted(vmax.items())) + f"; {verdict}")
    return 0 if all(math.isfinite(v) for v in vmax.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
