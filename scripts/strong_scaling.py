#!/usr/bin/env python3
"""Strong scaling of fsiopt on the 3D pressure-wave tube (scene tube3d): one mesh level, one
short horizon, several rank layouts.

A layout is P:K = MPI ranks : structure ranks (-structure_ranks K: the wall on the last K
ranks, the fluid on the other P - K; K = 0: both on all P ranks, one after the other; "P"
alone means P:0). --layouts takes a comma-separated list (default "1:0,2:1,2:0"); every
layout runs

  MPIEXEC -n P bin/fsiopt -options_file options/tube3d.yaml -t_final T
          -fluid_dm_plex_filename F -structure_dm_plex_filename W [-structure_ranks K]
          -log_view [--extra]

with the meshes of level n (--level, default 2, ~46k unknowns; generated with gmsh into
out/meshes/ as by scripts/tube3d_table.py) over --t-final (default 0.0005 = 5 steps).
MPIEXEC is --mpiexec (default "mpiexec"; split like a shell command line, so
--mpiexec srun or --mpiexec "srun --cpu-bind=cores" or --mpiexec "mpiexec --bind-to core"
work). The one-rank layout goes through the launcher as well, so every layout starts the
same way (inside a SLURM job, srun places and binds it like the others).

Tabulated per layout: fluid and structure ranks, wall time (summary.json wall_time_s,
set-up included), speed-up and parallel efficiency against the first layout (S = T1/T,
E = S P1/P), time per step (wall / steps), the speed-up of the time stepping alone (wall
time minus the Setup stage), Gauss-Newton iterations per step and CG iterations per
Gauss-Newton iteration (the same algorithm on every layout: these should barely move), and
the -log_view stage split in s per step (as in tube3d_table.py: with K > 0, Fluid and
MeshMotion averaged over the fluid's ranks, Structure over the structure's).

Outputs under out/scaling/ (--out): scaling.csv, scaling.md and scaling.png (speed-up
against ranks, log-log, with the ideal line P/P1; shared and split layouts as separate
series; open markers: the time stepping alone). Runs go to <out>/runs/<run>/ (--runs-dir),
one at a time, re-used while complete, with the same command line and newer than their
meshes (--force: run again). A failing layout is reported in the tables with its error and
the script exits non-zero at the end; so is a run whose summary.json reports other rank
counts than its layout (a launcher that started P separate one-rank runs, e.g. srun with an
MPI built without SLURM's PMI support).

The runs get OMPI_ALLOW_RUN_AS_ROOT=1 and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
(fsiopt_runs.fsiopt_env, without oversubscription; Open MPI refuses root otherwise, other
users ignore them).

Examples (build first: make all):
  scripts/strong_scaling.py --level 1 --t-final 0.0003 --layouts 1:0,2:1
  scripts/strong_scaling.py                                  # n = 2, 1:0,2:1,2:0
  scripts/strong_scaling.py --level 3 --mpiexec srun --layouts "8:0,16:0,16:4,32:8"   # in a SLURM job"""
import argparse, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.ticker import FuncFormatter

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench as B   # noqa: E402
import tube3d_table as T   # noqa: E402
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, number, rel, say   # noqa: E402
from fsiopt_logview import parse_stage_events   # noqa: E402

DEFAULT_LAYOUTS = "1:0,2:1,2:0"


def parse_layouts(text):
    """'1:0,2:1,8' -> [(1, 0), (2, 1), (8, 0)]; 0 <= K < P."""
    layouts = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        p, _, k = part.partition(":")
        try:
            p, k = int(p), int(k or 0)
        except ValueError:
            raise ValueError("bad layout %r: expected P:K (integers)" % part)
        if p < 1 or not 0 <= k < p:
            raise ValueError("bad layout %r: expected P >= 1 and 0 <= K < P" % part)
        layouts.append((p, k))
    if len(set(layouts)) != len(layouts):
        raise ValueError("a layout is listed twice")
    return layouts


