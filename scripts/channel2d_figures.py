#!/usr/bin/env python3
"""Figures and tables of the seed dissertation for the haemodynamic channel (scene channel2d).

The channel: fluid [0,6]x[0,1], elastic wall [0,6]x[1,1.1] on top, inlet pressure pulse,
dt = 1e-4 to T = 0.1 (options/channel2d.yaml). Reproduces, from bin/fsiopt runs:

  probes RUNDIR...  scripts/probes_figure.py's figure with the displacement columns by
                    default (dx, dy, dz; --columns selects). For channel2d: dx and dy of
                    (1.5,1), (3,1), (4.5,1), Figs 3.2-3.5
  (the studies below plot dy, the vertical displacement of the interface points)
  mesh              hy = 0.1, 0.05, 1/30: fluid 30x10, 30x20, 30x30 cells with a wall of
                    1, 2, 3 cells across (Fig 3.2)
  order             first-order against second-order (midpoint) wall (Fig 3.5)
  tikhonov          Tikhonov weights eps = 1e-5, 1e-6, 5e-7 and 1e-12 ("small") (Fig 4.3);
                    a large weight makes the optimizer stop by its stall test (summary
                    converged: false): recorded, not a failure
  svk               St. Venant-Kirchhoff against linear wall, each coupled by Gauss-Newton
                    (opt) and by Dirichlet-Neumann with Aitken's relaxation (Fig 6.2); all four
                    with the midpoint wall (options/channel2d-svk.opts, and channel2d.yaml
                    with -structure_time_order 2); the Aitken runs take about half an hour each
  table [RUNDIR]    interface jump at each Gauss-Newton iteration of the steps at three times
                    (Table 3.1; default t = T/4, T/2, 3T/4 = 0.025, 0.05, 0.075 for the full
                    run) and the distribution of Gauss-Newton iterations per step
  pressure [RUNDIR] the fluid pressure on the deformed fluid mesh and the deformed wall at
                    three times (Fig 3.4; default T/4, T/2, 3T/4 = 0.025, 0.05, 0.075, --times),
                    one panel per time, one colour scale shared by the panels (--color-scale
                    panel: one each), displacement times --scale (default 1: true geometry).
                    Reads RUNDIR/fields.h5 (fsiopt -write_fields), the written step nearest to
                    each time (the panel title gives its time); without RUNDIR runs the default
                    variant with -write_fields -write_fields_interval K, K = gcd of the steps of
                    the times (250 for the defaults), a run of its own (<variant>-fK). The CSV
                    has per snapshot the pressure range, the wall's largest displacement, its
                    largest dy and where, and the gap between the fluid mesh and the wall
  all               mesh, order, tikhonov and the table of the shared default run (hy = 0.1,
                    first-order wall, eps = 0), and the pressure figure (its run with fields
                    goes with the others)

Every subcommand writes PNG + CSV (+ Markdown for tables) into out/figures/ (--out). Runs go
to out/figures/runs/<variant>/ (--runs-dir) and are re-used when complete and run with the
same command line (recorded in cmd.txt) unless --force; the runs' wall times and summary
numbers go into <figure>-runs.csv. A run that fails (non-zero exit) is reported with its
`fsiopt: error:` message, the others go on, and the script exits non-zero at the end.

Examples (build first: make all; the full T = 0.1 runs take several minutes each):
  scripts/channel2d_figures.py probes out/channel2d
  scripts/channel2d_figures.py probes out/tube3d --columns dx,dz
  scripts/channel2d_figures.py all --jobs 2
  scripts/channel2d_figures.py mesh --t-final 0.01 --out out/figures-short
  scripts/channel2d_figures.py pressure --t-final 0.01 --times 0.0025,0.005,0.0075 --out /tmp/pf"""
import argparse, csv, hashlib, math, os, shlex, sys, textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
import fsiopt_tables as ft   # noqa: E402  (probes.csv headers, scenes, units)
from channel2d_pressure import default_times, pressure_figure  # noqa: E402  (the pressure figure)
import probes_figure as pf   # noqa: E402  (probes.csv against time, any scene)
from probes_figure import plot_probes, read_probes   # noqa: E402,F401

