#!/usr/bin/env python3
"""Figures 6.3-6.4 of the seed dissertation: the pressure wave in the 3D tube (scene tube3d).

The tube: fluid cylinder r <= 0.5, z in [0,5], in an elastic wall 0.5 <= r <= 0.6 (hexahedral
O-grids, meshes/tube3d-*.msh); an overpressure of 1.333e4 dyn/cm^2 on the inlet z = 0 for
t <= 0.003 s, dt = 1e-4 (options/tube3d.yaml). From the fields that `bin/fsiopt -write_fields`
writes (RUNDIR/fields.h5), at the written steps nearest to --times (default 0.0005, 0.001,
0.002, 0.003; the times after the run's end are left out), draws:

  tube3d-wave.png       Fig 6.3 style, one curve per time: (a) the wall's radial displacement
                        on the interface r = 0.5 against z: its mean over the angle (line) and
                        its min..max over the angle (band), (b) the fluid pressure on the axis
                        (the fluid vertices on x = y = 0 at rest, else the nearest to the axis)
                        against z. The wave runs down the tube and the wall bulges behind it.
  tube3d-snapshots.png  Fig 6.4 style, one panel per time: the longitudinal cut y = 0 (the
                        fluid's and the wall's hexahedron faces on y = 0 at rest; the O-grids
                        have a vertex row there) in the (z, x) plane, the fluid coloured by its
                        pressure and the wall in grey (dashed: at rest), the displacements drawn
                        times --scale (default 10, as the seed did); one colour scale shared by
                        the panels (--color-scale panel: one each).
  tube3d-wave.csv       per time and z (at rest): mean, min and max radial wall displacement
                        and the axis pressure.
  tube3d-snapshots.csv  per time: the pressure range on the cut, the axis pressure at the
                        inlet, where the axis pressure first falls below half of it (the wave
                        front), the largest mean radial displacement and its z, and the largest
                        gap between the fluid's interface vertices and the wall's (0 when the
                        fluid mesh follows the wall).
  tube3d-runs.csv       the run's wall time and summary numbers (without RUNDIR).

Without RUNDIR runs

  bin/fsiopt -options_file options/tube3d.yaml -t_final T -write_fields
             -write_fields_interval K [--extra] -output_dir <runs-dir>/tube3d-T<T>-f<K>

with K the gcd of the steps of the times (5 for the defaults; the first and the last step are
always written), re-used when complete and run with the same command line (cmd.txt) unless
--force. A time outside the run, a failed run (its `fsiopt: error:` message is printed) or
unreadable fields make the script exit non-zero; a requested time that is not a written step
of a RUNDIR is a note (the nearest written step is drawn, its time in the panel title).

Examples (build first: make all; the default 30 steps on the coarse mesh take a few minutes):
  scripts/tube3d_figures.py
  scripts/tube3d_figures.py --t-final 0.0005 --times 0.0002,0.0005 --out /tmp/t3f
  scripts/tube3d_figures.py out/tube3d-run --times 0.001,0.003 --scale 20"""
import argparse, csv, hashlib, math, os, re, shlex, sys, textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import channel2d_figures as C   # noqa: E402
import channel2d_pressure as P   # noqa: E402  (the pressure figure's frame)
import fsiopt_runs as fr   # noqa: E402
import fsiopt_tables as ft   # noqa: E402  (the run's scene and units)

ROOT = fr.ROOT
OPTIONS_FILE = "options/tube3d.yaml"
DEFAULT_TIMES = [0.0005, 0.001, 0.002, 0.003]
R_INTERFACE = 0.5   # fluid radius = interface (meshes/tube3d-section.geoinc)
# vertices "on" a plane or the axis: gmsh puts the arcs' vertices on y = 0 only to ~1e-9
# (1.17e-9 on the coarse mesh), so the tolerance is relative to the tube's size, not 1e-9
REL_TOL = 1e-6


# ---------------------------------------------------------------------------- the run
def run_time_grid(extra):
    """(t_start, dt) of our runs: -t_start / -dt in the extra options, else the options file's."""
    return fr.run_time_grid(OPTIONS_FILE, extra)


