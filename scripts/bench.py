#!/usr/bin/env python3
"""Side-by-side benchmark of the coupling methods of fsiopt on one scene (default channel2d).

Runs bin/fsiopt once per method (-coupling NAME plus the method's own options, the same
horizon and --extra options for all) and once more as the reference: opt with
-coupling_tol 1e-7 -fluid_snes_rtol 1e-10 -fluid_rhs_rtol 1e-12 over the same horizon.
Measures, per method:

  wall time (summary.json wall_time_s), fluid nonlinear solves, fluid linear solves, the
  fluid residual evaluations (-log_view's FluidResidual events), the
  coupling's linearized and adjoint solves (summary.json linearized_solves, the explicit
  Jacobian's columns included), fluid factorizations, coupling iterations per step (for opt: Gauss-Newton iterations; for dn, aitken, iqnils:
  Dirichlet-Neumann sweeps), work factor, max interface jump, converged, the -log_view
  stage times (Main Stage, Setup, Fluid, Structure, Output, Optimizer = the coupling
  method's own work, Sensitivity, Adjoint), and the probe error against the reference:
  max over time and the three dy columns of probes.csv of |dy - dy_ref| divided by that
  column's max |dy_ref|. Every numeric column also gets its ratio to the best (smallest)
  value among the methods that ran (the reference is not a competitor).

A method is NAME[:extra options], e.g. "dn:-coupling_omega 0.05"; --methods takes a
comma-separated list (a comma inside the options, as in "-fluid_dm_plex_box_faces 30,10",
is kept when the text after it does not look like a method name). A failing method is
reported in the tables (status and its `fsiopt: error:` message) and the others go on; the
script exits non-zero only when a reference run fails.

--work-precision: every method is run over a list of tolerances (opt: -coupling_tol
1e-2,1e-3,1e-4,1e-5, --opt-tols; the partitioned methods: -coupling_rtol
1e-3,1e-4,1e-5,1e-6, --rtols) and over --refine-levels (default 0; "0,1" adds the mesh
refined once, -refine 1, with its own reference), and the probe error (against the
reference of the same refine level) is plotted against the wall time, log-log, one line per
method and refine level (work-precision.png, .csv, .md).

Outputs under out/bench/ (--out): bench.csv, bench.md, or work-precision.{png,csv,md}.
Runs go to <out>/runs/<run>/ (--runs-dir), each run with -log_view (stdout.log),
stderr.log, cmd.txt (written after a successful run) and status.json; a complete run whose
command line is the one we would run now is re-used (--force: run again). A run that failed
with an `fsiopt: error:` message or timed out (after at least the current --timeout) is
re-used as a failure too, unless --rerun-failed. A run that dies otherwise (signal, binary
missing or being rebuilt) is retried once after a few seconds (--retries).

Examples (build first: make all; the full T = 0.1 opt run alone takes ~90 s, the partitioned
methods many times that):
  scripts/bench.py --t-final 0.001 --out /tmp/b1
  scripts/bench.py --methods "opt,aitken,iqnils,iqnils:-coupling_iqn_reuse 0" --t-final 0.01
  scripts/bench.py --work-precision --t-final 0.0005 --methods opt,iqnils --out /tmp/b2"""
import argparse, csv, hashlib, math, os, re, shlex, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, extra_tag, floats, fmt_num, ints, md_escape, rel, say   # noqa: E402
from fsiopt_logview import parse_event_count   # noqa: E402
from bench_runs import Run, run_all   # noqa: E402  (the runs: re-use, retries, status.json, -log_view)

