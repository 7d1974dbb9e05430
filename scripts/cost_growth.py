#!/usr/bin/env python3
"""How the cost of tube3d (or bend3d, --scene) grows with its unknowns: LU against the
iterative solvers of options/solvers/, level by level, one run at a time.

Every level n of --levels (default 1,2) runs with each solver of --solvers (default
lu,iterative):

  [LAUNCHER -n P] bin/fsiopt -options_file options/SCENE.yaml -t_final T
          -fluid_dm_plex_filename F -structure_dm_plex_filename W -log_view
          -fluid_ksp_converged_reason -structure_ksp_converged_reason -mesh_ksp_converged_reason
          [solver's options files] [--extra]

lu adds nothing (MUMPS LU, the default); iterative adds options/solvers/fluid-schur-gamg.yaml,
structure-cg-gamg.yaml and mesh-cg-gamg.yaml; iterative-ilu is fluid-schur-gamg.yaml with
fluid-velocity-ilu.yaml, structure-cg-ilu.yaml and mesh-cg-gamg.yaml (ILU(0) on the fluid's
velocity block and on the wall, for small time steps); iterative-ilu-cholesky the same with
structure-cholesky.yaml in place of structure-cg-ilu.yaml (the wall by MUMPS's Cholesky,
factored once); monolithic is -coupling monolithic (one
MUMPS LU of the whole coupled Jacobian) and monolithic-schur the same with
options/solvers/monolithic-schur.yaml (the fluid and the wall factored apart, GMRES on the
interface traction's Schur complement). The meshes of level n are generated with gmsh
into out/meshes/ (as by scripts/tube3d_table.py; bend3d's from meshes/bend3d-*.geo). --ranks
gives the ranks per level, one number for all or one per level ("1,8,64": a weak-scaling
series, a level per rank count);
with more than one rank the run goes through --mpiexec (default mpiexec; "srun" in a SLURM
job, see scripts/slurm/).

Tabulated per run: unknowns (fluid + wall), wall and stepping time (wall minus the Setup
stage), core-microseconds per unknown and step (stepping x ranks / (steps x unknowns)), peak
memory (summary.json memory_gib.peak) per unknown, Krylov iterations per linear solve of
each subproblem (the mean of the KSP converged-reason lines; forward and transposed solves
together), Gauss-Newton iterations per step and inner iterations per Gauss-Newton
iteration, the -log_view stage split per step, and the kernels a step is made of (the fluid's
field-split application inside a product, the fluid Jacobian and residual, the product's
structure solve, the mesh-motion solve): core-µs per unknown and call and calls per step,
with each kernel's growth from the first level to the last split into the two. The crossover is the first level at
which the iterative runs cost fewer core-microseconds per unknown and step than LU.

--repeat N runs the whole series N times, round after round (level 2, 3, 4, then 2, 3, 4
again, ...), so that this machine's drift over the minutes falls on every level alike; the
report then gives the growth from the first level to the last for each round and its median
(the crossover compares each level's median).

Outputs under out/cost_growth/ (--out): cost_growth.csv and cost_growth.md; runs in
<out>/runs/<run>/, one at a time, re-used while complete with the same command line and
newer than their meshes (--force: run again). A failed run is reported in the tables with
its error and the script exits non-zero at the end.

Examples (build first: make all):
  /usr/bin/python3 scripts/cost_growth.py --levels 1 --t-final 0.0001
  /usr/bin/python3 scripts/cost_growth.py --levels 1,2,3 --t-final 0.0003
  /usr/bin/python3 scripts/cost_growth.py --levels 2,3,4 --t-final 0.001 --solvers iterative-ilu-cholesky --repeat 3
  /usr/bin/python3 scripts/cost_growth.py --scene bend3d --levels 1,2 --t-final 0.0001
  scripts/cost_growth.py --levels 2,3,4 --ranks 8,64,512 --mpiexec srun   # in a SLURM job"""
import argparse, os, re, statistics, sys

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench as B   # noqa: E402
import tube3d_table as T   # noqa: E402
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, rel, say   # noqa: E402
from fsiopt_logview import parse_stage_event_table, parse_stages   # noqa: E402

def solver_files(*names):
    """-options_file arguments for files of options/solvers/, by name."""
    return [a for name in names for a in ("-options_file", "options/solvers/%s.yaml" % name)]