def run_times(args):
    """The times to draw for our run: --times (sys.exit on one outside the run), else the
    default times up to --t-final (else t_final alone)."""
    t_start, _ = run_time_grid(shlex.split(args.extra))
    if args.times:
        for t in args.times:
            if not t_start - 1e-12 <= t <= args.t_final + 1e-12:
                sys.exit("tube3d_figures: t = %g is outside the run [%g, %g]" % (t, t_start, args.t_final))
        return args.times
    return [t for t in DEFAULT_TIMES if t_start < t <= args.t_final * (1 + 1e-9)] or [args.t_final]


def fields_interval(args, times):
    return fr.fields_interval(*run_time_grid(shlex.split(args.extra)), args.t_final, times, "tube3d_figures")


def tube_variant(args, times):
    extra = shlex.split(args.extra)
    k = fields_interval(args, times)
    name = "tube3d-T%.10g-f%d" % (args.t_final, k)
    if extra:
        name += "-x" + hashlib.sha1(" ".join(extra).encode()).hexdigest()[:8]
    options = ["-options_file", OPTIONS_FILE, "-t_final", "%.10g" % args.t_final,
               "-write_fields", "-write_fields_interval", str(k)] + extra
    label = "tube3d, T = %g, fields every %d steps%s" % (args.t_final, k, ", " + args.extra if extra else "")
    return fr.Variant(name, label, options, outputs=fr.OUTPUTS + ("fields.h5", "fields.xdmf"), fields=k)


# ---------------------------------------------------------------------------- fields.h5
def group_time(g):
    """The time of a step group: its 'time' attribute (fsiopt), else a 'time' dataset."""
    if "time" in g.attrs:
        return float(np.ravel(g.attrs["time"])[0])
    if "time" in g:
        return float(np.ravel(g["time"][()])[0])
    raise ValueError("%s: no time attribute or dataset" % g.name)


def read_fields(run_dir, times):
    """(snapshots, fluid topology, wall topology, fluid reference x, wall reference x, the
    written times). A snapshot: requested, time, step, fluid x (current) and p, wall x (current)
    and displacement. The fluid's reference is its first written step (the run starts at rest),
    the wall's is geometry - displacement."""
    import h5py
    path = fr.fields_file(run_dir)
    with h5py.File(path, "r") as f:
        for part in ("fluid", "structure"):
            if part not in f:
                raise ValueError("%s: no /%s group" % (fr.rel(path), part))
        fluid, wall = f["fluid"], f["structure"]
        steps = sorted((int(k[5:]), group_time(g)) for k, g in fluid.items() if k.startswith("step_"))
        if not steps:
            raise ValueError("%s: no /fluid/step_NNNNN groups" % fr.rel(path))
        if not times:
            written = [t for _, t in steps]
            times = [t for t in DEFAULT_TIMES if written[0] < t <= written[-1] * (1 + 1e-9)] or \
                [written[-1]]
        topo = np.asarray(fluid["topology"][:], dtype=int)
        wall_topo = np.asarray(wall["topology"][:], dtype=int)
        x_ref = np.asarray(fluid["step_%05d/geometry" % steps[0][0]][:], dtype=float)
        wall_ref = None
        snaps = []
        for t in times:
            n, tn = min(steps, key=lambda s: (abs(s[1] - t), s[0]))
            key = "step_%05d" % n
            if key not in wall:
                raise ValueError("%s: /fluid/%s has no /structure/%s" % (fr.rel(path), key, key))
            g, w = fluid[key], wall[key]
            snap = {"requested": t, "time": tn, "step": n, "x": np.asarray(g["geometry"][:], dtype=float),
                    "p": np.asarray(g["pressure"][:], dtype=float).ravel(),
                    "wall_x": np.asarray(w["geometry"][:], dtype=float),
                    "wall_d": np.asarray(w["displacement"][:], dtype=float)}
            if snap["x"].shape != x_ref.shape or snap["p"].shape[0] != x_ref.shape[0] or \
                    snap["wall_d"].shape != snap["wall_x"].shape:
                raise ValueError("%s: %s: inconsistent array sizes" % (fr.rel(path), key))
            if wall_ref is None:
                wall_ref = snap["wall_x"] - snap["wall_d"]
            snaps.append(snap)
    if x_ref.shape[1] != 3:
        raise ValueError("%s: %d-dimensional geometry, expected 3 (scene tube3d)" % (fr.rel(path), x_ref.shape[1]))
    return snaps, topo, wall_topo, x_ref, wall_ref, [tn for _, tn in steps]