ROOT = fr.ROOT
OPTIONS_FILE = {"linear": "options/channel2d.yaml", "svk": "options/channel2d-svk.opts"}
MODEL_LABEL = {"linear": "linear wall", "svk": "St. Venant-Kirchhoff wall"}
COUPLING_LABEL = {"opt": "Gauss-Newton (opt)", "aitken": "Dirichlet-Neumann + Aitken"}
HY_LABEL = {10: "hy = 0.1", 20: "hy = 0.05", 30: "hy = 1/30"}
ORDER_LABEL = {1: "first-order wall", 2: "second-order (midpoint) wall"}
DEFAULT_EPS = [1e-5, 1e-6, 5e-7, 1e-12]


# ---------------------------------------------------------------------------- variants
_variants = {}


def variant(args, ny=10, order=1, eps=0.0, fields=0, model="linear", coupling="opt"):
    """The channel run with fluid NX x ny cells, a wall of NX x ny/10 cells, the given wall
    time order, Tikhonov weight, wall model and coupling method; one object per distinct run
    (shared between studies). fields = K > 0: also -write_fields -write_fields_interval K
    (a run of its own, name ...-fK)."""
    nx, extra = args.nx, shlex.split(args.extra)
    name = "nx%d-ny%d-o%d-eps%g-T%g" % (nx, ny, order, eps, args.t_final)
    if fields:
        name += "-f%d" % fields
    for value, default in ((model, "linear"), (coupling, "opt")):
        if value != default:
            name += "-" + value
    if extra:
        name += "-x" + hashlib.sha1(" ".join(extra).encode()).hexdigest()[:8]
    if name not in _variants:
        options = ["-options_file", OPTIONS_FILE[model], "-t_final", "%g" % args.t_final,
                   "-fluid_dm_plex_box_faces", "%d,%d" % (nx, ny),
                   "-structure_dm_plex_box_faces", "%d,%d" % (nx, ny // 10),
                   "-structure_time_order", str(order), "-coupling_tikhonov", "%g" % eps]
        if coupling != "opt":
            options += ["-coupling", coupling]
        outputs = fr.OUTPUTS
        if fields:
            options += ["-write_fields", "-write_fields_interval", str(fields)]
            outputs += ("fields.h5", "fields.xdmf")
        label = "%s (hx = %g), %s, eps = %g" % (HY_LABEL.get(ny, "hy = 1/%d" % ny), 6.0 / nx, ORDER_LABEL[order], eps)
        if (model, coupling) != ("linear", "opt"):
            label += ", %s, %s" % (MODEL_LABEL[model], COUPLING_LABEL[coupling])
        if fields:
            label += ", fields every %d steps" % fields
        _variants[name] = fr.Variant(name, label, options + extra, outputs=outputs, nx=nx, ny=ny, order=order, eps=eps,
                                     fields=fields)
    return _variants[name]


def study(args, which):
    """(title, [(legend label, variant)]) of one study."""
    if which == "mesh":
        for ny in args.ny:
            if ny % 10:
                sys.exit("channel2d_figures: --ny %d: expected a multiple of 10 (the wall is 0.1 thick)" % ny)
        return ("mesh: fluid %d x NY, wall %d x NY/10 cells" % (args.nx, args.nx),
                [(HY_LABEL.get(ny, "hy = 1/%d" % ny), variant(args, ny=ny)) for ny in args.ny])
    if which == "order":
        return ("time order of the wall", [(ORDER_LABEL[o], variant(args, order=o)) for o in (1, 2)])
    if which == "tikhonov":
        return ("Tikhonov weight", [("eps = %g%s" % (e, " (small)" if 0 < e <= 1e-10 else ""), variant(args, eps=e))
                                    for e in args.eps])
    if which == "svk":
        return ("St. Venant-Kirchhoff against linear wall, Gauss-Newton against Aitken (midpoint wall)",
                [("%s, %s" % (MODEL_LABEL[m], COUPLING_LABEL[c]), variant(args, order=2, model=m, coupling=c))
                 for m in ("linear", "svk") for c in ("opt", "aitken")])
    raise ValueError(which)


def peak_dy(run_dir):
    """{dy column header: (max dy, t at the max)}; {} when unreadable."""
    try:
        t, dy = read_probes(run_dir)
    except (OSError, ValueError):
        return {}
    return {p: (float(v.max()), float(t[int(v.argmax())])) for p, v in dy.items()}


def write_study_markdown(path, title, labelled):
    points = []
    for _, v in labelled:
        points += [p for p in peak_dy(v.run_dir) if p not in points] if v.ok else []
    md = ["# channel2d: " + title, "",
          "| run | status | steps | GN its/step | inner its | work factor | max jump | stalled steps | wall s | "
          + " | ".join("max %s (t)" % fr.md_escape(p) for p in points) + " |",
          "|" + "---|" * (9 + len(points))]
    for label, v in labelled:
        s, peaks = v.summary or {}, peak_dy(v.run_dir) if v.ok else {}
        status = v.status if v.ok else "FAILED: " + v.error.replace("|", "\\|")
        if v.ok and not s.get("converged", True):
            status += " (not converged)"
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            label, status, s.get("steps", ""), "%.3f" % s["avg_coupling_iterations"] if "avg_coupling_iterations" in s else "",
            s.get("inner_iterations", ""),
            s.get("work_factor", ""), "%.3e" % s["max_interface_jump"] if "max_interface_jump" in s else "",
            s.get("stalled_steps", ""), "%.1f" % s["wall_time_s"] if "wall_time_s" in s else "",
            " | ".join("%.4e (%.4g)" % peaks[p] if p in peaks else "" for p in points)))
    with open(path, "w") as f:
        f.write("\n".join(md) + "\n")