def layouts_argument(ap, text):
    """--layouts parsed, or the parser's one-line error"""
    try:
        layouts = parse_layouts(text)
    except ValueError as e:
        ap.error("--layouts: %s" % e)
    if not layouts:
        ap.error("--layouts: no layout")
    return layouts


def stepping_time(row):
    """wall time minus the Setup stage (s), or None."""
    wall, setup = number(row.get("wall_time_s")), number(row.get(B.stage_key("Setup")))
    return wall - setup if wall is not None and setup is not None else None


def add_speedups(rows):
    """speed-up and efficiency of every row against the first row (blank when either failed)."""
    base = rows[0]
    t0, s0, p0 = number(base["wall_time_s"]), stepping_time(base), base["np"]
    for row in rows:
        t, s = number(row["wall_time_s"]), stepping_time(row)
        row["stepping_s"] = s if s is not None else ""
        row["speedup"] = t0 / t if t0 and t else ""
        row["efficiency"] = row["speedup"] * p0 / row["np"] if row["speedup"] != "" else ""
        row["stepping_speedup"] = s0 / s if s0 and s else ""
        row["stepping_efficiency"] = row["stepping_speedup"] * p0 / row["np"] if row["stepping_speedup"] != "" else ""


PRODUCT_STAGES = ("Sensitivity", "Adjoint")


def overlap_ideal(r, lagged):
    """What separate fluid and structure ranks can do at the same time, from a one-rank run's
    -log_view (s): the linearized solves of the products (FluidLinSolve against StructLinSolve
    in the Sensitivity and Adjoint stages), and on a lagged domain also the nonlinear solves
    (Fluid + MeshMotion against Structure); on the current domain the structure solves before
    the fluid. None when the log is unreadable."""
    try:
        with open(os.path.join(r.run_dir, "stdout.log")) as f:
            events = parse_stage_events(f.read())
    except (OSError, TypeError):
        return None
    fluid = sum(events.get(st, {}).get("FluidLinSolve", 0.0) for st in PRODUCT_STAGES)
    structure = sum(events.get(st, {}).get("StructLinSolve", 0.0) for st in PRODUCT_STAGES)
    if not fluid and not structure:
        return None
    overlap = {"products_fluid_s": fluid, "products_structure_s": structure, "overlap_s": min(fluid, structure)}
    if lagged:
        f = r.stages.get("Fluid", 0.0) + r.stages.get("MeshMotion", 0.0)
        overlap["overlap_s"] += min(f, r.stages.get("Structure", 0.0))
    return overlap


def add_ideal(rows, runs, lagged):
    """ideal_speedup of the 2:1 layouts against a 1:0 first layout: its stepping time over
    that time less what the two ranks could overlap (the rest runs one after the other)."""
    base = rows[0]
    ideal = overlap_ideal(runs[0], lagged) if base["np"] == 1 and runs[0].ok else None
    s0 = stepping_time(base)
    for row in rows:
        row["ideal_speedup"] = ""
        if ideal and s0 and row["np"] == 2 and row["structure_ranks_option"] == 1:
            row["ideal_speedup"] = s0 / (s0 - ideal["overlap_s"])
    return ideal