# ---------------------------------------------------------------------------- analysis
def z_levels(z, tol):
    """(sorted distinct z values, index of each entry's level) of z values equal within tol."""
    order = np.argsort(z)
    level = np.zeros(len(z), dtype=int)
    levels = []
    for i in order:
        if not levels or z[i] - levels[-1][0] > tol:
            levels.append([z[i]])
        else:
            levels[-1].append(z[i])
        level[i] = len(levels) - 1
    return np.array([np.mean(l) for l in levels]), level


def interface_nodes(wall_ref, tol):
    """The wall's vertices on r = 0.5 at rest (else on its smallest radius)."""
    r = np.hypot(wall_ref[:, 0], wall_ref[:, 1])
    sel = np.flatnonzero(np.abs(r - R_INTERFACE) < tol)
    return sel if len(sel) else np.flatnonzero(r < r.min() + tol)


def axis_nodes(x_ref, tol):
    """The fluid vertices on the axis at rest (else the nearest to it at each z)."""
    r = np.hypot(x_ref[:, 0], x_ref[:, 1])
    sel = np.flatnonzero(r < tol)
    if len(sel):
        return sel, True
    zs, level = z_levels(x_ref[:, 2], tol)
    return np.array([np.flatnonzero(level == k)[np.argmin(r[level == k])] for k in range(len(zs))]), False


def wave(snap, x_ref, wall_ref, iface, axis, tol):
    """The wall's radial displacement on the interface per z (mean, min, max over the angle)
    and the axis pressure per z, all on the z levels at rest."""
    xi = wall_ref[iface]
    er = xi[:, :2] / np.hypot(xi[:, 0], xi[:, 1])[:, None]
    ur = np.einsum("ij,ij->i", snap["wall_d"][iface, :2], er)
    zw, lw = z_levels(xi[:, 2], tol)
    mean = np.array([ur[lw == k].mean() for k in range(len(zw))])
    lo = np.array([ur[lw == k].min() for k in range(len(zw))])
    hi = np.array([ur[lw == k].max() for k in range(len(zw))])
    order = np.argsort(x_ref[axis, 2])
    return {"z_wall": zw, "ur_mean": mean, "ur_min": lo, "ur_max": hi,
            "z_axis": x_ref[axis[order], 2], "p_axis": snap["p"][axis[order]]}


