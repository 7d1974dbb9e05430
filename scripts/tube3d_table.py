#!/usr/bin/env python3
"""The seed's Table 6.1: the 3D pressure-wave tube (scene tube3d) over mesh refinements.

For every refinement level n (--levels, default 1,2,3) generates the fluid and the wall
mesh with gmsh (-setnumber n N: meshes/tube3d-fluid.geo and meshes/tube3d-wall.geo, which
share meshes/tube3d-section.geoinc, so the two meshes of a level conform on r = 0.5) into
out/meshes/tube3d-{fluid,wall}-n<N>.msh (--mesh-dir; re-used while newer than the .geo and
.geoinc files), runs

  bin/fsiopt -options_file options/tube3d.yaml -t_final T -fluid_dm_plex_filename F
             -structure_dm_plex_filename W -log_view [--extra]

over --t-final (default 0.003: the 30 steps of the inlet pulse), and tabulates per level:

  fluid and structure unknowns, steps, Gauss-Newton iterations per step, inner (CG)
  iterations per Gauss-Newton iteration (inner_iterations / coupling_iterations), work
  factor, wall time (summary.json wall_time_s, set-up included), time per step (wall time /
  steps), and the -log_view stage split in s per step: Fluid, Structure, MeshMotion,
  Sensitivity, Adjoint, Optimizer, Setup (the one-off set-up spread over the steps).

Parallel runs: --np P runs `MPIEXEC -n P bin/fsiopt ...` (--mpiexec, default "mpiexec";
P = 1 runs bin/fsiopt directly), --structure-ranks K puts the wall on the last K ranks and
the fluid on the others (-structure_ranks K; 0: both on all P ranks). PETSc's "Summary of
Stages" averages a stage's time over all P ranks, counting 0 on a rank that never enters it;
with K > 0 the Fluid and MeshMotion stages run on the P - K fluid ranks only and Structure
on the K wall ranks only, so the stage split here is scaled back to the average over the
ranks that run the stage (x P/(P-K), x P/K; the CSV keeps PETSc's numbers as well). A run
whose summary.json reports other rank counts than asked for counts as failed (the launcher
started P one-rank runs). The runs get OMPI_ALLOW_RUN_AS_ROOT=1 and
OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 (fsiopt_runs.fsiopt_env, without oversubscription; Open
MPI refuses root otherwise, other users ignore them).

Outputs under out/tube3d/ (--out): table6_1.csv and table6_1.md. Runs go to <out>/runs/<run>/
(--runs-dir) with stdout.log (the -log_view), stderr.log and cmd.txt (written after a
successful run); a complete run whose command line is the one we would run now, and which is
newer than its meshes, is re-used (--force: run again). A level whose mesh generation or run
fails is reported in the table with its error, the other levels go on, and the script exits
non-zero at the end.

Examples (build first: make all; the full pulse at n = 3, ~146k unknowns, takes long):
  scripts/tube3d_table.py --levels 1 --t-final 0.0003 --out /tmp/t1
  scripts/tube3d_table.py --levels 1,2 --np 2 --structure-ranks 1
  scripts/tube3d_table.py"""
import argparse, math, os, re, shlex, sys

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench as B   # noqa: E402
import bench_runs   # noqa: E402  (bench.py's runs)
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, rel, say   # noqa: E402

FSIOPT = fr.FSIOPT
OPTIONS_FILE = "options/tube3d.yaml"
GEO = {"fluid": "meshes/tube3d-fluid.geo", "wall": "meshes/tube3d-wall.geo"}
GEO_INCLUDES = ["meshes/tube3d-section.geoinc"]
# the tube scenes a study can run (--scene of scripts/cost_growth.py): options file, .geo
# files per part and the files they include
TUBES = {"tube3d": (OPTIONS_FILE, GEO, GEO_INCLUDES),
         "bend3d": ("options/bend3d.yaml", {"fluid": "meshes/bend3d-fluid.geo", "wall": "meshes/bend3d-wall.geo"},
                    ["meshes/bend3d.geoinc", "meshes/tube3d-section.geoinc"])}