FSIOPT = fr.FSIOPT
OPTIONS_FILE = "options/channel2d.yaml"
STAGES = ["Main Stage", "Setup", "Fluid", "Structure", "MeshMotion", "Output", "Optimizer", "Sensitivity", "Adjoint"]
DEFAULT_METHODS = "opt,dn:-coupling_omega 0.05,aitken,iqnils"
REFERENCE_OPTIONS = ["-coupling", "opt", "-coupling_tol", "1e-7", "-fluid_snes_rtol", "1e-10", "-fluid_rhs_rtol", "1e-12"]
REFERENCE_DEFAULT = " ".join(REFERENCE_OPTIONS)
OPT_TOLS = [1e-2, 1e-3, 1e-4, 1e-5]
RTOLS = [1e-3, 1e-4, 1e-5, 1e-6]


# ---------------------------------------------------------------------------- methods
class Method:
    """NAME[:extra options]: -coupling NAME plus the options."""

    def __init__(self, spec):
        spec = spec.strip()
        name, _, opts = spec.partition(":")
        self.spec, self.name, self.options = spec, name.strip(), shlex.split(opts)
        if not re.fullmatch(r"[A-Za-z][\w-]*", self.name):
            raise ValueError("bad method %r: expected NAME[:options]" % spec)
        slug = "-".join([self.name] + [re.sub(r"^-+", "", o) for o in self.options])
        slug = re.sub(r"[^\w.+-]+", "_", slug)
        if len(slug) > 60:
            slug = slug[:40] + "-" + hashlib.sha1(slug.encode()).hexdigest()[:8]
        self.slug = slug

    @property
    def partitioned(self):
        return self.name not in ("opt", "monolithic")   # those two read -coupling_tol

    def coupling_options(self):
        return ["-coupling", self.name] + self.options


def parse_methods(text):
    """'opt,dn:-coupling_omega 0.05,aitken' -> [Method]; a comma followed by something that
    is not a method name (e.g. '30,10') stays inside the options."""
    parts = re.split(r",(?=\s*[A-Za-z][\w-]*\s*(?::|,|$))", text)
    methods = [Method(p) for p in parts if p.strip()]
    if len({m.slug for m in methods}) != len(methods):
        raise ValueError("--methods: a method is listed twice")
    return methods


# ---------------------------------------------------------------------------- probes
PROBE_PREFIXES = ("dy(",)  # --probes


def read_probes(run_dir):
    """(t, {column name: values}) from probes.csv (the columns named by PROBE_PREFIXES, dy(...) by default)."""
    path = os.path.join(run_dir, "probes.csv")
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r]
    names = [fr.column_name(n) for n in rows[0]] if rows else []
    if len(rows) < 2 or names[0] != "t":
        raise ValueError("%s: no data or no first column t" % rel(path))
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    dy = {n: data[:, i] for i, n in enumerate(names) if n.startswith(PROBE_PREFIXES)}
    if not dy:
        raise ValueError("%s: no %s columns" % (rel(path), " or ".join(p + "...)" for p in PROBE_PREFIXES)))
    return data[:, 0], dy


def probe_error(run, ref):
    """max over the dy columns and time of |dy - dy_ref| / max |dy_ref| of that column; the
    run is compared at the reference's times (interpolated when its time grid differs).
    nan when either is missing or the run does not cover the reference's time span."""
    if not (run.ok and ref is not None and ref.ok):
        return float("nan")
    try:
        t, dy = read_probes(run.run_dir)
        tr, dyr = read_probes(ref.run_dir)
    except (OSError, ValueError):
        return float("nan")
    span = max(abs(tr[-1] - tr[0]), 1e-300)
    if abs(t[0] - tr[0]) > 1e-9 * span or abs(t[-1] - tr[-1]) > 1e-9 * span:
        return float("nan")
    err = 0.0
    for name, ref_col in dyr.items():
        if name not in dy:
            return float("nan")
        col = dy[name] if len(t) == len(tr) and np.allclose(t, tr, rtol=0, atol=1e-9 * span) \
            else np.interp(tr, t, dy[name])
        scale = np.max(np.abs(ref_col))
        if scale > 0:
            err = max(err, float(np.max(np.abs(col - ref_col)) / scale))
    return err


