#!/usr/bin/env python3
"""The time series of Turek-Hron runs (probes.csv of options/turek-hron/CASE.yaml): windows, quantities, plots.

A run is a directory with probes.csv (a finished or stopped run) or probes.csv.partial (a run
still going, e.g. a long run of scripts/turek_hron_table.py); its columns are t, the
displacement of A = (0.6, 0.2) dx(0.6;0.2), dy(0.6;0.2) in m, and drag, lift in N/m (the
csm cases have no drag and lift, the cfd cases no displacement). A restarted run's
probes.csv covers the whole run.

  windows RUN [--width W] [--from T0] [--to T1]
        per window [a, a + W] of W seconds (default 0.25; both ends included, so neighbours share
        a step) from T0 (default: the first whole multiple of W)
        the least and the largest value of every quantity, and the change of its amplitude
        (max - min)/2 from the window before: how a periodic state is approached. Markdown.
  quantities RUN... [--from T0] [--to T1]
        over [T0, T1] (default: the whole series, or up to its end) the quantities as
        summary.json reports them (src/report/quantities.c): the mean (max + min)/2, the
        amplitude (max - min)/2, and the frequency of the upward crossings of the mean ("-"
        for a steady signal or fewer than two crossings). With one window for every run,
        runs on different levels compare on the same stretch of time. Markdown.
  plot RUN[=LABEL]... --out PNG [--from T0] [--to T1]
        uy(A), ux(A), drag and lift against time, one panel each, one curve per run.

--csv F writes the windows or quantities table as CSV as well. Examples:
  scripts/turek_hron_series.py windows out/turek-hron-periodic/runs/fsi3-n2 --from 5 --width 0.25
  scripts/turek_hron_series.py quantities out/turek-hron-long/fsi2-n1-biharmonic \\
      out/turek-hron-periodic/runs/fsi2-n2 --from 13 --to 15
  scripts/turek_hron_series.py plot out/turek-hron-long/fsi2-n1-biharmonic=n1 \\
      out/turek-hron-periodic/runs/fsi2-n2=n2 --from 13 --out out/figures/fsi2.png"""
import argparse, csv, math, os, sys

sys.dont_write_bytecode = True
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402
import fsiopt_tables as ft  # noqa: E402  (the units in probes.csv's header)

# probes.csv column -> how the tables and plots name it
LABELS = {"dx(0.6;0.2)": "ux(A)", "dy(0.6;0.2)": "uy(A)", "drag": "drag", "lift": "lift"}
ORDER = ["dy(0.6;0.2)", "dx(0.6;0.2)", "drag", "lift"]
TOL = 1e-9   # window bounds on a grid of steps
UNITS = {"dx(0.6;0.2)": "m", "dy(0.6;0.2)": "m", "drag": "N/m", "lift": "N/m"}   # headers without units


def header_units(path):
    """{column name: unit} of the columns of a probes file whose header gives one."""
    with open(path, newline="") as f:
        header = next(csv.reader(f), [])
    return {n: u for n, u in map(ft.split_header, header) if u}


class InputError(Exception):
    pass


def read_run(spec):
    """(label, path, t, {column: values}) of RUN[=LABEL]."""
    path, _, label = spec.partition("=")
    files = [os.path.join(path, "probes.csv"), os.path.join(path, "probes.csv.partial"), path]
    found = next((f for f in files if os.path.isfile(f)), None)
    if found is None:
        raise InputError("%s: expected a run directory with probes.csv or probes.csv.partial, or a probes file" % path)
    try:
        names, cols = fr.read_table(found, growing=found.endswith(".partial"))
    except (ValueError, IndexError) as e:
        raise InputError("%s: expected a header line and rows of numbers (%s)" % (found, e))
    if names[:1] != ["t"]:
        raise InputError("%s: expected a header line starting with t" % found)
    values = {n: np.array(c) for n, c in zip(names, cols) if n in LABELS}
    if not values:
        raise InputError("%s: none of the columns %s" % (found, ", ".join(LABELS)))
    if len(cols[0]) < 2:
        raise InputError("%s: fewer than two time steps" % found)
    return label or os.path.basename(os.path.normpath(path)), found, np.array(cols[0]), values


def analyze(t, v):
    """mean, amplitude, frequency (None: steady or too few crossings), as src/report/quantities.c."""
    lo, hi = float(v.min()), float(v.max())
    mean, amplitude = 0.5 * (hi + lo), 0.5 * (hi - lo)
    if amplitude <= 1e-5 * max(abs(hi), abs(lo)):
        return mean, amplitude, None
    a, b = v[:-1] - mean, v[1:] - mean
    up = np.nonzero((a < 0) & (b >= 0))[0]
    if len(up) < 2:
        return mean, amplitude, None
    tc = t[up] + (t[up + 1] - t[up]) * (-a[up]) / (b[up] - a[up])
    return mean, amplitude, (len(up) - 1) / (tc[-1] - tc[0])


def select(t, t0, t1):
    lo = -math.inf if t0 is None else t0 - TOL
    hi = math.inf if t1 is None else t1 + TOL
    return (t >= lo) & (t <= hi)


def write_csv(path, header, rows):
    if path:
        with open(path + ".partial", "w", newline="") as fh:
            csv.writer(fh).writerows([header] + rows)
        os.replace(path + ".partial", path)