OUTPUTS = fr.OUTPUTS + ("stdout.log",)
# the stage split of the tables, in s per step; B.STAGES (all of fsiopt's stages) go to the CSV
STEP_STAGES = ["Fluid", "Structure", "MeshMotion", "Sensitivity", "Adjoint", "Optimizer", "Setup"]
FLUID_STAGES = ("Fluid", "MeshMotion")    # entered on the fluid's ranks only
STRUCTURE_STAGES = ("Structure",)         # entered on the structure's ranks only


def per_step_key(stage):
    return re.sub(r"\W+", "_", stage).strip("_").lower() + "_s_per_step"


# ---------------------------------------------------------------------------- meshes
def mesh_paths(level, mesh_dir, scene="tube3d"):
    return {part: os.path.join(mesh_dir, "%s-%s-n%d.msh" % (scene, part, level)) for part in TUBES[scene][1]}


def ensure_meshes(level, mesh_dir, gmsh="gmsh", scene="tube3d"):
    """{'fluid': path, 'wall': path} of level n (fsiopt_runs.ensure_gmsh_mesh). Raises MeshError."""
    paths = mesh_paths(level, mesh_dir, scene)
    _, geos, includes = TUBES[scene]
    for part, geo in geos.items():
        fr.ensure_gmsh_mesh(geo, includes, paths[part], level, 3, "%s n=%d" % (part, level), gmsh=gmsh, verbosity=1)
    return paths


def add_study_args(ap, out_name, extra_example):
    """The arguments every tube3d study shares (checked by check_study_args)."""
    ap.add_argument("--mpiexec", default="mpiexec", help='launcher, called as LAUNCHER -n P bin/fsiopt ... '
                                                         '(default "mpiexec"; e.g. "srun")')
    ap.add_argument("--extra", default="", help='options passed to every run, e.g. --extra="%s"' % extra_example)
    ap.add_argument("--gmsh", default="gmsh", help="gmsh binary (default gmsh)")
    ap.add_argument("--mesh-dir", default=os.path.join(ROOT, "out", "meshes"), help="where the meshes go "
                                                                                    "(default out/meshes)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", out_name), help="output directory "
                                                                               "(default out/%s)" % out_name)


def check_study_args(ap, args, script):
    """The arguments every tube3d study shares: --t-final positive, --mpiexec split into the
    launcher, --out and --mesh-dir made absolute, --extra split, a missing --bin named;
    returns (launcher, extra)."""
    if args.t_final <= 0:
        ap.error("--t-final: positive expected")
    launcher = shlex.split(args.mpiexec)
    if not launcher:
        ap.error("--mpiexec: empty")
    args.out = os.path.abspath(args.out)
    args.mesh_dir = os.path.abspath(args.mesh_dir)
    if not os.path.isfile(args.bin):
        say("%s: %s not found (build first: make all)" % (script, rel(args.bin)), err=True)
    return launcher, shlex.split(args.extra)


# ---------------------------------------------------------------------------- runs
class Run(fr.Variant):
    """A tube3d run on a rank layout: np ranks (launcher + ['-n', np] in front of bin/fsiopt
    when launcher is given), structure_ranks K (0: fluid and structure on all ranks)."""

    def __init__(self, name, label, options, launcher=None, np=1, structure_ranks=0, **params):
        super().__init__(name, label, options, outputs=OUTPUTS, np=np, structure_ranks=structure_ranks, **params)
        self.launcher = list(launcher) if launcher else []
        self.stages = {}

    def command(self, fsiopt, runs_dir):
        cmd = super().command(fsiopt, runs_dir)
        return self.launcher + ["-n", str(self.params["np"])] + cmd if self.launcher else cmd


