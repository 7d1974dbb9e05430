#!/usr/bin/env python3
"""Stability stress test of the coupling methods: density ratio x time step on channel2d.

For every method (default opt, dn:-coupling_omega 0.05, aitken, iqnils; NAME[:options] as
in scripts/bench.py), every density ratio rho_s/rho_f (default 10,1.1,0.5,0.1,0.01; the
channel's fluid density is 1, so -structure_density = the ratio) and every time step
(default 1e-3,1e-4,1e-5,1e-6) runs channel2d for --steps steps (default 10: -dt DT
-t_final STEPS*DT) and records whether it converged (exit status; the `fsiopt: error:`
message and its abbreviation, e.g. "diverged s1 it2", "max_it s3"; a run killed after
--timeout seconds counts as "timeout"), the coupling iterations per step (opt: Gauss-Newton
iterations, the partitioned methods: Dirichlet-Neumann sweeps), the wall time, fluid solves
and work factor. The added-mass effect grows as rho_s/rho_f falls, so the partitioned
methods are expected to need more sweeps or to fail at the small ratios, and smaller time
steps make it worse for them (the wall's stiffness, which helps, weighs dt^2 against its
inertia; Causin, Gerbeau & Nobile 2005).

With dt = 1e-3 the inlet pulse (0.025 s) is resolved by a few steps only, and 10 steps of
dt = 1e-6 are a very short horizon: both are fine for a stability test.

Outputs under out/stress/ (--out): stress.csv, stress.md, and per method
stress-<method>.png (rows rho_s/rho_f, columns dt, colour = coupling iterations per step on
a log scale shared by all methods, failed cells greyed with an X and the reason) and
stress-all.png (all methods side by side). Runs go to <out>/runs/ (--runs-dir) with
-log_view; complete runs with the same command line are re-used, and so are failures with
an `fsiopt: error:` message and timeouts (after at least the current --timeout), unless
--rerun-failed or --force. The script exits 0 when every run has an outcome (a failing run
is a result here, not an error).

From rest the wall barely moves over a few steps of a small dt, so a cell there tests little
(opt's absolute tolerance is met at iteration 0). --developed T0:DT starts every cell from a
developed state instead: for each ratio one run of --developed-method (default opt) to T0 with
that DT writes a checkpoint, and each cell restarts from it at its own dt
(-restart_change_dt) to T0 + steps x dt. --restart FILE:T0 starts every cell from one given
checkpoint at time T0 (e.g. a periodic Turek-Hron state; its density is then changed to each
ratio's). Every cell runs with -dt_min equal to its dt: a step that fails is not retried
with dt/2, it fails the cell. --relative R holds every method to the same relative accuracy: opt stops when the
jump is below R ||v_s|| (-coupling_tol_relative R, the absolute tolerance out of the way), the
partitioned methods when the traction changes by less than R relative (-coupling_rtol R,
-coupling_atol 0). A cell counts only when the wall moved during it: some probe (--probes,
default dy) changed by at least --moved (default 1e-6) of its largest value over the series;
the others are marked "wall at rest" and left out of the counts.

Examples (build first: make all):
  scripts/stress.py --jobs 2
  scripts/stress.py --steps 3 --ratios 1.1,0.1 --dts 1e-4,1e-5 --methods opt,iqnils --out /tmp/s1
  scripts/stress.py --steps 3 --developed 0.012:1e-4 --relative 1e-5
  scripts/stress.py --options-file options/turek-hron/fsi3.yaml --fluid-density 1000 \
      --restart out/fsi3-swing/checkpoint.h5:5 --ratios 1,0.5,0.1,0.01 --relative 1e-5 --out out/stress-fsi3"""
import argparse, math, os, re, shlex, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.colors import LogNorm
from matplotlib.ticker import FuncFormatter
import numpy as np

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench as B   # noqa: E402
import bench_runs   # noqa: E402  (bench.py's runs)
import fsiopt_runs as fr   # noqa: E402

ROOT = B.ROOT
# opt with a tight absolute tolerance: channel2d's 1e-4 is met without any iteration while the
# wall barely moves (a few steps of a small dt), which would say nothing about stability
DEFAULT_METHODS = "opt:-coupling_tol 1e-8,dn:-coupling_omega 0.05,aitken,iqnils"
RATIOS = [10, 1.1, 0.5, 0.1, 0.01]
DTS = [1e-3, 1e-4, 1e-5, 1e-6]