def figure_for_study(args, which):
    """Runs the study's variants (already run by 'all') and writes its figure; returns ok."""
    title, labelled = study(args, which)
    todo = [v for _, v in labelled if v.status == "pending"]
    if todo:
        fr.run_all(todo, args.bin, args.runs_dir, args.jobs, args.force, args.retries)
    base = os.path.join(args.out, "channel2d-" + which)
    fr.write_runs_csv(base + "-runs.csv", [v for _, v in labelled])
    write_study_markdown(base + ".md", "%s, T = %g" % (title, args.t_final), labelled)
    ok_curves = [(label, v.run_dir) for label, v in labelled if v.ok]
    errors = plot_probes(ok_curves, "channel2d, %s: vertical displacement of the interface (T = %g)"
                         % (title, args.t_final), base + ".png", base + "-probes.csv", columns="dy")[1] if ok_curves else []
    print("written: %s, %s" % (fr.rel(base + "-runs.csv"), fr.rel(base + ".md")))
    failed = [(label, v) for label, v in labelled if not v.ok]
    for label, v in failed:
        print("channel2d_figures: %s: variant %s (%s) failed: %s" % (which, v.name, label, v.error), file=sys.stderr)
    for e in errors:
        print("channel2d_figures: %s: %s" % (which, e), file=sys.stderr)
    if not ok_curves:
        print("channel2d_figures: %s: no successful run, no figure" % which, file=sys.stderr)
    return not failed and not errors


# ---------------------------------------------------------------------------- table
def read_history(run_dir):
    """{step: [(iteration, objective, jump, inner_iterations)]} from run_dir/history.csv."""
    path = os.path.join(run_dir, "history.csv")
    if not os.path.isfile(path):
        raise FileNotFoundError("%s: no such file" % fr.rel(path))
    steps = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("event"):  # a failed attempt's marker (the step was retried)
                continue
            steps.setdefault(int(r["step"]), []).append(
                (int(r["iteration"]), float(r["objective"]), float(r["jump"]), int(r["inner_iterations"])))
    if not steps:
        raise ValueError("%s: no rows" % fr.rel(path))
    for rows in steps.values():
        rows.sort()
    return steps


def time_grid(run_dir):
    """(t_start, dt, t_final) from summary.json, else from probes.csv."""
    s = fr.read_summary(run_dir)
    if all(k in s for k in ("t_start", "dt", "t_final")):
        return float(s["t_start"]), float(s["dt"]), float(s["t_final"])
    t, _ = read_columns(run_dir)
    return float(t[0]), float(t[1] - t[0]), float(t[-1])