def tube3d_run(level, t_final, meshes, extra, np=1, structure_ranks=0, launcher=None, scene="tube3d"):
    tf = fr.fmt_num(t_final)
    options = ["-options_file", TUBES[scene][0], "-t_final", tf, "-fluid_dm_plex_filename", rel(meshes["fluid"]),
               "-structure_dm_plex_filename", rel(meshes["wall"])]
    if np > 1:   # the layout asked for, also where fsiopt's default would size a split
        options += ["-structure_ranks", str(structure_ranks)]
    options += ["-log_view"] + extra
    name = "%sn%d-T%s-np%d%s%s" % ("" if scene == "tube3d" else scene + "-", level, tf, np, "-k%d" % structure_ranks if structure_ranks else "",
                                 fr.extra_tag(extra))
    label = "n = %d, %s" % (level, layout_text(np, structure_ranks))
    return Run(name, label, options, launcher=launcher, np=np, structure_ranks=structure_ranks, level=level,
               meshes=meshes)


def layout_text(np, structure_ranks):
    if np == 1:
        return "1 rank"
    if structure_ranks:
        return "%d ranks: fluid %d, structure %d" % (np, np - structure_ranks, structure_ranks)
    return "%d ranks, shared" % np


def failed_run(name, label, error, **params):
    r = Run(name, label, [], **params)
    r.status, r.error = "failed", error
    return r


def forget_if_older(r, runs_dir, files):
    """A run older than a mesh it reads is run again: its cmd.txt goes."""
    cmd_txt = os.path.join(runs_dir, r.name, "cmd.txt")
    try:
        t = os.path.getmtime(cmd_txt)
    except OSError:
        return
    if any(os.path.getmtime(f) > t for f in files if os.path.isfile(f)):
        say("  %-28s older than its meshes: will run again" % r.name)
        os.remove(cmd_txt)


def run_runs(runs, fsiopt, runs_dir, force=False, retries=2):
    """Runs the runs that are not failed already, one at a time (timings), and reads their
    -log_view stage times."""
    todo = [r for r in runs if r.status == "pending"]
    for r in todo:
        forget_if_older(r, runs_dir, r.params.get("meshes", {}).values())
    if todo:
        # fsiopt_env() without oversubscription: a layout larger than the machine fails, as before
        fr.run_all(todo, fsiopt, runs_dir, jobs=1, force=force, retries=retries, oversubscribe=False)
    for r in runs:
        if r.run_dir and (r.ok or os.path.isfile(os.path.join(r.run_dir, "stdout.log"))):
            r.stages = bench_runs.read_stages(r.run_dir)
        error = layout_error(r) if r.ok else ""
        if error:
            say("  %-28s FAILED: %s" % (r.name, error), err=True)
            r.status, r.error = "failed", error
    return runs


def layout_error(r):
    """'' when summary.json's ranks are the layout's, else why not: a launcher that starts P
    separate one-rank runs (e.g. srun with an MPI built without SLURM's PMI) would otherwise
    pass for a P-rank run."""
    np, k = r.params.get("np", 1), r.params.get("structure_ranks", 0)
    ranks = r.summary.get("ranks") or {}
    want = (np - k, k) if k else (np, np)
    got = (ranks.get("fluid"), ranks.get("structure"))
    if got == want:
        return ""
    return ("summary.json has %s fluid / %s structure ranks, the layout %d:%d means %d / %d: the launcher did not "
            "start one %d-rank MPI job (srun with an MPI built without SLURM's PMI? try --mpiexec mpirun)"
            % (got[0], got[1], np, k, want[0], want[1], np))


# ---------------------------------------------------------------------------- rows
def ratio(a, b):
    try:
        a, b = float(a), float(b)
    except (TypeError, ValueError):
        return ""
    return a / b if b else ""