def reason(r):
    """Short reason of a failed run (for the map cells)."""
    if r.status == "timeout":
        return "timeout"
    e = r.error
    m = re.search(r"diverged at step (\d+), iteration (\d+)", e)
    if m:
        return "diverged s%s it%s" % m.groups()
    m = re.search(r"did not converge at step (\d+)", e)
    if m:
        return "max_it s%s" % m.group(1)
    m = re.search(r"at step (\d+), iteration (\d+): (fluid mesh inverted)", e)
    if m:
        return "mesh inverted s%s it%s" % m.groups()[:2]
    m = re.search(r"at step (\d+), iteration (\d+): (fluid|structure) solve", e)
    if m:
        return "%s solve failed s%s it%s" % (m.group(3), m.group(1), m.group(2))
    m = re.match(r"killed by signal (\d+)", e)
    if m:
        return "signal %s" % m.group(1)
    words = re.sub(r"^coupling \w+ ", "", e).split()
    return " ".join(words[:3]) if words else r.status


def cell_probes(r):
    """(t, {column: values}) of a finished run's probes.csv, read once per run; None if it is
    not finished or unreadable."""
    if not hasattr(r, "_probes"):
        r._probes = None
        if r.ok:
            try:
                r._probes = B.read_probes(r.run_dir)
            except (OSError, ValueError):
                pass
    return r._probes


def max_dy(r):
    """max |dy| over the probes of a finished run (0: the wall never moved); nan if unreadable."""
    probes = cell_probes(r)
    if probes is None:
        return float("nan")
    return max(float(np.max(np.abs(c))) for c in probes[1].values())


def motion(r):
    """How far the wall moved during the cell's own steps (after its start time t0): the
    largest change of a probe over them relative to that probe's largest value over the
    series; nan if unreadable."""
    probes = cell_probes(r)
    if probes is None:
        return float("nan")
    t, dy = probes
    start = int(np.searchsorted(t, r.params.get("t0", 0.0) - 1e-12 * max(1.0, abs(t[-1]))))
    moved = 0.0
    for c in dy.values():
        scale = float(np.max(np.abs(c)))
        if scale > 0:
            moved = max(moved, float(np.max(np.abs(c[start:] - c[start]))) / scale)
    return moved


def counted(r, args):
    """a finished cell in which the wall moved (the others test nothing)."""
    return r.ok and motion(r) >= args.moved


def notes(r, args):
    """remarks on a finished run: not converged (stalled), wall at rest (not counted)."""
    out = []
    if r.summary.get("converged") is False:
        out.append("not converged")
    if r.ok and not counted(r, args):
        out.append("wall at rest")
    if r.ok and r.summary.get("retried_steps"):
        out.append("%d retried, dt down to %g" % (r.summary["retried_steps"], r.summary.get("smallest_dt", 0)))
    return out


def end_probes(r):
    """{column: (value at the end, largest |value| over the series)} of a finished run, {} if unreadable."""
    probes = cell_probes(r)
    if probes is None:
        return {}
    return {k: (float(c[-1]), float(np.max(np.abs(c)))) for k, c in probes[1].items()}


def difference(r, ref):
    """the largest difference of the end probes of r and ref, relative to each probe's largest value; nan if
    either is missing."""
    a, b = end_probes(r), end_probes(ref) if ref is not None else {}
    if not a or not b:
        return float("nan")
    return max(abs(a[k][0] - b[k][0]) / max(a[k][1], b[k][1], 1e-300) for k in a if k in b)


def relative_options(m, args):
    """the same relative accuracy for every method (--relative); the method's own options follow"""
    if not args.relative:
        return []
    if m.partitioned:
        return ["-coupling_rtol", B.fmt_num(args.relative), "-coupling_atol", "0"]
    return ["-coupling_tol", "1e30", "-coupling_tol_relative", B.fmt_num(args.relative)]


def parse_start(text, what):
    """'A:T0' -> (A, T0)"""
    head, sep, t0 = text.rpartition(":")
    try:
        return head, float(t0)
    except ValueError:
        raise SystemExit("stress.py: %s: expected %s, got %r" % (what, "T0:DT" if what == "--developed" else
                                                                   "FILE:T0", text)) from None


