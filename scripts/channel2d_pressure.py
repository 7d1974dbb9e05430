#!/usr/bin/env python3
"""channel2d's pressure figure (scripts/channel2d_figures.py pressure | all): the fluid
pressure on the deformed mesh at a few times, read from a run's fields.h5, with the
wall's outline and the interface gap between fluid and wall; its CSV of the snapshots."""
import csv, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402
import fsiopt_tables as ft  # noqa: E402  (the run's scene and units)


def default_times(t_start, t_final):
    return [t_start + f * (t_final - t_start) for f in (0.25, 0.5, 0.75)]


def boundary_edges(cells):
    """The edges (vertex pairs) of a cell mesh that belong to one cell only."""
    count = {}
    for c in cells:
        for a, b in zip(c, np.roll(c, -1)):
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    return np.array([e for e, k in count.items() if k == 1], dtype=int).reshape(-1, 2)


def read_fields(run_dir, times):
    """Snapshots of run_dir/fields.h5 at the written steps nearest to the times (default
    T/4, T/2, 3T/4 of the written range): (snapshots, fluid topology, wall topology or
    None, wall reference coordinates or None). A snapshot is a dict: requested, time, step,
    fluid x (current), fluid x0 (first written step: the reference when the run starts at
    rest), p, wall x, wall displacement."""
    import h5py   # only this subcommand needs it
    path = fr.fields_file(run_dir)
    with h5py.File(path, "r") as f:
        if "fluid" not in f:
            raise ValueError("%s: no /fluid group" % fr.rel(path))
        fluid, wall = f["fluid"], f.get("structure")
        steps = sorted((int(k[5:]), float(g.attrs["time"])) for k, g in fluid.items() if k.startswith("step_"))
        if not steps:
            raise ValueError("%s: no /fluid/step_NNNNN groups" % fr.rel(path))
        if not times:
            times = default_times(steps[0][1], steps[-1][1])
        topo = np.asarray(fluid["topology"][:], dtype=int)
        dim = fluid["step_%05d/geometry" % steps[0][0]].shape[1]
        if dim != 2:
            raise ValueError("%s: %d-dimensional geometry, this figure draws 2-dimensional runs (tube3d: "
                             "scripts/tube3d_figures.py)" % (fr.rel(path), dim))
        x0 = np.asarray(fluid["step_%05d/geometry" % steps[0][0]][:, :2], dtype=float)
        wall_topo = np.asarray(wall["topology"][:], dtype=int) if wall is not None else None
        snaps = []
        for t in times:
            n, tn = min(steps, key=lambda s: (abs(s[1] - t), s[0]))
            g = fluid["step_%05d" % n]
            snap = {"requested": t, "time": tn, "step": n, "x": np.asarray(g["geometry"][:, :2], dtype=float), "x0": x0,
                    "p": np.asarray(g["pressure"][:], dtype=float).ravel(), "wall_x": None, "wall_d": None}
            if wall is not None and "step_%05d" % n in wall:
                w = wall["step_%05d" % n]
                snap["wall_x"] = np.asarray(w["geometry"][:, :2], dtype=float)
                snap["wall_d"] = np.asarray(w["displacement"][:, :2], dtype=float)
            snaps.append(snap)
    return snaps, topo, wall_topo, [tn for _, tn in steps]


def interface_gap(snap):
    """Largest distance of a fluid vertex on the deformed wall (reference y = max y) from the
    nearest wall vertex: 0 when the fluid mesh follows the wall exactly."""
    if snap["wall_x"] is None:
        return float("nan")
    top = snap["x0"][:, 1] > snap["x0"][:, 1].max() - 1e-9
    d = np.linalg.norm(snap["x"][top][:, None, :] - snap["wall_x"][None, :, :], axis=2)
    return float(d.min(axis=1).max())