# ---------------------------------------------------------------------------- tables
NUMERIC = [  # (csv column, markdown header, format)
    ("wall_time_s", "wall s", "%.3g"),
    ("fluid_solves", "fluid solves", "%d"),
    ("fluid_linear_solves", "fluid linear solves", "%d"),
    ("fluid_residuals", "fluid residuals", "%d"),
    ("linearized_solves", "linearized + adjoint solves", "%d"),
    ("factorizations_fluid", "fluid factorizations", "%d"),
    ("its_per_step", "coupling its/step", "%.3g"),
    ("work_factor", "work factor", "%.3g"),
    ("max_interface_jump", "max jump", "%.2e"),
    ("probe_error", "probe error", "%.2e"),
]


def stage_key(stage):
    return "stage_" + re.sub(r"\W+", "_", stage).strip("_").lower() + "_s"


def bench_row(label, r, ref):
    s = r.summary if r.ok else {}
    f = s.get("factorizations", {})
    lin = s.get("linearized_solves", {})
    row = {"method": label, "status": r.status, "reused": str(r.reused).lower(), "error": r.error,
           "attempts": r.attempts, "elapsed_s": "%.3f" % r.elapsed_s,
           "wall_time_s": s.get("wall_time_s", ""), "fluid_solves": s.get("fluid_solves", ""),
           "fluid_linear_solves": s.get("fluid_linear_solves", ""),
           "linearized_solves": lin.get("forward", 0) + lin.get("adjoint", 0) if lin else "",
           "structure_solves": s.get("structure_solves", ""),
           "coupling_iterations": s.get("coupling_iterations", ""), "its_per_step": s.get("avg_coupling_iterations", ""),
           "work_factor": s.get("work_factor", ""), "max_interface_jump": s.get("max_interface_jump", ""),
           "converged": str(s["converged"]).lower() if "converged" in s else "", "steps": s.get("steps", ""),
           "factorizations_fluid": f.get("fluid", ""), "factorizations_structure": f.get("structure", ""),
           "probe_error": "", "fluid_residuals": "", "run_dir": rel(r.run_dir) if r.run_dir else "", "command": r.cmdline}
    if r.ok and r.run_dir and os.path.isfile(os.path.join(r.run_dir, "stdout.log")):
        with open(os.path.join(r.run_dir, "stdout.log"), errors="replace") as f:
            count = parse_event_count(f.read(), "FluidResidual")
        row["fluid_residuals"] = count if count is not None else ""
    e = probe_error(r, ref)
    if not math.isnan(e):
        row["probe_error"] = e
    for st in STAGES:
        row[stage_key(st)] = r.stages.get(st, "")
    return row


def number(x):
    """fr.number(x) when it is >= 0 (the measured columns), else None."""
    v = fr.number(x)
    return v if v is not None and v >= 0 else None


def add_ratios(rows, keys):
    """row[key + '_ratio'] = value / smallest value of the column (over rows with a value):
    1 for the best; with a best of 0, 1 for the zeros and inf for the others."""
    for k in keys:
        vals = [number(r.get(k)) for r in rows]
        present = [v for v in vals if v is not None]
        if not present:
            continue
        best = min(present)
        for r, v in zip(rows, vals):
            if v is None:
                r[k + "_ratio"] = ""
            elif best > 0:
                r[k + "_ratio"] = v / best
            else:
                r[k + "_ratio"] = 1.0 if v == 0 else float("inf")


def cell(row, key, fmt, ratio=True):
    v = number(row.get(key))
    if v is None:
        return ""
    text = fmt % v
    q = row.get(key + "_ratio", "")
    if ratio and q != "":
        text += " (%s)" % ratio_text(q)
    return text


def ratio_text(q):
    return "x inf" if math.isinf(q) else "x%.2f" % q if q < 100 else "x%.3g" % q


def status_cell(row):
    text = row["status"] + (" (re-used)" if row["reused"] == "true" else "")
    if row["error"]:
        text += " after %.3g s: %s" % (float(row["elapsed_s"]), md_escape(row["error"]))
    return text