def plot(path, rows, title):
    fig, ax = plt.subplots(figsize=(7, 5))
    ok = [r for r in rows if number(r["speedup"]) is not None]
    if ok:
        p0 = rows[0]["np"]
        ps = sorted({r["np"] for r in rows})
        lo, hi = min(ps + [p0]), max(ps + [p0])
        ax.plot([lo, hi], [lo / p0, hi / p0], "--", color="grey", lw=1, label="ideal (P/%d)" % p0)
        colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for i, (label, pick) in enumerate((("shared: -structure_ranks 0", lambda r: r["structure_ranks_option"] == 0),
                                           ("split: -structure_ranks K > 0", lambda r: r["structure_ranks_option"] > 0))):
            series = sorted((r for r in ok if pick(r)), key=lambda r: (r["np"], r["structure_ranks_option"]))
            if not series:
                continue
            c = colours[i % len(colours)]
            xs = [r["np"] for r in series]
            ax.plot(xs, [r["speedup"] for r in series], "-o", color=c, zorder=3, label=label + ", wall time")
            st = [(r["np"], r["stepping_speedup"]) for r in series if number(r["stepping_speedup"]) is not None]
            if st:   # larger open markers behind the filled ones, so that both show where they meet
                ax.plot([x for x, _ in st], [y for _, y in st], ":o", color=c, mfc="white", ms=10, zorder=2,
                        label=label + ", time stepping (wall - Setup)")
            for r in series:
                ax.annotate(r["layout"], (r["np"], r["speedup"]), textcoords="offset points", xytext=(5, -10),
                            fontsize=8, color=c)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log", base=2)
        ax.set_xticks(ps)
        ax.set_xticklabels([str(p) for p in ps])
        ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: "%g" % y))
        ax.legend(fontsize="small", loc="upper left")
    else:
        ax.text(0.5, 0.5, "no speed-up: the first layout or all others failed", ha="center", va="center",
                transform=ax.transAxes)
    ax.set_xlabel("MPI ranks P")
    ax.set_ylabel("speed-up against layout %s" % rows[0]["layout"])
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--level", type=int, default=2, help="mesh refinement level n (default 2)")
    ap.add_argument("--t-final", type=float, default=0.0005, help="end time of every run (default 0.0005 = 5 steps)")
    ap.add_argument("--layouts", default=DEFAULT_LAYOUTS, help='comma-separated P:K, MPI ranks : structure ranks; '
                                                               'the first is the speed-up\'s base (default "%s")'
                                                               % DEFAULT_LAYOUTS)
    T.add_study_args(ap, "scaling", "-coupling_tol 1e-5")
    ap.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    ap.add_argument("--bin", default=T.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error "
                                                           "(default 2)")
    args = ap.parse_args()
    layouts = layouts_argument(ap, args.layouts)
    if args.level < 1:
        ap.error("--level: at least 1")
    launcher, extra = T.check_study_args(ap, args, "strong_scaling")
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))

    say("meshes in %s" % rel(args.mesh_dir))
    runs = []
    try:
        meshes = T.ensure_meshes(args.level, args.mesh_dir, args.gmsh)
    except fr.MeshError as e:
        say("  mesh n=%d FAILED: %s" % (args.level, e), err=True)
        runs = [T.failed_run("np%d-k%d" % (p, k), T.layout_text(p, k), "mesh: %s" % e, np=p, structure_ranks=k)
                for p, k in layouts]
    else:
        runs = [T.tube3d_run(args.level, args.t_final, meshes, extra, p, k, launcher) for p, k in layouts]
    T.run_runs(runs, args.bin, args.runs_dir, args.force, args.retries)

    rows = []
    for (p, k), r in zip(layouts, runs):
        row = T.result_row(r)
        row["layout"] = "%d:%d" % (p, k)
        rows.append(row)
    add_speedups(rows)
    lagged = "lagged" in extra[extra.index("-coupling_domain") + 1:][:1] if "-coupling_domain" in extra else False
    ideal = add_ideal(rows, runs, lagged)
    step_keys = [T.per_step_key(s) for s in T.STEP_STAGES]
    fields = ["layout", "status", "error", "np", "structure_ranks_option", "fluid_ranks", "structure_ranks",
              "wall_time_s", "speedup", "efficiency", "time_per_step_s", "stepping_s", "stepping_speedup",
              "stepping_efficiency", "ideal_speedup"] + step_keys + \
             ["fluid_dofs", "structure_dofs", "steps", "avg_coupling_iterations", "inner_per_coupling_iteration",
              "coupling_iterations", "inner_iterations", "work_factor", "fluid_solves", "fluid_linear_solves",
              "max_interface_jump", "stalled_steps", "converged", "elapsed_s"] + \
             [B.stage_key(s) for s in B.STAGES] + ["run_dir", "command"]
    os.makedirs(args.out, exist_ok=True)
    base = os.path.join(args.out, "scaling")
    fr.write_csv(base + ".csv", rows, fields)
    tf = fr.fmt_num(args.t_final)
    dofs = next(((r["fluid_dofs"], r["structure_dofs"]) for r in rows if r["fluid_dofs"] != ""), None)
    plot(base + ".png", rows, "fsiopt strong scaling, tube3d n = %d%s, t_final = %s" % (
        args.level, " (%d + %d unknowns)" % dofs if dofs else "", tf))

    fmt = T.fmt
    md = ["# fsiopt strong scaling: tube3d", "",
          "Scene: `-options_file %s -t_final %s`%s, level n = %d (`%s/tube3d-{fluid,wall}-n%d.msh`%s); launcher "
          "`%s -n P`; runs in `%s`, one at a time." % (
              T.OPTIONS_FILE, tf, ", extra options `%s`" % " ".join(extra) if extra else "", args.level,
              rel(args.mesh_dir), args.level, ", %d fluid + %d structure unknowns" % dofs if dofs else "",
              args.mpiexec, rel(args.runs_dir)), "",
          "Layout P:K = MPI ranks : structure ranks (K = 0: fluid and structure share all P ranks). Speed-up S and "
          "efficiency E = S P1/P against the first layout (%s). Wall: fsiopt's own (summary.json, set-up "
          "included); s/step = wall / steps; stepping = wall minus the Setup stage." % rows[0]["layout"], "",
          "| layout | fluid / structure ranks | wall s | speed-up | efficiency | s/step | stepping speed-up | "
          "GN its/step | CG its/GN it | status |", "|" + "---|" * 10]
    for r, row in zip(runs, rows):
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            row["layout"], "%s / %s" % (row["fluid_ranks"], row["structure_ranks"]) if row["fluid_ranks"] != "" else "",
            fmt(row["wall_time_s"], "%.3g"), fmt(row["speedup"], "%.2f"), fmt(100 * row["efficiency"] if row["efficiency"] != "" else "", "%.0f%%"),
            fmt(row["time_per_step_s"], "%.3g"), fmt(row["stepping_speedup"], "%.2f"),
            fmt(row["avg_coupling_iterations"], "%.3g"), fmt(row["inner_per_coupling_iteration"], "%.3g"),
            T.status_text(r)))
    split = [row for row in rows if row["ideal_speedup"] != ""]
    if ideal and split:
        md += ["", "Overlap on fluid | structure ranks (2:1): of the first layout's %.3g s of time stepping, the "
               "products' linearized solves take %.3g s in the fluid and %.3g s in the structure (FluidLinSolve, "
               "StructLinSolve in the Sensitivity and Adjoint stages)%s; two ranks can do at most %.3g s of it at "
               "the same time, the rest runs one after the other (%s). Ideal stepping speed-up of 2:1: %.2f; "
               "measured: %s." % (
                   stepping_time(rows[0]), ideal["products_fluid_s"], ideal["products_structure_s"],
                   " and, on the lagged domain, the nonlinear solves" if lagged else "", ideal["overlap_s"],
                   "the lagged domain: fluid and structure solve at once" if lagged else
                   "the current domain: the structure solves before the fluid", split[0]["ideal_speedup"],
                   ", ".join(fmt(row["stepping_speedup"], "%.2f") for row in split))]
    md += ["", "## -log_view stage split (s per step)", "",
           "| layout | " + " | ".join(T.STEP_STAGES) + " |", "|" + "---|" * (1 + len(T.STEP_STAGES))]
    for row in rows:
        md.append("| %s | %s |" % (row["layout"], " | ".join(fmt(row[k], "%.3g") for k in step_keys)))
    md += ["", T.STAGE_NOTE]
    fr.finish_report(md, base + ".md", [base + e for e in (".csv", ".md", ".png")],
                     [(row["layout"], r) for row, r in zip(rows, runs) if not r.ok], len(runs), "strong_scaling",
                     "layout(s)")


if __name__ == "__main__":
    main()