def interface_gap(snap, x_ref, iface):
    """Largest distance of a fluid vertex on r = 0.5 (at rest) from the nearest wall vertex on
    the interface, current geometry: 0 when the fluid mesh follows the wall."""
    r = np.hypot(x_ref[:, 0], x_ref[:, 1])
    top = np.flatnonzero(r > R_INTERFACE * (1 - REL_TOL))
    if not len(top):
        return float("nan")
    w = snap["wall_x"][iface]
    d = np.linalg.norm(snap["x"][top][:, None, :] - w[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def wave_front(z, p):
    """The first z at which the axis pressure falls below half of its inlet value (linear
    interpolation); nan when it never does."""
    half = 0.5 * p[0]
    if not half > 0:
        return float("nan")
    for i in range(1, len(p)):
        if p[i] < half:
            return float(z[i - 1] + (half - p[i - 1]) * (z[i] - z[i - 1]) / (p[i] - p[i - 1]))
    return float("nan")


def plane_cut(cells, ref, tol):
    """The cells' faces on the plane y = 0 at rest: (quads as vertex index rows ordered around
    the face in the (z, x) plane, vertices on the plane)."""
    on = np.abs(ref[:, 1]) < tol
    hit = on[cells]
    rows = cells[hit.sum(axis=1) == 4]
    quads = rows[hit[hit.sum(axis=1) == 4]].reshape(-1, 4)
    if not len(quads):
        return np.zeros((0, 4), dtype=int), np.flatnonzero(on)
    pz, px = ref[quads, 2], ref[quads, 0]
    ang = np.arctan2(px - px.mean(axis=1, keepdims=True), pz - pz.mean(axis=1, keepdims=True))
    quads = np.take_along_axis(quads, np.argsort(ang, axis=1), axis=1)
    _, first = np.unique(np.sort(quads, axis=1), axis=0, return_index=True)   # a face of two cells
    return quads[np.sort(first)], np.flatnonzero(on)


def quad_edges(quads):
    """The edges of the quads that belong to one quad only (the cut's outline)."""
    e = np.concatenate([quads[:, [i, (i + 1) % 4]] for i in range(4)])
    e = np.sort(e, axis=1)
    u, count = np.unique(e, axis=0, return_counts=True)
    return u[count == 1]


# ---------------------------------------------------------------------------- figures
def label_of(s):
    text = "t = %.4g s" % s["time"]
    if abs(s["time"] - s["requested"]) > 1e-9:
        text += " (requested %g)" % s["requested"]
    return text


def plot_wave(snaps, waves, run_dir, png, axis_exact):
    units, scene = ft.run_units(run_dir), ft.run_scene(run_dir)
    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(9, 7.5))
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, max(len(snaps), 1)))
    for s, w, c in zip(snaps, waves, colours):
        a.fill_between(w["z_wall"], w["ur_min"], w["ur_max"], color=c, alpha=0.2, lw=0)
        a.plot(w["z_wall"], w["ur_mean"], color=c, lw=1.5, label=label_of(s))
        b.plot(w["z_axis"], w["p_axis"], "o-", color=c, lw=1.5, ms=3, label=label_of(s))
    a.axhline(0, color="k", lw=0.5)
    b.axhline(0, color="k", lw=0.5)
    a.set_ylabel("radial displacement (%s)" % units["length"])
    a.set_title("(a) wall on the interface r = 0.5: mean over the angle (band: min..max)", fontsize="medium")
    b.set_ylabel("pressure (%s)" % units["pressure"])
    b.set_title("(b) fluid pressure on the axis%s" % ("" if axis_exact else " (the vertices nearest to it)"),
                fontsize="medium")
    b.set_xlabel("z (%s, at rest)" % units["length"])
    for ax in (a, b):
        ax.grid(True, alpha=0.3)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        ax.legend(fontsize="small", loc="best")
    fig.suptitle(textwrap.fill("%s: the pressure wave (inlet z = 0); %s" % (scene, fr.rel(run_dir)), 90), fontsize="medium")
    fig.tight_layout()
    fig.savefig(png, dpi=130)
    plt.close(fig)


def plot_snapshots(snaps, topo, wall_topo, x_ref, wall_ref, tol, run_dir, png, scale, color_scale, cmap, mesh):
    """Fig 6.4 style: the cut y = 0 per time, (z, x) plane, pressure colours, wall in grey."""
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.tri import Triangulation
    units, scene = ft.run_units(run_dir), ft.run_scene(run_dir)
    quads, fluid_on = plane_cut(topo, x_ref, tol)
    wquads, wall_on = plane_cut(wall_topo, wall_ref, tol)
    if not len(fluid_on):
        raise ValueError("no fluid vertex on the plane y = 0 (|y| < %g)" % tol)
    wall_outline = quad_edges(wquads) if len(wquads) else np.zeros((0, 2), dtype=int)
    for s in snaps:   # exaggerated geometry: reference + scale * displacement, in the (z, x) plane
        xs = x_ref + scale * (s["x"] - x_ref)
        ws = wall_ref + scale * s["wall_d"]
        s["zx"], s["wall_zx"] = xs[:, [2, 0]], ws[:, [2, 0]]
    plim = (min(s["p"][fluid_on].min() for s in snaps), max(s["p"][fluid_on].max() for s in snaps))
    allzx = np.concatenate([s["zx"][fluid_on] for s in snaps] + [s["wall_zx"][wall_on] for s in snaps])
    lo, hi = allzx.min(axis=0), allzx.max(axis=0)
    pad = 0.03 * (hi - lo).max()
    aspect = (hi[1] - lo[1] + 2 * pad) / (hi[0] - lo[0] + 2 * pad)
    fig, axes = plt.subplots(len(snaps), 1, sharex=True, squeeze=False,
                             figsize=(10, len(snaps) * (8.5 * aspect + 0.6) + 1.0))
    im = None
    for ax, s in zip(axes[:, 0], snaps):
        vmin, vmax = plim if color_scale == "shared" else (s["p"][fluid_on].min(), s["p"][fluid_on].max())
        if vmax <= vmin:
            vmax = vmin + 1.0
        if len(quads):
            tri = Triangulation(s["zx"][:, 0], s["zx"][:, 1], np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]))
            im = ax.tripcolor(tri, s["p"], shading="gouraud", cmap=cmap, vmin=vmin, vmax=vmax)
            if mesh:
                ax.add_collection(PolyCollection(s["zx"][quads], facecolors="none", edgecolors="k", linewidths=0.25,
                                                 alpha=0.3))
        else:   # no cell face on the plane: the vertices on it, triangulated
            pts = s["zx"][fluid_on]
            im = ax.tricontourf(pts[:, 0], pts[:, 1], s["p"][fluid_on], levels=np.linspace(vmin, vmax, 31), cmap=cmap,
                                extend="both")
        if len(wquads):
            ax.add_collection(PolyCollection(s["wall_zx"][wquads], facecolors="0.75", edgecolors="0.35",
                                             linewidths=0.4))
            ax.add_collection(LineCollection(wall_ref[:, [2, 0]][wall_outline], colors="k", linewidths=0.6,
                                             linestyles="--"))
        else:
            ax.plot(s["wall_zx"][wall_on, 0], s["wall_zx"][wall_on, 1], "s", color="0.4", ms=2)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_aspect("equal")
        ax.set_ylabel("x (%s)" % units["length"])
        ax.set_title("%s (step %d)" % (label_of(s), s["step"]), fontsize="medium")
        if color_scale != "shared":
            fig.colorbar(im, ax=ax, label="pressure (%s)" % units["pressure"], fraction=0.03, pad=0.015)
    axes[-1, 0].set_xlabel("z (%s)" % units["length"])
    P.finish_pressure_figure(fig, axes, im, color_scale, "%s: fluid pressure on the cut y = 0" % scene, scale, run_dir,
                             png, units["pressure"])