def developed_runs(args, extra):
    """{ratio: Run}: the state each ratio's cells start from (--developed)."""
    if not args.developed:
        return {}
    t0_text, dt = parse_start(args.developed, "--developed")
    t0 = float(t0_text)
    steps = int(round(t0 / dt))
    if steps < 1 or abs(steps * dt - t0) > 1e-9 * t0:
        raise SystemExit("stress.py: --developed %s: T0 must be a whole number of steps of DT" % args.developed)
    m = B.Method(args.developed_method)
    runs = {}
    for ratio in args.ratios:
        opts = ["-options_file", args.options_file, "-structure_density", "%g" % (ratio * args.fluid_density),
                "-dt", B.fmt_num(dt), "-t_final", B.fmt_num(t0), "-checkpoint_every", str(steps)]
        name = "developed-%s-rho%g-T%g-dt%g%s" % (m.slug, ratio, t0, dt, B.extra_tag(extra))
        runs[ratio] = bench_runs.Run(name, "developed state, rho_s/rho_f %g" % ratio, opts + m.coupling_options() + extra,
                            ratio=ratio, dt=dt)
    return runs


def cell_runs(args, methods, extra, developed):
    """{(method slug, ratio, dt): Run}"""
    grid = {}
    t0, restart = 0.0, None
    if args.restart:
        restart, t0 = parse_start(args.restart, "--restart")
        restart = os.path.abspath(restart)
    elif args.developed:
        t0 = float(args.developed.rpartition(":")[0])
    for m in methods:
        for ratio in args.ratios:
            for dt in args.dts:
                opts = ["-options_file", args.options_file,
                        "-structure_density", "%g" % (ratio * args.fluid_density),
                        "-dt", B.fmt_num(dt), "-t_final", B.fmt_num(t0 + args.steps * dt),
                        "-dt_min", B.fmt_num(dt)]   # no retries at dt/2: the cell is about this dt
                start = restart or (os.path.join(args.runs_dir, developed[ratio].name, "checkpoint.h5")
                                    if developed else None)
                if start:
                    # the same state for every method (developed by one), and at --restart every ratio's density
                    opts += ["-restart", B.rel(start), "-restart_change_dt", "-restart_change", "coupling,structure_density"]
                name = "%s-rho%g-dt%g-n%d%s%s" % (m.slug, ratio, dt, args.steps, "-t%g" % t0 if start else "",
                                                  B.extra_tag(extra + relative_options(m, args)))
                grid[m.slug, ratio, dt] = bench_runs.Run(name, "%s, rho_s/rho_f %g, dt %g" % (m.spec, ratio, dt),
                                                opts + relative_options(m, args) + m.coupling_options() + extra,
                                                ratio=ratio, dt=dt, t0=t0, developed=developed.get(ratio))
    return grid


def draw_map(ax, args, m, grid, norm, cmap, ylabel=True):
    ratios, dts = args.ratios, args.dts
    data = np.full((len(ratios), len(dts)), np.nan)
    for i, ratio in enumerate(ratios):
        for j, dt in enumerate(dts):
            r = grid[m.slug, ratio, dt]
            if r.ok:
                data[i, j] = max(r.summary.get("avg_coupling_iterations", np.nan), norm.vmin)
    cm = plt.get_cmap(cmap).copy()
    cm.set_bad("#d9d9d9")
    im = ax.imshow(np.ma.masked_invalid(data), cmap=cm, norm=norm, aspect="auto", origin="upper")
    for i, ratio in enumerate(ratios):
        for j, dt in enumerate(dts):
            r = grid[m.slug, ratio, dt]
            if r.ok:
                s = r.summary
                its = s.get("avg_coupling_iterations", float("nan"))
                rgba = cm(norm(max(its, norm.vmin))) if math.isfinite(its) else (1, 1, 1, 1)
                dark = 0.299 * rgba[0] + 0.587 * rgba[1] + 0.114 * rgba[2] < 0.5
                text = "\n".join(["%.3g its/step" % its, "%.2g s" % r.wall] + notes(r, args))
                ax.text(j, i, text, ha="center", va="center", fontsize=7, color="white" if dark else "black")
            else:
                ax.plot([j - 0.45, j + 0.45], [i - 0.45, i + 0.45], color="#b2182b", lw=1.5)
                ax.plot([j - 0.45, j + 0.45], [i + 0.45, i - 0.45], color="#b2182b", lw=1.5)
                ax.text(j, i, reason(r).replace(" ", "\n", 1), ha="center", va="center", fontsize=7,
                        bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="none", alpha=0.85))
    ax.set_xticks(range(len(dts)))
    ax.set_xticklabels(["%g" % d for d in dts])
    ax.set_yticks(range(len(ratios)))
    ax.set_yticklabels(["%g" % q for q in ratios])
    ax.set_xlabel("dt")
    if ylabel:
        ax.set_ylabel("rho_s / rho_f")
    ax.set_title(m.spec, fontsize=10)
    return im