def windows(args):
    label, found, t, values = read_run(args.run)
    if args.width <= 0:
        raise InputError("--width %g: expected a positive number of seconds" % args.width)
    columns = [c for c in ORDER if c in values]
    start = args.t0 if args.t0 is not None else math.ceil(t[0] / args.width - TOL) * args.width
    end = min(t[-1], args.t1) if args.t1 is not None else t[-1]
    lines = ["%s (%s, t = %g … %g)\n" % (label, found, t[0], t[-1]),
             "| window | " + " | ".join("%s min … max | Δ amplitude" % LABELS[c] for c in columns) + " |",
             "|---|" + "---|---|" * len(columns)]
    rows, before = [], {}
    for k in range(int(math.floor((end - start) / args.width + TOL))):
        a = start + k * args.width
        m = (t >= a - TOL) & (t <= a + args.width + TOL)
        if m.sum() >= 2:
            cells, row = [], ["%.6g" % a, "%.6g" % (a + args.width)]
            for c in columns:
                lo, hi = float(values[c][m].min()), float(values[c][m].max())
                amplitude = 0.5 * (hi - lo)
                change = (amplitude - before[c]) / before[c] if before.get(c) else None
                before[c] = amplitude
                cells.append("%.5g … %.5g | %s" % (lo, hi, "—" if change is None else "%+.2f %%" % (100 * change)))
                row += [repr(lo), repr(hi), "" if change is None else repr(change)]
            lines.append("| [%g, %g] | %s |" % (a, a + args.width, " | ".join(cells)))
            rows.append(row)
    if not rows:
        raise InputError("no whole window of %g s between t = %g and %g" % (args.width, start, end))
    print("\n".join(lines))
    write_csv(args.csv, ["t0", "t1"] + [k % c for c in columns for k in ("%s_min", "%s_max", "%s_amplitude_change")], rows)


def quantities(args):
    runs = [read_run(r) for r in args.runs]
    columns = [c for c in ORDER if any(c in r[3] for r in runs)]
    lines = ["| run | window | " + " | ".join(LABELS[c] for c in columns) + " |", "|---|---|" + "---|" * len(columns)]
    rows = []
    for label, found, t, values in runs:
        m = select(t, args.t0, args.t1)
        if m.sum() < 2:
            raise InputError("%s: fewer than two time steps in [%s, %s] (the run has t = %g … %g)" % (
                found, "start" if args.t0 is None else "%g" % args.t0, "end" if args.t1 is None else "%g" % args.t1, t[0], t[-1]))
        cells, row = [], [label, repr(t[m][0]), repr(t[m][-1])]
        for c in columns:
            if c not in values:
                cells.append("")
                row += ["", "", ""]
                continue
            mean, amplitude, frequency = analyze(t[m], values[c][m])
            cells.append("%.5g ± %.5g [%s Hz]" % (mean, amplitude, "—" if frequency is None else "%.4g" % frequency))
            row += [repr(mean), repr(amplitude), "" if frequency is None else repr(frequency)]
        lines.append("| %s | [%g, %g] | %s |" % (label, t[m][0], t[m][-1], " | ".join(cells)))
        rows.append(row)
    print("\n".join(lines))
    write_csv(args.csv, ["run", "t0", "t1"] + [k % c for c in columns for k in ("%s_mean", "%s_amplitude", "%s_frequency")], rows)


def plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = [read_run(r) for r in args.runs]
    columns = [c for c in ORDER if any(c in r[3] for r in runs)]
    units = dict(UNITS)   # the scene's (SI); a header's own unit wins
    for _, found, _, _ in runs:
        units.update(header_units(found))
    fig, axes = plt.subplots(len(columns), 1, figsize=(9, 2.4 * len(columns)), sharex=True, squeeze=False)
    for ax, c in zip(axes[:, 0], columns):
        for label, found, t, values in runs:
            if c in values:
                m = select(t, args.t0, args.t1)
                ax.plot(t[m], values[c][m], lw=0.9, label=label)
        ax.set_ylabel("%s [%s]" % (LABELS[c], units[c]))
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="upper right", fontsize="small")
    axes[-1, 0].set_xlabel("t [s]")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    partial = args.out + ".partial"
    fig.savefig(partial, format="png", dpi=120)
    os.replace(partial, args.out)
    print("wrote %s" % args.out)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    for name, many in (("windows", False), ("quantities", True), ("plot", True)):
        s = sub.add_parser(name)
        if many:
            s.add_argument("runs", nargs="+", metavar="RUN")
        else:
            s.add_argument("run", metavar="RUN")
        s.add_argument("--from", dest="t0", type=float)
        s.add_argument("--to", dest="t1", type=float)
        if name == "windows":
            s.add_argument("--width", type=float, default=0.25)
        if name == "plot":
            s.add_argument("--out", required=True)
        else:
            s.add_argument("--csv")
    args = p.parse_args()
    try:
        {"windows": windows, "quantities": quantities, "plot": plot}[args.command](args)
    except InputError as e:
        sys.exit("turek_hron_series: %s" % e)
    except BrokenPipeError:
        # the reader (e.g. `| head`) stopped early: not an error of ours; keep Python from
        # complaining again when it flushes stdout at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


if __name__ == "__main__":
    main()