def result_row(r):
    """The numbers of one run: summary.json, derived ratios, stage times (PETSc's average
    over all ranks, whole run: stage_*_s) and the per-step stage split over the ranks that
    run each stage (*_s_per_step)."""
    s = r.summary if r.ok else {}
    np, k = r.params.get("np", 1), r.params.get("structure_ranks", 0)
    ranks = s.get("ranks", {})
    row = {"label": r.label, "status": r.status, "error": r.error, "np": np, "structure_ranks_option": k,
           "fluid_ranks": ranks.get("fluid", ""), "structure_ranks": ranks.get("structure", ""),
           "elapsed_s": r.elapsed_s if math.isfinite(r.elapsed_s) else "",
           "run_dir": rel(r.run_dir) if r.run_dir else "", "command": r.cmdline}
    for key in ("fluid_dofs", "structure_dofs", "steps", "coupling_iterations", "avg_coupling_iterations",
                "inner_iterations", "work_factor", "fluid_solves", "fluid_linear_solves", "structure_solves",
                "wall_time_s", "max_interface_jump", "stalled_steps"):
        row[key] = s.get(key, "")
    row["converged"] = str(s["converged"]).lower() if "converged" in s else ""
    steps = s.get("steps") or 0
    row["inner_per_coupling_iteration"] = ratio(s.get("inner_iterations"), s.get("coupling_iterations"))
    row["time_per_step_s"] = ratio(s.get("wall_time_s"), steps)
    for st in B.STAGES:
        row[B.stage_key(st)] = r.stages.get(st, "")
    for st in STEP_STAGES:
        t = r.stages.get(st)
        if t is None or not steps:
            row[per_step_key(st)] = ""
            continue
        if k and st in FLUID_STAGES:
            t *= np / (np - k)
        elif k and st in STRUCTURE_STAGES:
            t *= np / k
        row[per_step_key(st)] = t / steps
    return row


