#!/usr/bin/env python3
"""probes.csv of any run against time: every column (the probes, forces, integrals and 0D
outlets a case records), or those --columns selects, each labelled by its header as written
(name, point, unit). One run: a panel per quantity (dy, drag, Q, p_outlet, ...) with the
quantity and its unit on the y axis, a curve per column; several runs: a panel per column, a
curve per run. The title names the runs' scene and case (summary.json). Writes PNG + CSV of
the plotted values (+ <name>-runs.csv: the runs' summary numbers) into out/figures/ (--out).

  scripts/probes_figure.py out/bifurcation
  scripts/probes_figure.py out/turek-hron-fsi3 --columns dy,lift
  scripts/probes_figure.py out/channel2d out/channel2d-svk --labels linear svk --columns dy"""
import argparse, csv, os, sys, textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
import fsiopt_tables as ft   # noqa: E402  (probes.csv headers, scenes, units)


def probes_path(run_dir):
    path = os.path.join(run_dir, "probes.csv")
    if not os.path.isfile(path):
        extra = " (only probes.csv.partial: the run is unfinished or failed)" \
            if os.path.isfile(path + ".partial") else ""
        raise FileNotFoundError("%s: no such file%s" % (fr.rel(path), extra))
    return path


def read_columns(run_dir):
    """(t, [(name, unit, header, values)]) of run_dir/probes.csv: every column after t, its
    name ('dz(0.5;0.;1.25)'), unit ('cm', None without one) and header exactly as written."""
    path = probes_path(run_dir)
    t, cols = ft.read_probe_columns(path)
    return np.array(t), [(n, u, h, np.array(v)) for n, u, h, v in cols]


def read_probes(run_dir, kind="dy"):
    """(t, {column header: values}) of the columns of one quantity (default dy, the vertical
    displacement) of run_dir/probes.csv; the header as written, e.g. 'dy(1.5;1.) [cm]'."""
    t, cols = read_columns(run_dir)
    picked = {h: v for n, u, h, v in cols if ft.column_kind(n) == kind}
    if not picked:
        raise ValueError("%s: no %s(...) columns" % (fr.rel(probes_path(run_dir)), kind))
    return t, picked


def axis_label(kind, units):
    """'dy [cm]' from a quantity and the units of its columns (several: all of them)."""
    units = [u for u in dict.fromkeys(units) if u]
    return "%s [%s]" % (kind, ", ".join(units)) if units else kind


def plot_probes(curves, title, png, csv_path, columns=None):
    """curves: [(label, run_dir)]. One run: one panel per quantity (dx, dy, dz, ...), one curve
    per probes.csv column, the legend giving each column's header as written (name, probe
    point, unit). Several runs: one panel per column, titled by its header as written, one
    curve per run. The y axes name the quantity and its unit. columns: a filter as in
    ft.select_columns ('dx,dz', a column's name or header; None: every displacement column
    dx, dy, dz; "all": every column). Returns (whether a figure was written, the error messages of runs
    whose probes could not be read and of filter entries that select nothing); a run that
    lacks a column the others have is a note on stderr."""
    data, errors = [], []
    for label, run_dir in curves:
        try:
            data.append((label, run_dir) + read_columns(run_dir))
        except (OSError, ValueError) as e:
            errors.append("%s: %s" % (label, e))
    if not data:
        return False, errors
    available = []   # (name, header) over the runs, in file order
    for _, _, _, cols in data:
        available += [(n, h) for n, _, h, _ in cols if (n, h) not in available]
    chosen, unused = (available, []) if columns == "all" else ft.select_columns(available, columns)
    for e in unused:
        errors.append("--columns %s: no such column in %s (columns: %s)"
                      % (e, ", ".join(fr.rel(d) for _, d, _, _ in data), ", ".join(h for _, h in available)))
    if not chosen:
        errors.append("no %s column to plot in %s" % ("selected" if columns and columns != "all" else
                                                        "displacement" if not columns else "",
                                                        ", ".join(fr.rel(d) for _, d, _, _ in data)))
        return False, errors
    for label, run_dir, _, cols in data:
        have = {(n, h) for n, _, h, _ in cols}
        missing = [h for n, h in chosen if (n, h) not in have]
        if missing:
            print("probes_figure: note: %s: %s has no column %s" % (label, fr.rel(run_dir), ", ".join(missing)),
                  file=sys.stderr)
    if len(data) == 1:   # panels: the quantities; curves: the columns
        panels = [(None, [c for c in chosen if ft.column_kind(c[0]) == k])
                  for k in dict.fromkeys(ft.column_kind(n) for n, _ in chosen)]
    else:                # panels: the columns; curves: the runs
        panels = [(c[1], [c]) for c in chosen]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(8, 2.5 * len(panels) + 0.9), squeeze=False,
                             layout="constrained")
    for ax, (panel_title, panel_columns) in zip(axes[:, 0], panels):
        units = []
        for name, header in panel_columns:
            for label, _, t, cols in data:
                for n, u, h, v in cols:
                    if (n, h) == (name, header):
                        ax.plot(t, v, label=header if len(data) == 1 else label, lw=1.2)
                        units.append(u)
        if panel_title:
            ax.set_title(panel_title, fontsize="medium")
        ax.set_ylabel(axis_label(ft.column_kind(panel_columns[0][0]), units))
        ax.grid(True, alpha=0.3)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        ax.legend(fontsize="small", loc="best")
    axes[-1, 0].set_xlabel("t [s]")
    fig.suptitle(textwrap.fill(title, 80), fontsize="medium")
    fig.savefig(png, dpi=130)
    plt.close(fig)
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["label", "run_dir", "t"] + [h for _, h in chosen])
        for label, run_dir, t, cols in data:
            by = {(n, h): v for n, _, h, v in cols}
            for i in range(len(t)):
                w.writerow([label, fr.rel(run_dir), "%.10g" % t[i]] +
                           ["%.12e" % by[c][i] if c in by else "" for c in chosen])
    print("written: %s, %s" % (fr.rel(png), fr.rel(csv_path)))
    return True, errors