def write_wave_csv(path, snaps, waves, tol):
    """One row per time and z level (at rest): the wall's levels and the axis vertices' levels
    merged (blank where one of them has no vertex)."""
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["requested_t", "t", "step", "z", "ur_mean", "ur_min", "ur_max", "p_axis"])
        for s, w in zip(snaps, waves):
            rows = {}
            for i, z in enumerate(w["z_wall"]):
                rows.setdefault(round(z / tol), [z, None, None])[1] = i
            for i, z in enumerate(w["z_axis"]):
                key = round(z / tol)
                key = next((k for k in (key - 1, key, key + 1) if k in rows), key)
                rows.setdefault(key, [z, None, None])[2] = i
            for key in sorted(rows):
                z, iw, ia = rows[key]
                row = ["%g" % s["requested"], "%.10g" % s["time"], s["step"], "%.10g" % z]
                row += ["%.6e" % w[k][iw] if iw is not None else "" for k in ("ur_mean", "ur_min", "ur_max")]
                row.append("%.6e" % w["p_axis"][ia] if ia is not None else "")
                out.writerow(row)


def write_snapshot_csv(path, snaps, waves, gaps, fluid_on):
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["requested_t", "t", "step", "p_min_cut", "p_max_cut", "p_axis_inlet", "z_front",
                      "max_ur_mean", "z_max_ur_mean", "max_ur", "min_ur", "interface_gap"])
        for s, w, gap in zip(snaps, waves, gaps):
            i = int(np.argmax(w["ur_mean"]))
            out.writerow(["%g" % s["requested"], "%.10g" % s["time"], s["step"], "%.6e" % s["p"][fluid_on].min(),
                          "%.6e" % s["p"][fluid_on].max(), "%.6e" % w["p_axis"][0],
                          "%.4g" % wave_front(w["z_axis"], w["p_axis"]), "%.6e" % w["ur_mean"][i],
                          "%.4g" % w["z_wall"][i], "%.6e" % w["ur_max"].max(), "%.6e" % w["ur_min"].min(),
                          "%.3e" % gap])