ILU_FLUID = ("fluid-schur-gamg", "fluid-velocity-ilu")
SOLVERS = {
    "lu": [],
    "iterative": solver_files("fluid-schur-gamg", "structure-cg-gamg", "mesh-cg-gamg"),
    "iterative-ilu": solver_files(*ILU_FLUID, "structure-cg-ilu", "mesh-cg-gamg"),
    "iterative-ilu-cholesky": solver_files(*ILU_FLUID, "structure-cholesky", "mesh-cg-gamg"),
    "monolithic": ["-coupling", "monolithic", "-options_allow_unused"],
    "monolithic-schur": ["-coupling", "monolithic", "-options_allow_unused"] + solver_files("monolithic-schur"),
}
REASONS = ["-fluid_ksp_converged_reason", "-structure_ksp_converged_reason", "-mesh_ksp_converged_reason"]
SUBPROBLEMS = ("fluid", "structure", "mesh")
KRYLOV_LINE = re.compile(r"Linear (\w+?)_ solve converged due to \w+ iterations (\d+)")
# The kernels a step is made of, from -log_view: (key, label, stage (None: all stages), the
# event timed, the event counted (None: the timed one), the unknowns it is per). A cost that
# grows with the unknowns is either more calls per step or dearer calls; this splits the two.
# The first three are fixed work per call; a structure or mesh solve iterates inside its call.
FIXED_WORK = ("fs_apply", "fluid_jacobian", "fluid_residual")
KERNELS = [
    ("fs_apply", "product's fluid solve, per field-split application", "Sensitivity", "FluidLinSolve",
     "KSPSolve_FS_Schu", "fluid_dofs"),
    ("fluid_jacobian", "fluid Jacobian assembly", None, "FluidJacobian", None, "fluid_dofs"),
    ("fluid_residual", "fluid residual", None, "FluidResidual", None, "fluid_dofs"),
    ("structure_product", "product's structure solve", "Sensitivity", "StructLinSolve", None, "structure_dofs"),
    ("mesh_solve", "mesh-motion solve", "MeshMotion", "MeshMotion", "KSPSolve", "fluid_dofs"),
]


def int_list(text, what):
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise SystemExit("cost_growth: %s: expected comma-separated integers, got %r" % (what, text))
    if not values or min(values) < 1:
        raise SystemExit("cost_growth: %s: expected integers >= 1, got %r" % (what, text))
    return values


def krylov_iterations(run_dir):
    """{subproblem: mean Krylov iterations per linear solve} from the run's stdout.log."""
    counts = {}
    try:
        with open(os.path.join(run_dir, "stdout.log")) as f:
            for m in KRYLOV_LINE.finditer(f.read()):
                counts.setdefault(m.group(1), []).append(int(m.group(2)))
    except (OSError, TypeError):
        return {}
    return {k: sum(v) / len(v) for k, v in counts.items()}


def kernel_costs(run_dir, row, np):
    """{key_us: core-µs per unknown and call, key_calls: calls per step} of every kernel
    (empty where the run has no such event, e.g. no field split with LU)."""
    out = {}
    try:
        with open(os.path.join(run_dir, "stdout.log")) as f:
            text = f.read()
    except (OSError, TypeError):
        text = ""
    table = parse_stage_event_table(text)
    stages = parse_stages(text)

    def total(stage, event):
        """(count, seconds) of event in stage, or over all stages; a stage's own time for a stage's name"""
        if stage is not None and event == stage:
            return 1, stages.get(stage, 0.0)
        tables = [table.get(stage, {})] if stage is not None else table.values()
        found = [t[event] for t in tables if event in t]
        return sum(e[0] for e in found), sum(e[1] for e in found)

    for key, _, stage, timed, counted, per in KERNELS:
        calls, seconds = total(stage, timed)
        if counted:
            calls = total(stage, counted)[0]
        unknowns, steps = row.get(per) or 0, row.get("steps") or 0
        ok = calls and seconds and unknowns and steps
        out[key + "_us"] = seconds * np / (calls * unknowns) * 1e6 if ok else ""
        out[key + "_calls"] = calls / steps if ok else ""
    return out