def bench(args, methods, extra):
    tf = fmt_num(args.t_final)
    base = ["-options_file", args.options_file, "-t_final", tf]
    tag = "-T%s%s" % (tf, extra_tag(extra))
    ref = Run("reference" + tag, "reference (opt, tight tolerances)", base + REFERENCE_OPTIONS + extra)
    runs = [(m.spec, Run(m.slug + tag, m.spec, base + m.coupling_options() + extra)) for m in methods]
    run_all([r for _, r in runs] + [ref], args.bin, args.runs_dir, args.jobs, args.timeout, args.force,
            args.rerun_failed, args.retries)
    rows = [bench_row(label, r, ref) for label, r in runs]
    stage_keys = [stage_key(s) for s in STAGES]
    ok_rows = [row for row, (_, r) in zip(rows, runs) if r.ok]
    add_ratios(ok_rows, [k for k, _, _ in NUMERIC] + stage_keys)
    ref_row = bench_row("reference", ref, ref)
    fields = ["method", "status", "reused", "error", "attempts", "elapsed_s", "wall_time_s", "fluid_solves",
              "fluid_linear_solves", "fluid_residuals", "linearized_solves", "structure_solves", "coupling_iterations", "its_per_step", "work_factor",
              "max_interface_jump", "converged", "steps", "factorizations_fluid", "factorizations_structure",
              "probe_error"] + stage_keys + [k + "_ratio" for k, _, _ in NUMERIC] + \
             [k + "_ratio" for k in stage_keys] + ["run_dir", "command"]
    os.makedirs(args.out, exist_ok=True)
    csv_path, md_path = os.path.join(args.out, "bench.csv"), os.path.join(args.out, "bench.md")
    fr.write_csv(csv_path, rows + [ref_row], fields)

    present = [s for s in STAGES if any(r.stages.get(s) for _, r in runs + [("", ref)])]
    md = ["# fsiopt coupling methods side by side", "",
          "Scene: `%s`, t_final = %s%s; runs %s, %d at a time%s." % (
              " ".join(base), tf, ", extra options `%s`" % " ".join(extra) if extra else "", rel(args.runs_dir),
              args.jobs, " (timings compete for the cores)" if args.jobs > 1 else ""),
          "Reference: `%s`. Probe error: max over t and the %s probes of |d - d_ref| / max |d_ref|." %
          (" ".join(REFERENCE_OPTIONS), ", ".join(p[:-1] for p in PROBE_PREFIXES)), "(xR) = ratio to the best method in that column. Coupling its/step: "
          "Gauss-Newton iterations for opt, Dirichlet-Neumann sweeps for the partitioned methods.", "",
          "| method | status | " + " | ".join(h for _, h, _ in NUMERIC) + " | converged |",
          "|" + "---|" * (3 + len(NUMERIC))]
    for row in rows + [ref_row]:
        md.append("| %s | %s | %s | %s |" % (md_escape(row["method"]), status_cell(row),
                                              " | ".join(cell(row, k, f) for k, _, f in NUMERIC), row["converged"]))
    md += ["", "## -log_view stage times (s; share of the sum of the stages)", "",
           "| method | " + " | ".join(present) + " |", "|" + "---|" * (1 + len(present))]
    for row, (_, r) in zip(rows + [ref_row], runs + [("", ref)]):
        total = sum(r.stages.values()) or float("nan")
        md.append("| %s | %s |" % (md_escape(row["method"]), " | ".join(
            "%.3g (%.0f%%)%s" % (r.stages[s], 100 * r.stages[s] / total,
                                 " " + ratio_text(row[stage_key(s) + "_ratio"])
                                 if isinstance(row.get(stage_key(s) + "_ratio"), float) else "")
            if s in r.stages else "" for s in present)))
    md.append("")
    md.append("Stage times of a failed run are those up to its failure.")
    failed = [(label, r) for label, r in runs + [("reference", ref)] if not r.ok]
    if failed:
        md += ["", "## Failures", ""] + ["- %s: %s after %.1f s: %s" % (label, r.status, r.elapsed_s, md_escape(r.error))
                                         for label, r in failed]
    if any(row["max_interface_jump"] == 0 for row in rows):
        md += ["", "Max jump 0: the partitioned methods impose the structure's velocity on the fluid as a Dirichlet "
               "condition, so the interface velocity jump vanishes by construction."]
    fr.write_report(md, md_path, [csv_path, md_path])
    return ref.ok