def figures(args, run_dir, times):
    """Both figures and the CSVs from run_dir/fields.h5; returns ok."""
    try:
        snaps, topo, wall_topo, x_ref, wall_ref, written = read_fields(run_dir, times)
        tol = REL_TOL * max(np.abs(x_ref).max(), np.abs(wall_ref).max())
        iface = interface_nodes(wall_ref, tol)
        axis, axis_exact = axis_nodes(x_ref, tol)
        waves = [wave(s, x_ref, wall_ref, iface, axis, tol) for s in snaps]
        gaps = [interface_gap(s, x_ref, iface) for s in snaps]
        base = os.path.join(args.out, "tube3d-")
        plot_wave(snaps, waves, run_dir, base + "wave.png", axis_exact)
        write_wave_csv(base + "wave.csv", snaps, waves, tol)
        plot_snapshots(snaps, topo, wall_topo, x_ref, wall_ref, tol, run_dir, base + "snapshots.png", args.scale,
                       args.color_scale, args.cmap, args.mesh)
        write_snapshot_csv(base + "snapshots.csv", snaps, waves, gaps, np.flatnonzero(np.abs(x_ref[:, 1]) < tol))
    except (OSError, ValueError, KeyError) as e:
        print("tube3d_figures: %s" % e, file=sys.stderr)
        return False
    for s in snaps:
        if abs(s["time"] - s["requested"]) > 1e-9:
            print("tube3d_figures: note: t = %g is not written, drawn: the nearest written step %d at t = %g "
                  "(%s has t = %s)" % (s["requested"], s["step"], s["time"], fr.rel(run_dir),
                                       ", ".join("%g" % t for t in written[:12]) + (", ..." if len(written) > 12 else "")),
                  file=sys.stderr)
    if not axis_exact:
        print("tube3d_figures: note: no fluid vertex on the axis; the axis pressure is taken at the vertex nearest "
              "to it at each z", file=sys.stderr)
    with open(base + "snapshots.csv") as f:
        print(f.read().rstrip())
    print("written: %s" % ", ".join(fr.rel(base + e) for e in ("wave.png", "wave.csv", "snapshots.png",
                                                                  "snapshots.csv")))
    return True


# ---------------------------------------------------------------------------- main
def floats(text):
    return [float(x) for x in text.replace(",", " ").split()]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("rundir", nargs="?", metavar="RUNDIR", help="a finished run with fields.h5 (default: run "
                    "options/tube3d.yaml with -write_fields)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "figures"), help="output directory (default out/figures)")
    ap.add_argument("--times", type=floats, help="times of the curves and panels (default 0.0005,0.001,0.002,0.003, "
                    "those up to the run's end); the nearest written step is drawn")
    ap.add_argument("--t-final", type=float, default=0.003, help="end time of the run (default 0.003 = 30 steps: "
                    "the inlet pulse)")
    ap.add_argument("--bin", default=fr.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--extra", default="", help='options passed to the run, e.g. --extra="-fluid_dm_plex_filename F '
                    '-structure_dm_plex_filename W"')
    ap.add_argument("--runs-dir", default=None, help="where the run goes (default <out>/runs)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error (default 2)")
    ap.add_argument("--scale", type=float, default=10.0, help="snapshots: displacement drawn times SCALE (default 10, "
                    "as the seed; 1: the true geometry)")
    ap.add_argument("--color-scale", choices=("shared", "panel"), default="shared",
                    help="snapshots: one colour scale for all panels (default) or one per panel")
    ap.add_argument("--cmap", default="turbo", help="snapshots: matplotlib colour map (default turbo)")
    ap.add_argument("--no-mesh", dest="mesh", action="store_false", help="snapshots: do not draw the fluid cells' edges")
    args = ap.parse_args()
    args.out = os.path.abspath(args.out)
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
    args.bin = os.path.abspath(args.bin)
    os.makedirs(args.out, exist_ok=True)
    if args.rundir:
        ok = figures(args, args.rundir, args.times)
    else:
        times = run_times(args)
        v = tube_variant(args, times)
        fr.run_all([v], args.bin, args.runs_dir, 1, args.force, args.retries)
        fr.write_runs_csv(os.path.join(args.out, "tube3d-runs.csv"), [v])
        print("written: %s" % fr.rel(os.path.join(args.out, "tube3d-runs.csv")))
        if v.ok:
            if v.summary.get("stalled_steps"):
                print("tube3d_figures: note: %d stalled steps (coupling not converged), see %s"
                      % (v.summary["stalled_steps"], fr.rel(v.run_dir)), file=sys.stderr)
            ok = figures(args, v.run_dir, times)
        else:
            print("tube3d_figures: the run %s failed: %s" % (v.name, v.error), file=sys.stderr)
            ok = False
    if not ok:
        print("tube3d_figures: there were failures (see above)", file=sys.stderr)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