def kernel_share(costs, calls, keys=None):
    """core-µs per unknown (fluid + wall) and step of the kernels (those of `keys`, default
    all), at the cost per call of the row `costs` and the calls per step of the row `calls`
    (None when a kernel is missing)"""
    total = 0.0
    for key, _, _, _, _, per in KERNELS:
        if keys is not None and key not in keys:
            continue
        if costs.get(key + "_us", "") == "" or calls.get(key + "_calls", "") == "" or not costs.get("unknowns"):
            return None
        total += costs[key + "_us"] * calls[key + "_calls"] * costs[per] / costs["unknowns"]
    return total


def cost_row(r, level, solver, np):
    row = T.result_row(r)
    row.update(level=level, solver=solver, np=np)
    unknowns = (row["fluid_dofs"] or 0) + (row["structure_dofs"] or 0) if row["fluid_dofs"] != "" else ""
    row["unknowns"] = unknowns
    setup = r.stages.get("Setup")
    stepping = row["wall_time_s"] - setup if row["wall_time_s"] != "" and setup is not None else ""
    row["stepping_s"] = stepping
    steps = row["steps"] or 0
    row["core_us_per_unknown_step"] = stepping * np / (steps * unknowns) * 1e6 if stepping != "" and steps and unknowns else ""
    peak = ((r.summary or {}).get("memory_gib") or {}).get("peak") if r.ok else None
    row["peak_memory_gib"] = peak if peak is not None else ""
    row["peak_kib_per_unknown"] = peak * 2 ** 20 / unknowns if peak is not None and unknowns else ""
    its = krylov_iterations(r.run_dir) if r.run_dir else {}
    for sub in SUBPROBLEMS:
        row["krylov_its_%s" % sub] = its.get(sub, "")
    row.update(kernel_costs(r.run_dir, row, np) if r.run_dir else {})
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="tube3d", choices=sorted(T.TUBES), help="the tube (default tube3d)")
    ap.add_argument("--levels", default="1,2", help="mesh levels n, comma-separated (default 1,2)")
    ap.add_argument("--solvers", default="lu,iterative", help="comma-separated of %s (default lu,iterative)"
                                                              % ",".join(SOLVERS))
    ap.add_argument("--t-final", type=float, default=0.0003, help="end time of every run (default 0.0003 = 3 steps)")
    ap.add_argument("--ranks", default="1", help="MPI ranks: one number, or one per level (default 1)")
    T.add_study_args(ap, "cost_growth", "-coupling_inner gmres")
    ap.add_argument("--bin", default=T.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error")
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds of all the runs, one round after another (default 1); the growth from the "
                         "first level to the last is then given per round, with its median")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat: expected an integer >= 1, got %d" % args.repeat)
    levels = int_list(args.levels, "--levels")
    ranks = int_list(args.ranks, "--ranks")
    if len(ranks) == 1:
        ranks = ranks * len(levels)
    if len(ranks) != len(levels):
        ap.error("--ranks: one number, or one per level (%d levels, %d rank counts)" % (len(levels), len(ranks)))
    solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]
    unknown = [s for s in solvers if s not in SOLVERS]
    if unknown or not solvers:
        ap.error("--solvers: expected some of %s, got %r" % (",".join(SOLVERS), args.solvers))
    launcher, extra = T.check_study_args(ap, args, "cost_growth")
    runs_dir = os.path.join(args.out, "runs")

    meshes = {}
    for level in levels:
        try:
            meshes[level] = T.ensure_meshes(level, args.mesh_dir, args.gmsh, args.scene)
        except fr.MeshError as e:
            say("  mesh n=%d FAILED: %s" % (level, e), err=True)
            meshes[level] = e
    # Round by round, every level in each round: the machine's drift then falls on all levels
    # alike, and each round's ratio between levels compares runs made minutes apart.
    plan = []   # (level, solver, np, run) of round 1, then round 2, ...
    for round_ in range(1, args.repeat + 1):
        tag = "-r%d" % round_ if round_ > 1 else ""
        for level, np in zip(levels, ranks):
            if isinstance(meshes[level], Exception):
                plan += [(level, s, np, T.failed_run("n%d-%s%s" % (level, s, tag), "n = %d, %s" % (level, s),
                                                     "mesh: %s" % meshes[level], np=np)) for s in solvers]
                continue
            for s in solvers:
                r = T.tube3d_run(level, args.t_final, meshes[level], REASONS + SOLVERS[s] + extra, np, 0,
                                 launcher if np > 1 else None, args.scene)
                r.name += tag
                r.label = "n = %d, %s, %s%s" % (level, s, T.layout_text(np, 0),
                                                ", round %d" % round_ if args.repeat > 1 else "")
                plan.append((level, s, np, r))
    T.run_runs([p[3] for p in plan], args.bin, runs_dir, args.force, args.retries)

    rows = [cost_row(r, level, s, np) for level, s, np, r in plan]
    for i, row in enumerate(rows):
        row["round"] = i // (len(levels) * len(solvers)) + 1
    step_keys = [T.per_step_key(st) for st in T.STEP_STAGES]
    fields = ["round", "level", "solver", "np", "status", "error", "fluid_dofs", "structure_dofs", "unknowns", "steps",
              "wall_time_s", "stepping_s", "core_us_per_unknown_step", "peak_memory_gib", "peak_kib_per_unknown"] + \
             ["krylov_its_%s" % sub for sub in SUBPROBLEMS] + \
             ["avg_coupling_iterations", "inner_per_coupling_iteration", "coupling_iterations", "inner_iterations",
              "fluid_linear_solves", "max_interface_jump", "converged"] + step_keys + \
             [k + suffix for k, *_ in KERNELS for suffix in ("_us", "_calls")] + \
             [B.stage_key(st) for st in B.STAGES] + ["run_dir", "command"]
    os.makedirs(args.out, exist_ok=True)
    base = os.path.join(args.out, "cost_growth")
    fr.write_csv(base + ".csv", rows, fields)

    fmt = T.fmt
    tf = fr.fmt_num(args.t_final)
    md = ["# fsiopt cost growth: %s, LU against iterative solvers" % args.scene, "",
          "Scene: `-options_file %s -t_final %s`%s; levels %s on %s rank(s); runs in `%s`, one at a time. "
          "%s." % (T.TUBES[args.scene][0], tf, ", extra options `%s`" % " ".join(extra) if extra else "",
                   ",".join(map(str, levels)), ",".join(map(str, ranks)), rel(runs_dir),
                   "; ".join("%s = %s" % (s, " ".join(SOLVERS[s][1::2])) for s in solvers if SOLVERS[s])), "",
          "| level | solver | ranks | unknowns | wall s | stepping s | core-µs / unknown / step | peak KiB / unknown "
          "| Krylov its fluid / structure / mesh | GN its/step | inner its/GN it | status |", "|" + "---|" * 12]

    def lev(row):
        """the level, and its round when there are several"""
        return "%s (round %d)" % (row["level"], row["round"]) if args.repeat > 1 else str(row["level"])

    for (level, s, np, r), row in zip(plan, rows):
        md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            lev(row), s, np, row["unknowns"], fmt(row["wall_time_s"], "%.3g"), fmt(row["stepping_s"], "%.3g"),
            fmt(row["core_us_per_unknown_step"], "%.4g"), fmt(row["peak_kib_per_unknown"], "%.3g"),
            " / ".join(fmt(row["krylov_its_%s" % sub], "%.1f") or "-" for sub in SUBPROBLEMS),
            fmt(row["avg_coupling_iterations"], "%.3g"), fmt(row["inner_per_coupling_iteration"], "%.3g"),
            T.status_text(r)))
    cost = {}   # (level, solver): the median over the rounds
    for key in {(row["level"], row["solver"]) for row in rows}:
        values = [row["core_us_per_unknown_step"] for row in rows if (row["level"], row["solver"]) == key
                  and row["core_us_per_unknown_step"] != ""]
        cost[key] = statistics.median(values) if values else ""
    cross = [lv for lv in levels if cost.get((lv, "iterative"), "") != "" and cost.get((lv, "lu"), "") != ""
             and cost[(lv, "iterative")] < cost[(lv, "lu")]]
    compared = [lv for lv in levels if cost.get((lv, "iterative"), "") != "" and cost.get((lv, "lu"), "") != ""]
    if compared:
        md += ["", "Iterative over LU, core-µs per unknown and step: %s. Crossover: %s." % (
            ", ".join("level %d %.3g×" % (lv, cost[(lv, "iterative")] / cost[(lv, "lu")]) for lv in compared),
            "level %d" % cross[0] if cross else "none up to level %d" % compared[-1])]
    md += ["", "## -log_view stage split (s per step)", "",
           "| level | solver | " + " | ".join(T.STEP_STAGES) + " |", "|" + "---|" * (2 + len(T.STEP_STAGES))]
    for row in rows:
        md.append("| %s | %s | %s |" % (lev(row), row["solver"], " | ".join(fmt(row[k], "%.3g") for k in step_keys)))
    md += ["", T.STAGE_NOTE]
    md += ["", "## Kernels: core-µs per unknown and call × calls per step", "",
           "| level | solver | " + " | ".join(k[1] for k in KERNELS) + " |", "|" + "---|" * (2 + len(KERNELS))]
    for row in rows:
        md.append("| %s | %s | %s |" % (lev(row), row["solver"], " | ".join(
            "%s × %s" % (fmt(row.get(k + "_us", ""), "%.3g"), fmt(row.get(k + "_calls", ""), "%.3g"))
            if row.get(k + "_us", "") != "" else "-" for k, *_ in KERNELS)))
    ratios = {s: [] for s in solvers}   # each round's growth from the first level to the last
    for s, round_ in [(s, k) for s in solvers for k in range(1, args.repeat + 1)]:
        mine = [row for row in rows if row["solver"] == s and row["round"] == round_
                and row.get("core_us_per_unknown_step", "") != ""]
        if len(mine) < 2:
            continue
        a, b = mine[0], mine[-1]
        growth = b["core_us_per_unknown_step"] / a["core_us_per_unknown_step"]
        if (a["level"], b["level"]) == (levels[0], levels[-1]):
            ratios[s].append(growth)
        parts = ["%s %.3g× per call, %.3g× calls" % (label, b[k + "_us"] / a[k + "_us"], b[k + "_calls"] / a[k + "_calls"])
                 for k, label, *_ in KERNELS if a.get(k + "_us", "") != "" and b.get(k + "_us", "") != ""]
        md += ["", "%s%s, level %s → %s: the whole step %.3g×; %s." % (
            s, ", round %d" % round_ if args.repeat > 1 else "", a["level"], b["level"], growth, "; ".join(parts))]
        shares = [kernel_share(a, a), kernel_share(b, b)]
        fixed = [kernel_share(a, a, FIXED_WORK), kernel_share(b, a, FIXED_WORK)]
        if all(shares) and all(fixed):
            md[-1] += (" At level %s's calls per step, level %s's kernels would cost %.3g× level %s's, the fluid's "
                       "three alone %.3g× (their work per call has no iteration in it: no iteration count removes "
                       "this growth). The kernels make %.0f %% and %.0f %% of the steps' cost." % (
                           a["level"], b["level"], kernel_share(b, a) / shares[0], a["level"], fixed[1] / fixed[0],
                           100 * shares[0] / a["core_us_per_unknown_step"], 100 * shares[1] / b["core_us_per_unknown_step"]))
    for s in solvers if args.repeat > 1 else []:
        if ratios[s]:
            md += ["", "%s, level %d → %d, the whole step per unknown, round by round: %s; median %.3g×, %d of %d "
                   "rounds measured." % (s, levels[0], levels[-1], ", ".join("%.3g×" % x for x in ratios[s]),
                                         statistics.median(ratios[s]), len(ratios[s]), args.repeat)]
    md += ["", "A kernel's cost is per unknown of its subproblem (fluid or structure; the mesh motion's per fluid "
           "unknown) and per call: a call of the field-split row is one application of the fluid's Schur field "
           "split inside a product's FGMRES (the product's fluid solve time over the applications), the mesh-motion "
           "row's one CG solve (the MeshMotion stage over its solves). A kernel whose cost per unknown and call "
           "grows does more work per unknown (wider stencils, more multigrid levels) or runs slower (caches); one "
           "whose calls per step grow is iterated more."]
    fr.finish_report(md, base + ".md", [base + e for e in (".csv", ".md")],
                     [(r.label, r) for _, _, _, r in plan if not r.ok], len(plan), "cost_growth", "run(s)")


if __name__ == "__main__":
    main()