def work_precision(args, methods, extra):
    tf = fmt_num(args.t_final)
    refs, points = {}, []   # points: (method, level, tol, run)
    for level in args.refine_levels:
        lev = ["-refine", str(level)] if level else []
        base = ["-options_file", args.options_file, "-t_final", tf] + lev
        tag = "-T%s%s%s" % (tf, "-r%d" % level if level else "", extra_tag(extra))
        refs[level] = Run("reference" + tag, "reference, refine %d" % level, base + REFERENCE_OPTIONS + extra)
        for m in methods:
            opt, tols = ("-coupling_rtol", args.rtols) if m.partitioned else ("-coupling_tol", args.opt_tols)
            for tol in tols:
                points.append((m, level, tol, Run("%s%s-tol%g" % (m.slug, tag, tol), "%s, tol %g" % (m.spec, tol),
                                                  base + m.coupling_options() + [opt, "%g" % tol] + extra)))
    run_all(list(refs.values()) + [p[3] for p in points], args.bin, args.runs_dir, args.jobs, args.timeout, args.force,
            args.rerun_failed, args.retries)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for m, level, tol, r in points:
        row = bench_row(m.spec, r, refs[level])
        row.update({"refine": level, "tolerance_option": "-coupling_rtol" if m.partitioned else "-coupling_tol",
                    "tolerance": tol})
        rows.append(row)
    for level, r in refs.items():
        row = bench_row("reference", r, r)
        tol = REFERENCE_OPTIONS[REFERENCE_OPTIONS.index("-coupling_tol") + 1] if "-coupling_tol" in REFERENCE_OPTIONS \
            else "nan"
        row.update({"refine": level, "tolerance_option": "-coupling_tol", "tolerance": float(tol)})
        rows.append(row)
    fields = ["method", "refine", "tolerance_option", "tolerance", "status", "reused", "error", "elapsed_s",
              "wall_time_s", "probe_error", "its_per_step", "fluid_solves", "fluid_linear_solves", "work_factor",
              "max_interface_jump", "converged", "steps"] + [stage_key(s) for s in STAGES] + ["run_dir", "command"]
    base_path = os.path.join(args.out, "work-precision")
    fr.write_csv(base_path + ".csv", rows, fields)

    fig, ax = plt.subplots(figsize=(8, 5.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    styles = ["-", "--", ":", "-."]
    markers = ["o", "s", "^", "D"]
    curves = []   # (method index, level index, label, [(wall, error, tol)])
    for i, m in enumerate(methods):
        for j, level in enumerate(args.refine_levels):
            pts = [(r.wall, probe_error(r, refs[level]), tol) for mm, lv, tol, r in points
                   if mm is m and lv == level and r.ok]
            pts = [p for p in pts if not math.isnan(p[1])]
            if pts:
                curves.append((i, j, m.spec + (", refine %d" % level if len(args.refine_levels) > 1 else ""), pts))
    positive = [p[1] for _, _, _, pts in curves for p in pts if p[1] > 0]
    # an error of exactly 0 (probes equal to the reference's as written) is drawn at a floor
    floor = 10 ** (math.floor(math.log10(min(positive))) - 1) if positive else 1e-12
    plotted = bool(curves)
    for i, j, label, pts in curves:
        colour = colours[i % len(colours)]
        xs, ys = [p[0] for p in pts], [p[1] if p[1] > 0 else floor for p in pts]
        ax.plot(xs, ys, styles[j % len(styles)], marker=markers[j % len(markers)], color=colour, label=label)
        for x, y, (_, e, tol) in zip(xs, ys, pts):
            if e == 0:
                ax.plot([x], [y], markers[j % len(markers)], color=colour, mfc="white")
            ax.annotate("%g" % tol, (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
    if plotted and any(p[1] == 0 for _, _, _, pts in curves for p in pts):
        ax.axhline(floor, color="grey", ls=":", lw=0.8)
        ax.text(0.01, floor, " open markers: error 0 (probes equal to the reference's as written), drawn at %g" % floor,
                transform=ax.get_yaxis_transform(), fontsize=7, color="grey", va="top")
    if plotted:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.legend(fontsize="small")
    else:
        ax.text(0.5, 0.5, "no successful run", ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("probe error: max |dy - dy_ref| / max |dy_ref|")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title("work-precision, %s, t_final = %s\n(labels: -coupling_tol for opt, -coupling_rtol for the others)"
                 % (os.path.basename(args.options_file), tf), fontsize=10)
    fig.tight_layout()
    fig.savefig(base_path + ".png", dpi=130)
    plt.close(fig)

    md = ["# fsiopt work-precision", "",
          "Scene: `-options_file %s -t_final %s`%s; reference per refine level: `%s`." % (
              args.options_file, tf, ", extra `%s`" % " ".join(extra) if extra else "", " ".join(REFERENCE_OPTIONS)), "",
          "| method | refine | tolerance | status | wall s | probe error | coupling its/step | fluid solves | work factor |",
          "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        md.append("| %s | %d | %s %g | %s | %s | %s | %s | %s | %s |" % (
            md_escape(row["method"]), row["refine"], row["tolerance_option"], row["tolerance"],
            status_cell(row),
            cell(row, "wall_time_s", "%.3g") or ("(%.3g)" % float(row["elapsed_s"])), cell(row, "probe_error", "%.2e"),
            cell(row, "its_per_step", "%.3g"), cell(row, "fluid_solves", "%d"), cell(row, "work_factor", "%.3g")))
    md += equal_accuracy_table(args, methods, points, refs)
    fr.write_report(md, base_path + ".md", [base_path + e for e in (".png", ".csv", ".md")])
    return all(r.ok for r in refs.values())


def equal_accuracy_table(args, methods, points, refs):
    """The speed-up of one method over each other at equal accuracy, without interpolation:
    for every run of another method, the cheapest run of the chosen method whose probe error
    is no larger, and the ratio of their wall times."""
    chosen = [m for m in methods if m.spec == args.speedup_of] if args.speedup_of else \
        [m for m in methods if not m.partitioned][:1]
    if not chosen:
        return ["", "No equal-accuracy table: --speedup-of names no method of --methods."]
    me = chosen[0]
    md = ["", "## Speed-up of `%s` at equal accuracy" % md_escape(me.spec), "",
          "For each run of another method: the cheapest run of `%s` with a probe error no larger, and the ratio of "
          "the wall times (above 1: `%s` is faster). None: no run of it was that accurate." % (
              md_escape(me.spec), md_escape(me.spec)), "",
          "| refine | method | tolerance | probe error | wall s | its tolerance | its probe error | its wall s | speed-up |",
          "|---|---|---|---|---|---|---|---|---|"]
    for level in args.refine_levels:
        mine = [(r.wall, probe_error(r, refs[level]), tol) for m, lv, tol, r in points
                if m is me and lv == level and r.ok]
        mine = [p for p in mine if not math.isnan(p[1])]
        for m in methods:
            if m is me:
                continue
            for mm, lv, tol, r in points:
                if mm is not m or lv != level or not r.ok:
                    continue
                err = probe_error(r, refs[level])
                if math.isnan(err):
                    continue
                better = [p for p in mine if p[1] <= err]
                if better:
                    w, e, t = min(better)
                    md.append("| %d | %s | %g | %.2e | %.3g | %g | %.2e | %.3g | %.2f |" % (
                        level, md_escape(m.spec), tol, err, r.wall, t, e, w, r.wall / w))
                else:
                    md.append("| %d | %s | %g | %.2e | %.3g | none | | | |" % (level, md_escape(m.spec), tol, err,
                                                                              r.wall))
    return md


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--methods", default=DEFAULT_METHODS,
                    help='comma-separated NAME[:options] (default "%s")' % DEFAULT_METHODS)
    ap.add_argument("--t-final", type=float, default=0.1, help="end time of every run (default 0.1 = 1000 steps)")
    ap.add_argument("--options-file", default=OPTIONS_FILE, help="scene options (default %s)" % OPTIONS_FILE)
    ap.add_argument("--extra", default="", help='options passed to every run, e.g. --extra="-dt 5e-5"')
    ap.add_argument("--jobs", type=int, default=1,
                    help="runs in parallel (default 1: the wall times are compared side by side and must not "
                         "compete for the cores; more jobs skew them)")
    ap.add_argument("--timeout", type=float, default=0, help="seconds per run before it is killed and reported as "
                                                              "timeout (default 0: no limit)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench"), help="output directory (default out/bench)")
    ap.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    ap.add_argument("--probes", default="dy", help="the probes.csv columns the probe error compares, by their "
                    "names' start before the parenthesis, comma separated (default dy; tube3d: dx,dz, its dy probes being zero by symmetry)")
    ap.add_argument("--bin", default=FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--rerun-failed", action="store_true", help="run again runs that failed or timed out before")
    ap.add_argument("--retries", type=int, default=1, help="retries of a run that dies without an fsiopt error "
                                                           "(default 1)")
    ap.add_argument("--work-precision", action="store_true", help="probe error against wall time over tolerances")
    ap.add_argument("--opt-tols", type=floats, default=OPT_TOLS, help="work-precision: -coupling_tol of opt "
                                                                      "(default 1e-2,1e-3,1e-4,1e-5)")
    ap.add_argument("--rtols", type=floats, default=RTOLS, help="work-precision: -coupling_rtol of the partitioned "
                                                                "methods (default 1e-3,1e-4,1e-5,1e-6)")
    ap.add_argument("--refine-levels", type=ints, default=[0], help="work-precision: -refine levels (default 0)")
    ap.add_argument("--reference", default=REFERENCE_DEFAULT,
                    help='the reference run\'s options (default "%s"); a scene whose own -coupling_tol is '
                         'already 1e-7 (turek-hron) needs a tighter one' % REFERENCE_DEFAULT)
    ap.add_argument("--speedup-of", default="",
                    help="work-precision: the method (its NAME[:options] as in --methods) whose speed-up over the "
                         "others at equal probe error is tabulated (default: the first opt method)")
    args = ap.parse_args()
    global PROBE_PREFIXES, REFERENCE_OPTIONS
    REFERENCE_OPTIONS = shlex.split(args.reference)
    PROBE_PREFIXES = tuple(p.strip() + "(" for p in args.probes.split(",") if p.strip())
    if not PROBE_PREFIXES:
        ap.error("--probes: no column")
    args.out = os.path.abspath(args.out)
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
    try:
        methods = parse_methods(args.methods)
    except ValueError as e:
        ap.error(str(e))
    if not methods:
        ap.error("--methods: no method")
    extra = shlex.split(args.extra)
    if not os.path.isfile(args.bin):
        say("bench: %s not found (build first: make all); the runs will retry once" % rel(args.bin), err=True)
    ok = work_precision(args, methods, extra) if args.work_precision else bench(args, methods, extra)
    if not ok:
        say("bench: the reference run failed: no probe errors", err=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