def fmt(value, f):
    """value formatted with f; '' for a missing value."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return ""
    return f % v if math.isfinite(v) else ""


def status_text(r):
    return {"ok": "ok", "reused": "ok (re-used)"}.get(r.status, r.status)


STAGE_NOTE = ("Stage split: -log_view stage times per step. PETSc averages a stage over all ranks; with "
              "-structure_ranks K > 0 the Fluid and MeshMotion stages are the average over the fluid's ranks "
              "and Structure over the structure's (PETSc's numbers x P/(P-K), x P/K). Setup is the one-off "
              "set-up (meshes read and distributed, discretizations, interface, coupling problem) spread over the "
              "steps. The CSV has PETSc's own numbers (stage_*_s, whole run).")


# ---------------------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", type=fr.ints, default=[1, 2, 3], help="refinement levels n (default 1,2,3)")
    ap.add_argument("--t-final", type=float, default=0.003, help="end time of every run (default 0.003 = 30 steps, "
                                                                 "the inlet pulse)")
    ap.add_argument("--extra", default="", help='options passed to every run, e.g. --extra="-coupling_tol 1e-5"')
    ap.add_argument("--np", type=int, default=1, help="MPI ranks of every run (default 1: no launcher)")
    ap.add_argument("--structure-ranks", type=int, default=0, help="-structure_ranks K: the wall on the last K of "
                                                                   "the --np ranks (default 0: shared)")
    ap.add_argument("--mpiexec", default="mpiexec", help='launcher used when --np > 1, called as LAUNCHER -n P '
                                                         '(default "mpiexec"; e.g. "srun")')
    ap.add_argument("--gmsh", default="gmsh", help="gmsh binary (default gmsh)")
    ap.add_argument("--mesh-dir", default=os.path.join(ROOT, "out", "meshes"), help="where the meshes go "
                                                                                    "(default out/meshes)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "tube3d"), help="output directory (default out/tube3d)")
    ap.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    ap.add_argument("--bin", default=FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error "
                                                           "(default 2)")
    args = ap.parse_args()
    if not args.levels or any(n < 1 for n in args.levels):
        ap.error("--levels: positive integers expected")
    if len(set(args.levels)) != len(args.levels):
        ap.error("--levels: a level is listed twice")
    if args.np < 1:
        ap.error("--np: at least 1")
    if not 0 <= args.structure_ranks < args.np:
        ap.error("--structure-ranks: 0 <= K < --np expected")
    if args.t_final <= 0:
        ap.error("--t-final: positive expected")
    args.out = os.path.abspath(args.out)
    args.mesh_dir = os.path.abspath(args.mesh_dir)
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
    extra = shlex.split(args.extra)
    launcher = shlex.split(args.mpiexec) if args.np > 1 else None
    if args.np > 1 and not launcher:
        ap.error("--mpiexec: empty")
    if not os.path.isfile(args.bin):
        say("tube3d_table: %s not found (build first: make all)" % rel(args.bin), err=True)

    say("meshes in %s" % rel(args.mesh_dir))
    runs = []
    for n in args.levels:
        try:
            meshes = ensure_meshes(n, args.mesh_dir, args.gmsh)
        except fr.MeshError as e:
            say("  mesh n=%d FAILED: %s" % (n, e), err=True)
            runs.append(failed_run("n%d" % n, "n = %d" % n, "mesh: %s" % e, level=n, np=args.np,
                                   structure_ranks=args.structure_ranks))
            continue
        runs.append(tube3d_run(n, args.t_final, meshes, extra, args.np, args.structure_ranks, launcher))
    run_runs(runs, args.bin, args.runs_dir, args.force, args.retries)

    rows = []
    for r in runs:
        row = result_row(r)
        row["level"] = r.params["level"]
        rows.append(row)
    fields = ["level", "status", "error", "np", "structure_ranks_option", "fluid_ranks", "structure_ranks",
              "fluid_dofs", "structure_dofs", "steps", "avg_coupling_iterations", "inner_per_coupling_iteration",
              "work_factor", "wall_time_s", "time_per_step_s"] + [per_step_key(s) for s in STEP_STAGES] + \
             ["coupling_iterations", "inner_iterations", "fluid_solves", "fluid_linear_solves", "structure_solves",
              "max_interface_jump", "stalled_steps", "converged", "elapsed_s"] + \
             [B.stage_key(s) for s in B.STAGES] + ["run_dir", "command"]
    os.makedirs(args.out, exist_ok=True)
    csv_path, md_path = os.path.join(args.out, "table6_1.csv"), os.path.join(args.out, "table6_1.md")
    fr.write_csv(csv_path, rows, fields)

    tf = fr.fmt_num(args.t_final)
    md = ["# Table 6.1: the 3D pressure-wave tube over mesh refinements", "",
          "Scene: `-options_file %s -t_final %s`%s, meshes `%s/tube3d-{fluid,wall}-n<n>.msh`; %s%s; runs in `%s`." % (
              OPTIONS_FILE, tf, ", extra options `%s`" % " ".join(extra) if extra else "", rel(args.mesh_dir),
              layout_text(args.np, args.structure_ranks),
              " (`%s -n %d`)" % (args.mpiexec, args.np) if launcher else "", rel(args.runs_dir)), "",
          "GN: Gauss-Newton iterations; CG: the inner iterations of its sub-solver. Wall time: fsiopt's own "
          "(summary.json, set-up included); s/step = wall / steps.", "",
          "| n | fluid unknowns | structure unknowns | steps | GN its/step | CG its/GN it | work factor | wall s | "
          "s/step | converged | status |", "|" + "---|" * 11]
    for r, row in zip(runs, rows):
        md.append("| %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            row["level"], fmt(row["fluid_dofs"], "%d"), fmt(row["structure_dofs"], "%d"), fmt(row["steps"], "%d"),
            fmt(row["avg_coupling_iterations"], "%.3g"), fmt(row["inner_per_coupling_iteration"], "%.3g"),
            fmt(row["work_factor"], "%.3g"), fmt(row["wall_time_s"], "%.3g"), fmt(row["time_per_step_s"], "%.3g"),
            row["converged"], status_text(r)))
    md += ["", "## -log_view stage split (s per step)", "",
           "| n | " + " | ".join(STEP_STAGES) + " |", "|" + "---|" * (1 + len(STEP_STAGES))]
    for row in rows:
        md.append("| %d | %s |" % (row["level"], " | ".join(fmt(row[per_step_key(s)], "%.3g") for s in STEP_STAGES)))
    md += ["", STAGE_NOTE]
    fr.finish_report(md, md_path, [csv_path, md_path],
                     [("n = %d" % r.params["level"], r) for r in runs if not r.ok], len(runs), "tube3d_table",
                     "level(s)")


if __name__ == "__main__":
    main()