def cmd_probes(args, default_columns="all"):
    if args.labels and len(args.labels) != len(args.rundirs):
        sys.exit("probes_figure: %d run dirs but %d labels" % (len(args.rundirs), len(args.labels)))
    labels = args.labels or [os.path.basename(os.path.normpath(d)) for d in args.rundirs]
    name = args.name
    if not name:
        stem = "-".join(os.path.basename(os.path.normpath(d)) for d in args.rundirs)
        name = (stem if len(stem) <= 80 else "%d-runs" % len(args.rundirs)) + "-probes"
    base = os.path.join(args.out, name)
    # a case of the general scene by its run directory's name (summary.json knows no options file)
    scenes = list(dict.fromkeys(ft.run_scene(d) if ft.run_scene(d) != "general" else
                                "general (%s)" % os.path.basename(os.path.normpath(d)) for d in args.rundirs))
    columns = args.columns or default_columns
    title = args.title or ("%s: probes.csv columns %s" % (", ".join(scenes), columns) if columns and columns != "all"
                           else "%s: %s" % (", ".join(scenes), "probes.csv" if columns else "displacement at the probes"))
    plotted, errors = plot_probes(list(zip(labels, args.rundirs)), title, base + ".png", base + ".csv",
                                  columns=columns)
    if not plotted:
        for e in errors:
            print("probes_figure: %s" % e, file=sys.stderr)
        return False
    variants = []
    for label, d in zip(labels, args.rundirs):
        v = fr.Variant(os.path.basename(os.path.normpath(d)), label, [])
        v.run_dir, v.summary = d, fr.read_summary(d)
        v.status = "reused" if v.summary else "no summary.json"
        variants.append(v)
    fr.write_runs_csv(base + "-runs.csv", variants)
    print("written: %s" % fr.rel(base + "-runs.csv"))
    for e in errors:
        print("probes_figure: %s" % e, file=sys.stderr)
    return not errors


def add_arguments(p):
    p.add_argument("rundirs", nargs="+", metavar="RUNDIR", help="fsiopt output directories with probes.csv")
    p.add_argument("--columns", "--probes", dest="columns", metavar="LIST",
                   help="the probes.csv columns to plot, comma separated: a quantity (dx, dy, dz, drag, lift, Q, "
                   "p_outlet, ...), a column's name or its header; default every column")
    p.add_argument("--labels", nargs="+", help="legend labels, one per RUNDIR (default the dir names)")
    p.add_argument("--title", help="the figure's title")
    p.add_argument("--name", help="output name (default <dirname>-probes)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(ap)
    ap.add_argument("--out", default=os.path.join(fr.ROOT, "out", "figures"), help="output directory (default out/figures)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    sys.exit(0 if cmd_probes(args) else 1)


if __name__ == "__main__":
    main()