def write_table(run_dir, times, name, out):
    """Table 3.1 (jump per GN iteration at the given times) and the iteration distribution.
    Returns the list of problems (times outside the run)."""
    steps = read_history(run_dir)
    t_start, dt, t_final = time_grid(run_dir)
    if not times:
        times = [t_start + f * (t_final - t_start) for f in (0.25, 0.5, 0.75)]
    problems, cols = [], []   # cols: (t, step, rows)
    for t in times:
        n = int(math.floor((t - t_start) / dt + 0.5))
        if n not in steps:
            problems.append("t = %g (step %d) is not in %s (steps %d..%d)" % (t, n, fr.rel(run_dir), min(steps), max(steps)))
            continue
        cols.append((t, n, steps[n]))
    base = os.path.join(out, name)
    # jump per iteration, rows = iteration, columns = time
    max_it = max((rows[-1][0] for _, _, rows in cols), default=-1)
    scene = ft.run_scene(run_dir)
    md = ["# %s: interface jump ||u - v_s||_{L2(Gamma_I)} per Gauss-Newton iteration" % scene, "",
          "run: `%s`; iteration 0 is the start of the step." % fr.rel(run_dir), ""]
    if cols:
        md += ["| iteration | " + " | ".join("t = %g (step %d)" % (t, n) for t, n, _ in cols) + " |",
               "|" + "---|" * (1 + len(cols))]
        for it in range(max_it + 1):
            cells = []
            for _, _, rows in cols:
                hit = [r for r in rows if r[0] == it]
                cells.append("%.3e" % hit[0][2] if hit else "")
            md.append("| %d | %s |" % (it, " | ".join(cells)))
        md.append("")
    for p in problems:
        md.append("(%s)" % p)
    with open(base + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "step", "iteration", "objective", "jump", "inner_iterations"])
        for t, n, rows in cols:
            for it, obj, jump, inner in rows:
                w.writerow(["%g" % t, n, it, "%.10e" % obj, "%.10e" % jump, inner])
    # Gauss-Newton iterations per step over the whole run
    its = np.array([rows[-1][0] for _, rows in sorted(steps.items())])
    counts = {k: int((its == k).sum()) for k in range(int(its.min()), int(its.max()) + 1)}
    s = fr.read_summary(run_dir)
    md += ["" if problems else None, "## Gauss-Newton iterations per step (%d steps)" % len(its), "",
           "| GN iterations | steps | share |", "|---|---|---|"]
    md += ["| %d | %d | %.1f%% |" % (k, c, 100.0 * c / len(its)) for k, c in counts.items() if c]
    md += ["", "average: %.3f Gauss-Newton iterations per step%s" % (
        its.mean(), " (summary.json: %s)" % s["avg_coupling_iterations"] if "avg_coupling_iterations" in s else "")]
    if s.get("stalled_steps"):
        md.append("stalled steps: %d (converged: false)" % s["stalled_steps"])
    md = [l for l in md if l is not None]
    with open(base + ".md", "w") as f:
        f.write("\n".join(md) + "\n")
    with open(base + "-iterations.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["gn_iterations", "steps"])
        w.writerows(counts.items())
    # figure: jump against iteration at the chosen times, distribution of iterations
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    for t, n, rows in cols:
        a.semilogy([r[0] for r in rows], [max(r[2], 1e-300) for r in rows], "o-", label="t = %g" % t)
    a.set_xlabel("Gauss-Newton iteration")
    a.set_ylabel("interface jump")
    a.grid(True, which="both", alpha=0.3)
    if cols:
        a.legend(fontsize="small")
        a.xaxis.get_major_locator().set_params(integer=True)
    b.bar(list(counts), list(counts.values()), color="tab:gray")
    b.set_xlabel("Gauss-Newton iterations per step")
    b.set_ylabel("steps")
    b.set_title("average %.3f" % its.mean())
    b.xaxis.get_major_locator().set_params(integer=True)
    fig.suptitle("%s: %s" % (scene, fr.rel(run_dir)))
    fig.tight_layout()
    fig.savefig(base + ".png", dpi=130)
    plt.close(fig)
    print("\n".join(md))
    print("written: %s" % ", ".join(fr.rel(base + e) for e in (".md", ".csv", "-iterations.csv", ".png")))
    return problems


# ---------------------------------------------------------------------------- pressure
def run_time_grid(args):
    """(t_start, dt) of our runs: -t_start / -dt in --extra, else the options file's."""
    return fr.run_time_grid(OPTIONS_FILE["linear"], shlex.split(args.extra))


def fields_interval(args, times):
    return fr.fields_interval(*run_time_grid(args), args.t_final, times, "channel2d_figures: pressure")


def pressure_variant(args):
    times = args.times or default_times(run_time_grid(args)[0], args.t_final)
    return variant(args, fields=fields_interval(args, times)), times


# ---------------------------------------------------------------------------- commands
def cmd_probes(args):
    """the generic figure (probes_figure.py), with this script's displacement default"""
    return pf.cmd_probes(args, default_columns=None)


def cmd_study(args):
    return figure_for_study(args, args.command)


def cmd_table(args):
    if args.rundir:
        run_dir, name = args.rundir, args.name or os.path.basename(os.path.normpath(args.rundir)) + "-table"
    else:   # the default run (hy = 0.1, first-order wall, eps = 0) at --t-final
        v = variant(args)
        fr.run_all([v], args.bin, args.runs_dir, 1, args.force, args.retries)
        fr.write_runs_csv(os.path.join(args.out, (args.name or "channel2d-table") + "-runs.csv"), [v])
        if not v.ok:
            print("channel2d_figures: table: variant %s failed: %s" % (v.name, v.error), file=sys.stderr)
            return False
        run_dir, name = v.run_dir, args.name or "channel2d-table"
    try:
        problems = write_table(run_dir, args.times, name, args.out)
    except (OSError, ValueError) as e:
        print("channel2d_figures: table: %s" % e, file=sys.stderr)
        return False
    for p in problems:
        print("channel2d_figures: table: %s" % p, file=sys.stderr)
    return not problems


def cmd_pressure(args):
    if args.rundir:
        return pressure_figure(args, args.rundir, args.name or os.path.basename(os.path.normpath(args.rundir)) + "-pressure",
                               args.times)
    # the default run (hy = 0.1, first-order wall, eps = 0) with -write_fields at --t-final
    v, times = pressure_variant(args)
    name = args.name or "channel2d-pressure"
    fr.run_all([v], args.bin, args.runs_dir, 1, args.force, args.retries)
    fr.write_runs_csv(os.path.join(args.out, name + "-runs.csv"), [v])
    if not v.ok:
        print("channel2d_figures: pressure: variant %s failed: %s" % (v.name, v.error), file=sys.stderr)
        return False
    return pressure_figure(args, v.run_dir, name, times)


def cmd_all(args):
    studies = ["mesh", "order", "tikhonov"]
    pv, ptimes = pressure_variant(args)
    everything = [variant(args)] + [v for s in studies for _, v in study(args, s)[1]] + [pv]
    unique = fr.run_all(everything, args.bin, args.runs_dir, args.jobs, args.force, args.retries)
    fr.write_runs_csv(os.path.join(args.out, "channel2d-all-runs.csv"), unique)
    print("written: %s" % fr.rel(os.path.join(args.out, "channel2d-all-runs.csv")))
    ok = all([figure_for_study(args, s) for s in studies])
    base = variant(args)
    if base.ok:
        args.rundir, args.name = base.run_dir, "channel2d-table"
        ok = cmd_table(args) and ok
    else:
        print("channel2d_figures: all: the default run failed, no table", file=sys.stderr)
        ok = False
    if pv.ok:
        ok = pressure_figure(args, pv.run_dir, "channel2d-pressure", ptimes) and ok
    else:
        print("channel2d_figures: all: the run with fields (%s) failed, no pressure figure: %s" % (pv.name, pv.error),
              file=sys.stderr)
        ok = False
    return ok


def floats(text):
    return [float(x) for x in text.replace(",", " ").split()]


def ints(text):
    return [int(x) for x in text.replace(",", " ").split()]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    out = argparse.ArgumentParser(add_help=False)
    out.add_argument("--out", default=os.path.join(ROOT, "out", "figures"), help="output directory (default out/figures)")
    runs = argparse.ArgumentParser(add_help=False)
    runs.add_argument("--t-final", type=float, default=0.1, help="end time of every run (default 0.1 = 1000 steps)")
    runs.add_argument("--bin", default=fr.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    runs.add_argument("--jobs", type=int, default=1, help="runs in parallel (default 1)")
    runs.add_argument("--extra", default="", help='options passed to every run, e.g. --extra="-refine 1"')
    runs.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    runs.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    runs.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error (default 2)")
    runs.add_argument("--nx", type=int, default=30, help="cells along the channel, fluid and wall (default 30; even, so that the probes x = 1.5, 3, 4.5 are Q2 nodes)")
    runs.add_argument("--ny", type=ints, default=[10, 20, 30], help="mesh study: fluid cells across (default 10,20,30)")
    runs.add_argument("--eps", type=floats, default=DEFAULT_EPS, help="tikhonov study: weights (default 1e-5,1e-6,5e-7,1e-12)")
    pres = argparse.ArgumentParser(add_help=False)
    pres.add_argument("--scale", type=float, default=1.0, help="pressure: displacement drawn times SCALE (default 1: the true geometry)")
    pres.add_argument("--color-scale", choices=("shared", "panel"), default="shared",
                      help="pressure: one colour scale for all panels (default) or one per panel")
    pres.add_argument("--cmap", default="turbo", help="pressure: matplotlib colour map (default turbo)")
    pres.add_argument("--no-mesh", dest="mesh", action="store_false", help="pressure: do not draw the fluid cells' edges")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("probes", parents=[out], help="any scene's displacement probes (dx, dy, dz; --columns "
                       "selects) against time, labelled by their probes.csv headers, one curve per column or run")
    p.add_argument("rundirs", nargs="+", metavar="RUNDIR", help="fsiopt output directories with probes.csv")
    p.add_argument("--columns", "--probes", dest="columns", metavar="LIST",
                   help="the probes.csv columns to plot, comma separated: a quantity (dx, dy, dz, drag, lift), a "
                   "column's name (dy(1.5;1.)) or its whole header (default: every displacement column dx, dy, dz), "
                   "e.g. --columns dx,dz")
    p.add_argument("--labels", nargs="+", help="legend labels, one per RUNDIR (default the dir names)")
    p.add_argument("--name", help="output name (default <dirname>-probes)")
    p.add_argument("--title", help="figure title (default: the scene of summary.json, else the dir name, and what is "
                   "plotted)")
    p.set_defaults(func=cmd_probes)
    for name, text in (("mesh", "hy = 0.1, 0.05, 1/30 (Fig 3.2)"), ("order", "first- against second-order wall (Fig 3.5)"),
                       ("tikhonov", "Tikhonov weights (Fig 4.3)"),
                       ("svk", "St. Venant-Kirchhoff against linear wall, opt against Aitken (Fig 6.2)")):
        sub.add_parser(name, parents=[out, runs], help=text).set_defaults(func=cmd_study)
    p = sub.add_parser("table", parents=[out, runs], help="jump per Gauss-Newton iteration at three times (Table 3.1)")
    p.add_argument("rundir", nargs="?", metavar="RUNDIR", help="a finished run (default: run the default variant)")
    p.add_argument("--times", type=floats, help="times of the columns (default T/4, T/2, 3T/4)")
    p.add_argument("--name", help="output name (default <dirname>-table or channel2d-table)")
    p.set_defaults(func=cmd_table)
    p = sub.add_parser("pressure", parents=[out, runs, pres], help="pressure field and wall at three times (Fig 3.4)")
    p.add_argument("rundir", nargs="?", metavar="RUNDIR", help="a finished run with fields.h5 (default: run the default "
                   "variant with -write_fields)")
    p.add_argument("--times", type=floats, help="times of the panels (default T/4, T/2, 3T/4 = 0.025,0.05,0.075 for "
                   "T = 0.1; of a RUNDIR: of its written time range); the nearest written step is drawn")
    p.add_argument("--name", help="output name (default <dirname>-pressure or channel2d-pressure)")
    p.set_defaults(func=cmd_pressure)
    p = sub.add_parser("all", parents=[out, runs, pres], help="mesh, order, tikhonov, the table and the pressure figure")
    p.add_argument("--times", type=floats, help="table and pressure: times (default T/4, T/2, 3T/4)")
    p.set_defaults(func=cmd_all)
    args = ap.parse_args()
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    if hasattr(args, "runs_dir"):
        args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
        args.bin = os.path.abspath(args.bin)
    ok = args.func(args)
    if not ok:
        print("channel2d_figures: %s: there were failures (see above)" % args.command, file=sys.stderr)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