def write_pressure(run_dir, times, name, out, scale=1.0, color_scale="shared", cmap="turbo", mesh=True):
    """Fig 3.4: the fluid pressure on the deformed fluid mesh and the deformed wall at the
    written steps nearest to the times, one panel per time; PNG + CSV. Returns notes on the
    requested times that are not written steps (the nearest one is drawn)."""
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.tri import Triangulation
    snaps, topo, wall_topo, written = read_fields(run_dir, times)
    units, scene = ft.run_units(run_dir), ft.run_scene(run_dir)
    notes = ["t = %g is not written, drawn: the nearest written step %d at t = %g (%s has t = %s)"
             % (s["requested"], s["step"], s["time"], fr.rel(run_dir),
                ", ".join("%g" % t for t in written[:12]) + (", ..." if len(written) > 12 else ""))
             for s in snaps if abs(s["time"] - s["requested"]) > 1e-9]
    tris = np.concatenate([topo[:, [0, 1, 2]], topo[:, [0, 2, 3]]]) if topo.shape[1] == 4 else topo
    wall_ref = snaps[0]["wall_x"] - snaps[0]["wall_d"] if snaps[0]["wall_x"] is not None else None
    wall_edges = boundary_edges(wall_topo) if wall_topo is not None else None
    plim = (min(s["p"].min() for s in snaps), max(s["p"].max() for s in snaps))
    for s in snaps:   # exaggerated geometry: reference + scale * displacement
        s["xs"] = s["x0"] + scale * (s["x"] - s["x0"])
        s["wall_xs"] = None if s["wall_x"] is None else wall_ref + scale * s["wall_d"]
    allx = np.concatenate([s["xs"] for s in snaps] + [s["wall_xs"] for s in snaps if s["wall_xs"] is not None])
    lo, hi = allx.min(axis=0), allx.max(axis=0)
    pad = 0.04 * (hi - lo).max()
    aspect = (hi[1] - lo[1] + 2 * pad) / (hi[0] - lo[0] + 2 * pad)
    fig, axes = plt.subplots(len(snaps), 1, sharex=True, squeeze=False,
                             figsize=(9.5, len(snaps) * (8.0 * aspect + 0.55) + 0.9))
    for ax, s in zip(axes[:, 0], snaps):
        vmin, vmax = plim if color_scale == "shared" else (s["p"].min(), s["p"].max())
        tri = Triangulation(s["xs"][:, 0], s["xs"][:, 1], tris)
        im = ax.tripcolor(tri, s["p"], shading="gouraud", cmap=cmap, vmin=vmin, vmax=vmax)
        if mesh:
            ax.add_collection(PolyCollection(s["xs"][topo], facecolors="none", edgecolors="k", linewidths=0.25,
                                             alpha=0.25))
        if s["wall_xs"] is not None:
            ax.add_collection(PolyCollection(s["wall_xs"][wall_topo], facecolors="0.75", edgecolors="0.35",
                                             linewidths=0.4))
            ax.add_collection(LineCollection(wall_ref[wall_edges], colors="k", linewidths=0.6, linestyles="--"))
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_aspect("equal")
        ax.set_ylabel("Height (%s)" % units["length"])
        title = "t = %.4g s (step %d)" % (s["time"], s["step"])
        if abs(s["time"] - s["requested"]) > 1e-9:
            title += ", requested t = %g" % s["requested"]
        ax.set_title(title, fontsize="medium")
        if color_scale != "shared":
            fig.colorbar(im, ax=ax, label="pressure (%s)" % units["pressure"], fraction=0.035, pad=0.015)
    axes[-1, 0].set_xlabel("Length (%s)" % units["length"])
    base = os.path.join(out, name)
    finish_pressure_figure(fig, axes, im, color_scale, "%s: fluid pressure on the deformed mesh" % scene, scale, run_dir,
                           base + ".png", units["pressure"])
    with open(base + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["requested_t", "t", "step", "p_min", "p_max", "x_p_max", "max_wall_displacement", "max_wall_dy",
                    "x_max_wall_dy", "min_wall_dy", "interface_gap"])
        for s in snaps:
            row = ["%g" % s["requested"], "%.10g" % s["time"], s["step"], "%.6e" % s["p"].min(), "%.6e" % s["p"].max(),
                   "%.4g" % s["x"][int(s["p"].argmax()), 0]]
            if s["wall_d"] is not None:
                d, i = s["wall_d"], int(s["wall_d"][:, 1].argmax())
                row += ["%.6e" % np.linalg.norm(d, axis=1).max(), "%.6e" % d[i, 1], "%.4g" % (s["wall_x"][i, 0] - d[i, 0]),
                        "%.6e" % d[:, 1].min(), "%.3e" % interface_gap(s)]
            else:
                row += [""] * 5
            w.writerow(row)
    with open(base + ".csv") as f:
        print(f.read().rstrip())
    print("written: %s, %s" % (fr.rel(base + ".png"), fr.rel(base + ".csv")))
    return notes


def finish_pressure_figure(fig, axes, im, color_scale, heading, scale, run_dir, png, pressure_unit="dyn/cm$^2$"):
    """The shared colour bar (color_scale "shared"; per-panel bars are the caller's), the
    title, and the PNG of a column of pressure panels."""
    if color_scale == "shared":
        fig.colorbar(im, ax=axes[:, 0].tolist(), label="pressure (%s)" % pressure_unit, fraction=0.035, pad=0.015,
                     aspect=30)
    fig.suptitle("%s, wall in grey (dashed: at rest)\n%s colour scale, displacement %s; %s"
                 % (heading, "shared" if color_scale == "shared" else "per-panel",
                    "true size" if scale == 1 else "x %g" % scale, fr.rel(run_dir)), fontsize="medium")
    fig.savefig(png, dpi=150, bbox_inches="tight")
    plt.close(fig)


def pressure_figure(args, run_dir, name, times):
    """write_pressure with the options of args; returns ok (a time that is not a written
    step is a note, not a failure)."""
    try:
        notes = write_pressure(run_dir, times, name, args.out, args.scale, args.color_scale, args.cmap, args.mesh)
    except (OSError, ValueError, KeyError) as e:
        print("channel2d_figures: pressure: %s" % e, file=sys.stderr)
        return False
    for n in notes:
        print("channel2d_figures: pressure: note: %s" % n, file=sys.stderr)
    return True


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "scripts/channel2d_figures.py (its subcommands pressure and all, which draw the figure) and by scripts/tube3d_figures.py")
