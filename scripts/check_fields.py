#!/usr/bin/env python3
"""Checks <output_dir>/fields.xdmf against <output_dir>/fields.h5 (fsiopt -write_fields).

usage: scripts/check_fields.py OUTPUT_DIR

Fails (exit 1, one line) when the XDMF does not parse, refers to a dataset the HDF5 file
lacks or gives it other dimensions, when a topology refers to a vertex the geometry lacks,
or when a value is not finite. Otherwise prints a summary: times, grids, max |velocity|."""
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np


def fail(message):
    print(f"check_fields: {message}", file=sys.stderr)
    sys.exit(1)


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


def main():
    if len(sys.argv) != 2:
        fail("usage: check_fields.py OUTPUT_DIR")
    out = sys.argv[1]
    xdmf, h5name = os.path.join(out, "fields.xdmf"), os.path.join(out, "fields.h5")
    for path in (xdmf, h5name):
        if not os.path.isfile(path):
            partial = " (fields.*.partial only: the run did not complete)" if any(os.path.isfile(p + ".partial") for p in (xdmf, h5name)) else ""
            fail(f"{path}: no such file{partial}")
    try:
        root = ET.parse(xdmf).getroot()
    except ET.ParseError as e:
        fail(f"{xdmf}: not valid XML: {e}")
    series = root.find("Domain/Grid")
    if series is None or series.get("CollectionType") != "Temporal":
        fail(f"{xdmf}: expected Domain/Grid with CollectionType=\"Temporal\"")

    times, grids, vmax = [], set(), {}
    with h5py.File(h5name, "r") as h5:
        for step in series.findall("Grid"):
            time = step.find("Time")
            if time is None:
                fail(f"{xdmf}: grid {step.get('Name')} has no Time")
            t = float(time.get("Value"))
            if times and t <= times[-1]:
                fail(f"{xdmf}: grid {step.get('Name')}: time {t} does not increase")
            times.append(t)
            for grid in step.findall("Grid"):
                name = grid.get("Name")
                where = f"{step.get('Name')}/{name}"
                grids.add(name)
                topology = grid.find("Topology")
                geometry = grid.find("Geometry")
                if topology is None or geometry is None:
                    fail(f"{where}: needs a Topology and a Geometry")
                cells = dataset(h5, topology.find("DataItem"), where + " topology")
                if cells.shape != (int(topology.get("NumberOfElements")), int(topology.get("NodesPerElement"))):
                    fail(f"{where}: topology shape {cells.shape} disagrees with NumberOfElements/NodesPerElement")
                x = dataset(h5, geometry.find("DataItem"), where + " geometry")
                if cells.size and (cells.min() < 0 or cells.max() >= x.shape[0]):
                    fail(f"{where}: topology refers to vertices outside 0..{x.shape[0] - 1}")
                for attribute in grid.findall("Attribute"):
                    a = dataset(h5, attribute.find("DataItem"), f"{where} {attribute.get('Name')}")
                    if a.shape[0] != x.shape[0]:
                        fail(f"{where}: attribute {attribute.get('Name')} has {a.shape[0]} values for {x.shape[0]} vertices")
                    if attribute.get("Name") == "velocity":
                        vmax[name] = max(vmax.get(name, 0.0), float(np.max(np.linalg.norm(a, axis=1))) if a.size else 0.0)
    if not times:
        fail(f"{xdmf}: no time in the series")
    print(f"check_fields: {out}: {len(times)} times in [{times[0]:g}, {times[-1]:g}], grids {', '.join(sorted(grids))}"
          + "".join(f", max |velocity| ({g}) {v:.6e}" for g, v in sorted(vmax.items())))
    return 0 if all(math.isfinite(v) for v in vmax.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