def plain_ticks(cbar):
    """colour bar labels 2, 5, 10 instead of 2x10^0."""
    cbar.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: "%g" % v))
    cbar.ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: "%g" % v if ("%.0e" % v)[0] in "25" else ""))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--methods", default=DEFAULT_METHODS, help='comma-separated NAME[:options] (default "%s")'
                    % DEFAULT_METHODS)
    ap.add_argument("--ratios", type=B.floats, default=RATIOS, help="rho_s/rho_f = -structure_density (fluid "
                                                                    "density 1; default 10,1.1,0.5,0.1,0.01)")
    ap.add_argument("--dts", type=B.floats, default=DTS, help="time steps (default 1e-3,1e-4,1e-5,1e-6)")
    ap.add_argument("--steps", type=int, default=10, help="time steps per run (default 10)")
    ap.add_argument("--options-file", default=B.OPTIONS_FILE, help="scene options (default %s)" % B.OPTIONS_FILE)
    ap.add_argument("--extra", default="", help="options passed to every run")
    ap.add_argument("--timeout", type=float, default=300, help="seconds per run before it is killed and counted as "
                                                               "timeout (default 300; 0: no limit)")
    ap.add_argument("--jobs", type=int, default=2, help="runs in parallel (default 2; the wall times then compete "
                                                        "for the cores)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "stress"), help="output directory (default out/stress)")
    ap.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    ap.add_argument("--bin", default=B.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--rerun-failed", action="store_true", help="run again runs that failed or timed out before")
    ap.add_argument("--retries", type=int, default=1, help="retries of a run that dies without an fsiopt error "
                                                           "(default 1)")
    ap.add_argument("--cmap", default="viridis", help="matplotlib colour map (default viridis)")
    ap.add_argument("--fluid-density", type=float, default=1.0, help="rho_f: -structure_density = ratio x rho_f "
                                                                     "(default 1, channel2d; 1000 for turek-hron)")
    start = ap.add_mutually_exclusive_group()
    start.add_argument("--developed", metavar="T0:DT", help="start every cell from a state developed to T0 with dt "
                                                            "DT by --developed-method, one per ratio")
    start.add_argument("--restart", metavar="FILE:T0", help="start every cell from this checkpoint (time T0)")
    ap.add_argument("--developed-method", default="opt", help="NAME[:options] of the developing runs (default opt)")
    ap.add_argument("--relative", type=float, default=0.0, help="the same relative accuracy for every method "
                                                                "(default 0: each method's own tolerance)")
    ap.add_argument("--moved", type=float, default=1e-6, help="a cell counts when a probe changed by this much of "
                                                              "its largest value during it (default 1e-6)")
    ap.add_argument("--probes", default="dy", help="comma-separated probe columns to watch (default dy)")
    args = ap.parse_args()
    B.PROBE_PREFIXES = tuple(p.strip() + "(" for p in args.probes.split(",") if p.strip())
    args.out = os.path.abspath(args.out)
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
    try:
        methods = B.parse_methods(args.methods)
    except ValueError as e:
        ap.error(str(e))
    if not methods or not args.ratios or not args.dts or args.steps < 1:
        ap.error("need at least one method, ratio, dt and step")
    extra = shlex.split(args.extra)
    developed = developed_runs(args, extra)
    if developed:
        bench_runs.run_all(list(developed.values()), args.bin, args.runs_dir, args.jobs, 0, args.force, args.rerun_failed,
                  args.retries)
        bad = [r for r in developed.values() if not r.ok]
        if bad:
            raise SystemExit("stress.py: the developed state failed: " + "; ".join("%s: %s" % (r.name, r.error)
                                                                                 for r in bad))
    grid = cell_runs(args, methods, extra, developed)
    # the heavy walls (few sweeps) first, the light ones (slow or failing partitioned runs) last
    order = sorted(grid.values(), key=lambda r: (-r.params["ratio"], -r.params["dt"]))
    bench_runs.run_all(order, args.bin, args.runs_dir, args.jobs, args.timeout, args.force, args.rerun_failed, args.retries)

    os.makedirs(args.out, exist_ok=True)
    rows = []
    for m in methods:
        for ratio in args.ratios:
            for dt in args.dts:
                r = grid[m.slug, ratio, dt]
                s = r.summary if r.ok else {}
                rows.append({"method": m.spec, "rho_ratio": "%g" % ratio, "dt": "%g" % dt, "steps": args.steps,
                             "status": r.status, "reused": str(r.reused).lower(),
                             "reason": "" if r.ok else reason(r), "error": r.error,
                             "its_per_step": s.get("avg_coupling_iterations", ""),
                             "coupling_iterations": s.get("coupling_iterations", ""),
                             "wall_time_s": s.get("wall_time_s", ""), "elapsed_s": "%.3f" % r.elapsed_s,
                             "fluid_solves": s.get("fluid_solves", ""), "work_factor": s.get("work_factor", ""),
                             "max_interface_jump": s.get("max_interface_jump", ""),
                             "max_abs_dy": "" if math.isnan(max_dy(r)) else max_dy(r),
                             "motion": "" if math.isnan(motion(r)) else "%.3g" % motion(r),
                             "counted": str(counted(r, args)).lower() if r.ok else "true",
                             "difference_to_first_opt": "" if not r.ok else "%.3g" % difference(
                                 r, next((grid[q.slug, ratio, dt] for q in methods if not q.partitioned), None)),
                             "converged": str(s["converged"]).lower() if "converged" in s else "",
                             "run_dir": B.rel(r.run_dir), "command": r.cmdline})
    fields = list(rows[0].keys())
    base = os.path.join(args.out, "stress")
    fr.write_csv(base + ".csv", rows, fields)

    its = [r.summary.get("avg_coupling_iterations") for r in grid.values() if r.ok]
    its = [x for x in its if isinstance(x, (int, float)) and math.isfinite(x)]
    pos = [x for x in its if x > 0]
    vmin = min(1.0, min(pos)) if pos else 1.0
    vmax = max(max(its) if its else 1.0, vmin * 10)
    norm = LogNorm(vmin=vmin, vmax=vmax)
    cbar_label = "coupling iterations per step" + (" (below %g: drawn as %g)" % (vmin, vmin)
                                                   if any(x < vmin for x in its) else "")
    scene = os.path.splitext(os.path.basename(args.options_file))[0]
    start = ("from %s" % args.restart) if args.restart else ("from developed states (%s)" % args.developed
                                                              if args.developed else "from rest")
    title = "%s stress: %d steps %s%s, %s" % (scene, args.steps, start, ", relative accuracy %g" % args.relative
                                              if args.relative else "", "extra " + " ".join(extra) if extra else "")
    pngs = []
    for m in methods:
        fig, ax = plt.subplots(figsize=(1.6 * len(args.dts) + 2.6, 0.75 * len(args.ratios) + 1.8))
        im = draw_map(ax, args, m, grid, norm, args.cmap)
        plain_ticks(fig.colorbar(im, ax=ax, label=cbar_label))
        fig.suptitle(title.rstrip(", "), fontsize=9)
        fig.tight_layout()
        path = "%s-%s.png" % (base, m.slug)
        fig.savefig(path, dpi=130)
        plt.close(fig)
        pngs.append(path)
    n = len(methods)
    fig, axes = plt.subplots(1, n, figsize=((1.6 * len(args.dts) + 1.2) * n + 1.4, 0.75 * len(args.ratios) + 1.9),
                             squeeze=False)
    for k, (ax, m) in enumerate(zip(axes[0], methods)):
        im = draw_map(ax, args, m, grid, norm, args.cmap, ylabel=k == 0)
    plain_ticks(fig.colorbar(im, ax=list(axes[0]), label=cbar_label))
    fig.suptitle(title.rstrip(", "), fontsize=10)
    fig.savefig(base + "-all.png", dpi=110, bbox_inches="tight")
    plt.close(fig)

    if args.relative:
        accuracy = ("every method held to the relative accuracy %g (opt: `-coupling_tol_relative`, the jump below "
                    "%g ||v_s||; partitioned: `-coupling_rtol`, `-coupling_atol 0`)" % (args.relative, args.relative))
    else:
        accuracy = "each method's own tolerance"
    if args.restart:
        begin = "Every cell restarts from `%s` at its own dt (`-restart_change_dt`)" % args.restart
    elif args.developed:
        begin = ("Every cell restarts at its own dt (`-restart_change_dt`) from a state developed to T0:DT = %s by "
                 "%s at its ratio" % (args.developed, args.developed_method))
    else:
        begin = "Every cell starts from rest"
    md = ["# %s stability stress test" % scene, "",
          "%d steps per run, `-options_file %s`%s, timeout %s, %d run(s) at a time. %s; %s. "
          "Coupling its/step: Gauss-Newton iterations for opt, Dirichlet-Neumann sweeps for the partitioned "
          "methods. Cells: its/step, wall s; or the failure. \"wall at rest\": no probe changed by %g of its "
          "largest value during the cell's steps: the cell tests nothing and is not counted." % (
              args.steps, args.options_file, ", extra `%s`" % " ".join(extra) if extra else "",
              "%g s" % args.timeout if args.timeout else "none", args.jobs, begin, accuracy, args.moved), ""]
    ref_method = next((m for m in methods if not m.partitioned), None)
    if ref_method is not None:
        md += ["\"X from %s\": the largest difference of the cell's last probe values (%s) from %s's in the same "
               "cell, relative to each probe's largest value over the series." % (
                   ref_method.name, args.probes, ref_method.spec), ""]
    md += ["| method | counted cells | converged | failed | its/step (counted, converged) |", "|---|---|---|---|---|"]
    for m in methods:
        cells = [grid[m.slug, q, d] for q in args.ratios for d in args.dts]
        count = [r for r in cells if not r.ok or counted(r, args)]
        conv = [r for r in count if r.ok and r.summary.get("converged") is not False]
        its = [r.summary.get("avg_coupling_iterations") for r in conv]
        its = [x for x in its if isinstance(x, (int, float))]
        md.append("| %s | %d of %d | %d | %d | %s |" % (B.md_escape(m.spec), len(count), len(cells), len(conv),
                                                       len(count) - len(conv),
                                                       "%.3g-%.3g" % (min(its), max(its)) if its else "-"))
    md.append("")
    for m in methods:
        md += ["## %s" % m.spec, "", "| rho_s/rho_f \\ dt | " + " | ".join("%g" % d for d in args.dts) + " |",
               "|" + "---|" * (1 + len(args.dts))]
        for ratio in args.ratios:
            cells = []
            for dt in args.dts:
                r = grid[m.slug, ratio, dt]
                if r.ok:
                    s = r.summary
                    n = notes(r, args)
                    if ref_method is not None and m is not ref_method:
                        diff = difference(r, grid[ref_method.slug, ratio, dt])
                        if math.isfinite(diff):
                            n = n + ["%.1e from %s" % (diff, ref_method.name)]
                    cells.append("%.3g, %.2g s%s" % (s.get("avg_coupling_iterations", float("nan")), r.wall,
                                                     " (%s)" % ", ".join(n) if n else ""))
                else:
                    cells.append("**%s** (%.2g s)" % (B.md_escape(reason(r)), r.elapsed_s))
            md.append("| %g | %s |" % (ratio, " | ".join(cells)))
        md.append("")
    failed = [(row, r) for row, r in zip(rows, [grid[m.slug, q, d] for m in methods for q in args.ratios
                                                 for d in args.dts]) if not r.ok]
    if failed:
        md += ["## Failures", ""] + ["- %s, rho_s/rho_f %s, dt %s: %s: %s" % (
            B.md_escape(row["method"]), row["rho_ratio"], row["dt"], r.status, B.md_escape(r.error)) for row, r in failed]
    with open(base + ".md", "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    print("written: %s.csv, %s.md, %s, %s-all.png" % (B.rel(base), B.rel(base), ", ".join(B.rel(p) for p in pngs),
                                                      B.rel(base)))


if __name__ == "__main__":
    main()
