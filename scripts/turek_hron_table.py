#!/usr/bin/env python3
"""The Turek-Hron benchmarks (options/turek-hron/CASE.yaml) over mesh refinements: our values in a table.

For every case (--cases, default all nine: csm1,csm2,csm3,cfd1,cfd2,cfd3,fsi1,fsi2,fsi3) and
refinement level n (--levels, default 1,2) generates the meshes the case needs with gmsh
(-setnumber n N: meshes/turek-hron-fluid.geo and meshes/turek-hron-flag.geo, which share
meshes/turek-hron.geoinc, so the two meshes of a level conform on the flag) into
out/meshes/turek-hron-{fluid,flag}-n<N>.msh (--mesh-dir; re-used while newer than the .geo
and .geoinc files), runs

  bin/fsiopt -options_file options/turek-hron/CASE.yaml
             [-fluid_dm_plex_filename F] [-structure_dm_plex_filename S]
             [-dt DT] [-t_final T] [--extra]

(csm*: the flag alone, only S; cfd*: the fluid around a rigid flag, only F; fsi*: both) and
tabulates per (case, level): unknowns (fluid + structure), dt, T and the quantities window
the run reports (summary.json), the displacement of the flag's tip A = (0.6, 0.2) ux(A),
uy(A) in m, the force of the fluid on cylinder and flag, drag and lift in N/m (SI
throughout), Gauss-Newton iterations per step (coupled runs only) and the wall time. A
steady case (csm1, csm2, cfd1, cfd2, fsi1), or any run with window 0, shows the final value; a
periodic case (csm3, cfd3, fsi2, fsi3) shows "mean ± amplitude [frequency Hz]" over the
window (summary.json quantities; "—" Hz when no period was found in it). A second table
gives, per case, the relative change (%) of each shown value from the case's previous level
that ran. Values are ours, as measured; the script writes no reference values.

dt, T and the window are each case's own (options/turek-hron/CASE.yaml) unless changed here:
  --dt-scale S   passes -dt (the case's default dt) x S; the default is the one the binary
                 reports with -help (which runs no step; it is what a run without -dt would
                 use); the script stops with a message if it cannot answer, and refuses -dt
                 in --extra as well;
  --t-final T    passes -t_final T to every case (quick checks: a T shorter than a periodic
                 case's window makes the window the whole run, flagged with * in the table);
  --extra "..."  options passed to every run (e.g. --extra="-coupling_tol 1e-8"; not
                 -checkpoint_every, -checkpoint_file or -restart: see below).

Run times: csm1, csm2, cfd1 and short checks take seconds to a minute a run on n = 1, 2; the periodic
cases run thousands of steps, and the periodic FSI cases (fsi2, fsi3) take hours already on
the coarse level n = 1 (measured times: docs/turek-hron.md). --jobs J runs J runs at a time (one core
each); the default 1 gives undisturbed wall times.

Checkpoints and resuming (the long runs):
  --checkpoint-every K  the periodic cases (csm3, cfd3, fsi2, fsi3) run with
                 -checkpoint_every K (default 500; 0: off), so fsiopt keeps the state of
                 every K-th step in <run dir>/checkpoint.h5; the steady cases never get it
                 (they are short), nor fsi runs whose --extra chooses a -coupling other than
                 opt (fsiopt checkpoints only -coupling opt). -checkpoint_every is NOT part of
                 the command line recorded in cmd.txt, which decides re-use: a complete run
                 is re-used whatever K it ran with (runs made before this option existed
                 too), and changing K never runs a case again. Why: K does not change what a
                 run computes, only when the coupled runs resynchronize their solvers (the
                 explicit Jacobian is rebuilt after each checkpoint, as a restarted run
                 builds it), which moves values by ~1e-8 relative, far below the 5
                 significant digits of the table; a structure-alone (csm) run is bitwise the
                 same. The exact command of each process is in <run dir>/attempts.json.
  resuming       an unfinished run (killed, interrupted by Ctrl-C or SIGTERM, a crash, a
                 failed step) whose directory has a checkpoint.h5 of the same command line
                 (cmd.txt's, kept in cmd.pending from its start) continues from it with
                 -restart <run dir>/checkpoint.h5 (one line `resuming from step N` per run),
                 in the same invocation when the process died without fsiopt's error line,
                 else when the script runs again; a checkpoint of another command line, an
                 unreadable one, or one of a run older than its meshes is deleted and the
                 run starts over; so does --force. A restart fsiopt refuses (another dt,
                 other unknowns, the checkpoint at the last step) starts over once with a
                 note. fsiopt restarts write probes.csv of the whole run, but summary.json
                 and history.csv of their own steps only: each process is recorded as a part
                 in <run dir>/attempts.json (steps first_step..last_step it hands on,
                 coupling iterations over them, its whole wall time), and the table's wall
                 time is the sum over the parts (including the steps a killed part ran past
                 its last checkpoint, which the next part ran again; "≈": a part's time
                 estimated from its files' times when neither fsiopt nor the script timed
                 it), GN its/step = the parts' coupling iterations / the run's steps (when a
                 part's count is unknown: the last part's, labelled with its steps). The
                 other counts of summary.json (work factor, inner iterations, maximal jump,
                 factorizations) are the last part's (table.csv: parts, its_cover,
                 last_part_steps); stalled steps are summed over the parts when known (a
                 killed process leaves no count: the status says which steps it covers,
                 table.csv: stalled_cover). After a complete run, checkpoint.h5 is deleted.
  Ctrl-C / SIGTERM  the script starts no new run; the running fsiopt processes get the
                 signal (Ctrl-C: from the terminal; SIGTERM to the script: forwarded), write
                 a checkpoint of their last step and stop; the script exits 130 without a
                 table. A second Ctrl-C kills them (the last K-step checkpoint stays).

Outputs under out/turek-hron/ (--out): table.md (preamble: what was run and when; the value
table; the change table; failures) and table.csv (one row per run: the raw final, mean,
amplitude and frequency of every quantity, dofs, steps, iterations, times, status, error,
run directory and command). Runs go to <out>/runs/<case>-n<N>[-dts<S>][-T<T>][-x<hash of
--extra>]/ (--runs-dir) with summary.json, probes.csv (the time series), history.csv
(coupled runs; of the last part only when resumed), stdout.log, stderr.log (the last
process's), attempts.json (the parts) and cmd.txt (the command line, written after a
successful run; while a run is unfinished: cmd.pending, checkpoint.h5, current_attempt.json); a complete run whose command line is the one we would run now, and which is
newer than its meshes, is re-used (--force: run again). A run or mesh that fails is reported
in the table with its error, the others go on, and the script exits non-zero at the end.

Examples (from anywhere; build first: make all):
  scripts/turek_hron_table.py --cases csm1,csm2,cfd1 --levels 1,2
  scripts/turek_hron_table.py --cases csm3,fsi1 --levels 1 --t-final 0.1 --out /tmp/th
  scripts/turek_hron_table.py --cases cfd1,cfd2 --levels 1,2,3 --jobs 2
  scripts/turek_hron_table.py --cases fsi2 --levels 1 --checkpoint-every 250   # again after a stop: resumes
  scripts/turek_hron_table.py                  # all nine cases on n = 1, 2: hours"""
import argparse, datetime, math, os, re, shlex, signal, subprocess, sys, tempfile, time
from concurrent.futures import ThreadPoolExecutor, as_completed

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, extra_tag, fmt_num, ints, md_escape, number, rel, say   # noqa: E402
from fsiopt_resume import PENDING   # noqa: E402  (an unfinished run's command line)
from turek_hron_rows import (CASES, DASH, MESH_OPTION, PARTS, QUANTITIES, STATS,  # noqa: E402,F401  (the table's rows)
    change, change_cell, duration, g, gn_cell, result_row, status_cell, unknowns_cell, value_cell, wall_cell, window_cell)

FSIOPT = fr.FSIOPT
OPTIONS_FILE = "options/turek-hron/%s.yaml"   # of a case
GEO = {"fluid": "meshes/turek-hron-fluid.geo", "flag": "meshes/turek-hron-flag.geo"}
GEO_INCLUDES = ["meshes/turek-hron.geoinc"]
# the benchmark's cases: which parts they have, and whether they are periodic (as the scene's cases[])


# ---------------------------------------------------------------------------- the cases' own values
class DefaultsError(Exception):
    pass


def binary_defaults(fsiopt, options):
    """{'dt', 't_final', 'window'} that a run of fsiopt with these options would use: its
    -help (which runs no step) prints them as `-dt <now : default>`. Raises DefaultsError."""
    with tempfile.TemporaryDirectory(prefix="turek-hron-help-") as tmp:
        p = fr.run_fsiopt(options + ["-help", "-output_dir", tmp], fsiopt=fsiopt, timeout=300)
        if p.returncode is None:   # it could not start, or timed out
            raise DefaultsError("%s -help: %s" % (rel(fsiopt), "no end after 300 s" if p.timed_out else
                                                  p.stderr.split(": ", 1)[-1]))
    found = {}
    for key, opt in (("dt", "dt"), ("t_final", "t_final"), ("window", "quantities_window")):
        m = re.search(r"^\s*-%s <(?:now )?([-+0-9.eE]+)" % opt, p.stdout, re.M)
        if m:
            found[key] = float(m.group(1))
    if p.returncode or len(found) < 3:
        msg, _ = fr.error_line(p.stderr, p.returncode)
        raise DefaultsError("%s: %s" % (shlex.join([rel(fsiopt)] + options + ["-help"]),
                                        msg if p.returncode else "no -dt/-t_final/-quantities_window in its -help"))
    return found


# ---------------------------------------------------------------------------- meshes
def mesh_path(part, level, mesh_dir):
    return os.path.join(mesh_dir, "turek-hron-%s-n%d.msh" % (part, level))


def ensure_mesh(part, level, mesh_dir, gmsh="gmsh"):
    """Path of the part's mesh of level n (fsiopt_runs.ensure_gmsh_mesh). Raises MeshError."""
    return fr.ensure_gmsh_mesh(GEO[part], GEO_INCLUDES, mesh_path(part, level, mesh_dir), level, 2,
                               "%s n=%d" % (part, level), gmsh=gmsh, verbosity=2)


# ---------------------------------------------------------------------------- runs
def outputs_of(kind):
    """The files of a complete run: coupled runs also write history.csv."""
    return ("summary.json", "probes.csv") + (("history.csv",) if kind == "fsi" else ())


def case_run(case, level, meshes, dt, t_final, extra, dt_scale, checkpoint_every=0):
    """The fsiopt run of a case on level n; dt, t_final: None for the case's own;
    checkpoint_every: -checkpoint_every K (0: none), a run option (not in cmd.txt)."""
    kind = CASES[case][0]
    options = ["-options_file", OPTIONS_FILE % case]
    for part in PARTS[kind]:
        options += [MESH_OPTION[part], rel(meshes[part])]
    name = "%s-n%d" % (case, level)
    if dt is not None:
        options += ["-dt", fmt_num(dt)]
        name += "-dts%s" % fmt_num(dt_scale)
    if t_final is not None:
        options += ["-t_final", fmt_num(t_final)]
        name += "-T%s" % fmt_num(t_final)
    options += extra
    name += extra_tag(extra)
    run_options = ["-checkpoint_every", str(checkpoint_every)] if checkpoint_every else []
    return fr.Variant(name, "%s n = %d" % (case, level), options, outputs=outputs_of(kind), run_options=run_options,
                      resumable=True, case=case, level=level, meshes=[meshes[p] for p in PARTS[kind]])


def failed_run(case, level, error):
    v = fr.Variant("%s-n%d" % (case, level), "%s n = %d" % (case, level), [], case=case, level=level, meshes=[])
    v.status, v.error = "failed", error
    return v


def forget_if_older(v, runs_dir):
    """A run older than a mesh it reads is run again: its cmd.txt goes; an unfinished run
    started before a mesh was made is not resumed: its cmd.pending goes (and with it the
    use of its checkpoint)."""
    for name, what in (("cmd.txt", "will run again"), (PENDING, "its checkpoint will not be used")):
        path = os.path.join(runs_dir, v.name, name)
        try:
            t = os.path.getmtime(path)
        except OSError:
            continue
        if any(os.path.getmtime(f) > t for f in v.params["meshes"] if os.path.isfile(f)):
            say("  %-28s older than its meshes: %s" % (v.name, what))
            os.remove(path)


def run_runs(runs, fsiopt, runs_dir, jobs=1, force=False, retries=2):
    """Runs (or re-uses) the runs not failed already, jobs at a time, with a progress line
    after each."""
    todo = [v for v in runs if v.status == "pending"]
    for v in todo:
        forget_if_older(v, runs_dir)
    env = fr.fsiopt_env(jobs=jobs)
    say("%d run(s) in %s, %d at a time" % (len(todo), rel(runs_dir), jobs))
    t0, done = time.time(), 0
    pool = ThreadPoolExecutor(max_workers=max(1, jobs))
    try:
        futures = [pool.submit(fr.run_variant, v, fsiopt, runs_dir, force, retries, env=env) for v in todo]
        for fut in as_completed(futures):
            v = fut.result()
            done += 1
            what = {"ok": "done in %s", "reused": "re-used (it ran in %s)"}.get(v.status, "FAILED after %s")
            say("  [%d/%d] %s %s; %s elapsed in all" % (done, len(todo), v.name, what % (duration(v.elapsed_s) or "?"),
                                                      duration(time.time() - t0)))
    except KeyboardInterrupt:   # Ctrl-C, or SIGTERM (on_sigterm)
        fr.stop_runs()
        say("turek_hron_table: interrupted: no new run; waiting for the running fsiopt process(es) to write a "
            "checkpoint of their last step (Ctrl-C again: kill them)", err=True)
        try:
            pool.shutdown(wait=True, cancel_futures=True)
        except KeyboardInterrupt:
            fr.stop_runs(signal.SIGKILL)
            pool.shutdown(wait=True, cancel_futures=True)
        say("turek_hron_table: interrupted; the same command resumes the unfinished runs from their checkpoints",
            err=True)
        sys.exit(130)
    pool.shutdown()
    return runs


def on_sigterm(signum, frame):
    """SIGTERM to the script: forwarded to the running fsiopt processes (each stops at a
    checkpoint of its last step), then handled as a Ctrl-C."""
    fr.stop_runs(signum)
    raise KeyboardInterrupt


def git_state():
    """'commit abc1234' (+ ', with uncommitted changes'), or '' outside a git checkout."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True)
    except OSError:
        return ""
    if head.returncode:
        return ""
    return "commit %s%s" % (head.stdout.strip(), ", with uncommitted changes" if dirty.stdout.strip() else "")


def case_defaults(cases, args, meshes, extra):
    """{case: {'dt', 't_final', 'window'}}: the defaults the runs would use, for --dt-scale,
    asked of the binary (its -help), which is what runs; sys.exit when it cannot answer."""
    found = {}
    for c in cases:
        parts = PARTS[CASES[c][0]]
        level = next((n for n in args.levels if all((p, n) in meshes for p in parts)), None)
        if level is None:
            sys.exit("turek_hron_table: --dt-scale needs %s's default dt, and none of its meshes exists" % c)
        options = ["-options_file", OPTIONS_FILE % c]
        for p in parts:
            options += [MESH_OPTION[p], rel(meshes[p, level])]
        try:
            found[c] = binary_defaults(args.fsiopt, options + extra)
        except DefaultsError as e:
            sys.exit("turek_hron_table: --dt-scale needs %s's default dt: %s" % (c, e))
    return found


# ---------------------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated cases (default all nine: %s)"
                                                             % ",".join(CASES))
    ap.add_argument("--levels", type=ints, default=[1, 2], help="mesh refinement levels n (default 1,2)")
    ap.add_argument("--dt-scale", type=float, default=1.0, help="run with the case's default dt x S (default 1: "
                                                                "the scene's dt, -dt not passed)")
    ap.add_argument("--t-final", type=float, default=None, help="-t_final T for every case (default: the case's)")
    ap.add_argument("--extra", default="", help='options passed to every run, e.g. --extra="-coupling_tol 1e-8"')
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--gmsh", default="gmsh", help="gmsh binary (default gmsh)")
    ap.add_argument("--mesh-dir", default=os.path.join(ROOT, "out", "meshes"), help="where the meshes go "
                                                                                    "(default out/meshes)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "turek-hron"), help="output directory "
                                                                                   "(default out/turek-hron)")
    ap.add_argument("--runs-dir", default=None, help="where the runs go (default <out>/runs)")
    ap.add_argument("--fsiopt", default=FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=2, help="retries of a run that dies without an fsiopt error "
                                                           "(default 2; a retry resumes from the checkpoint)")
    ap.add_argument("--checkpoint-every", type=int, default=500, metavar="K",
                    help="-checkpoint_every K for the periodic cases (default 500; 0: off); not part of the "
                         "recorded command line, so it never makes a complete run stale")
    args = ap.parse_args()
    signal.signal(signal.SIGTERM, on_sigterm)
    cases = [c.strip().lower() for c in args.cases.split(",") if c.strip()]
    unknown = [c for c in cases if c not in CASES]
    if not cases or unknown:
        ap.error("--cases: %s; expected some of %s" % ("unknown " + ", ".join(unknown) if unknown else "empty",
                                                         ",".join(CASES)))
    if len(set(cases)) != len(cases):
        ap.error("--cases: a case is listed twice")
    if not args.levels or any(n < 1 for n in args.levels):
        ap.error("--levels: positive integers expected")
    if len(set(args.levels)) != len(args.levels):
        ap.error("--levels: a level is listed twice")
    if not args.dt_scale > 0 or not math.isfinite(args.dt_scale):
        ap.error("--dt-scale: positive expected")
    if args.t_final is not None and not args.t_final > 0:
        ap.error("--t-final: positive expected")
    if args.jobs < 1:
        ap.error("--jobs: at least 1")
    try:
        extra = shlex.split(args.extra)
    except ValueError as e:
        ap.error("--extra: %s" % e)
    if args.dt_scale != 1 and "-dt" in extra:
        ap.error("--dt-scale and -dt in --extra: give one of them")
    if args.checkpoint_every < 0:
        ap.error("--checkpoint-every: 0 or more expected")
    own = [o for o in ("-checkpoint_every", "-checkpoint_file", "-restart") if o in extra]
    if own:
        ap.error("--extra: %s: the script sets it (--checkpoint-every; resuming uses <run dir>/checkpoint.h5)"
                 % ", ".join(own))
    coupling = next((extra[i + 1] for i in range(len(extra) - 1) if extra[i] == "-coupling"), "opt")
    args.out = os.path.abspath(args.out)
    args.mesh_dir = os.path.abspath(args.mesh_dir)
    args.runs_dir = os.path.abspath(args.runs_dir or os.path.join(args.out, "runs"))
    args.fsiopt = os.path.abspath(args.fsiopt)
    if not os.path.isfile(args.fsiopt):
        say("turek_hron_table: %s not found (build first: make all)" % rel(args.fsiopt), err=True)

    say("meshes in %s" % rel(args.mesh_dir))
    mesh_errors = {}
    meshes = {}
    for n in args.levels:
        for part in ("fluid", "flag"):
            if any(part in PARTS[CASES[c][0]] for c in cases):
                try:
                    meshes[part, n] = ensure_mesh(part, n, args.mesh_dir, args.gmsh)
                except fr.MeshError as e:
                    say("  mesh %s n=%d FAILED: %s" % (part, n, e), err=True)
                    mesh_errors[part, n] = str(e)

    defaults = {}
    if args.dt_scale != 1:
        defaults = case_defaults(cases, args, meshes, extra)

    runs = []
    if coupling != "opt" and args.checkpoint_every and any(CASES[c] == ("fsi", True) for c in cases):
        say("turek_hron_table: note: -coupling %s in --extra: the fsi runs get no checkpoints (fsiopt checkpoints "
            "-coupling opt only)" % coupling, err=True)
    say("plan:")
    for c in cases:
        kind = CASES[c][0]
        dt = defaults[c]["dt"] * args.dt_scale if args.dt_scale != 1 else None
        for n in args.levels:
            errs = [mesh_errors[p, n] for p in PARTS[kind] if (p, n) in mesh_errors]
            if errs:
                runs.append(failed_run(c, n, "mesh: " + "; ".join(errs)))
                say("  %-28s not run: mesh failed" % runs[-1].name)
                continue
            every = args.checkpoint_every if CASES[c][1] and (kind != "fsi" or coupling == "opt") else 0
            v = case_run(c, n, {p: meshes[p, n] for p in PARTS[kind]}, dt, args.t_final, extra, args.dt_scale, every)
            runs.append(v)
            if c in defaults:
                tf = args.t_final if args.t_final is not None else defaults[c]["t_final"]
                say("  %-28s dt %s, T %s: %d step(s)" % (v.name, fmt_num(dt), fmt_num(tf),
                                                       int(math.floor(tf / dt + 0.5))))
            else:
                say("  %s" % v.name)
    run_runs(runs, args.fsiopt, args.runs_dir, args.jobs, args.force, args.retries)

    rows = [result_row(v) for v in runs]
    fields = ["case", "level", "status", "error", "kind", "periodic", "unknowns", "fluid_dofs", "structure_dofs",
              "dt", "steps", "t_start", "t_final", "window_s"] + \
             ["%s_%s" % (k, st) for k, _, _, _ in QUANTITIES for st in STATS] + \
             ["avg_coupling_iterations", "coupling_iterations", "work_factor", "max_interface_jump", "stalled_steps",
              "converged", "wall_time_s", "elapsed_s", "parts", "its_cover", "stalled_cover", "last_part_steps",
              "wall_time_note",
              "run_date", "meshes", "run_dir", "command"]
    os.makedirs(args.out, exist_ok=True)
    csv_path, md_path = os.path.join(args.out, "table.csv"), os.path.join(args.out, "table.md")
    fr.write_csv(csv_path, rows, fields, float_format="%.10g")

    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    changes = []
    if args.dt_scale != 1:
        changes.append("dt = the case's default x %s" % fmt_num(args.dt_scale))
    if args.t_final is not None:
        changes.append("T = %s s for every case" % fmt_num(args.t_final))
    if extra:
        changes.append("extra options `%s`" % " ".join(extra))
    state = git_state()
    md = ["# Turek-Hron benchmarks: our values over mesh refinements", "",
          "Written %s by `scripts/turek_hron_table.py`%s. Binary `%s`. Case `-options_file %s`, "
          "cases %s, "
          "levels n = %s; %s. Meshes `%s/turek-hron-{fluid,flag}-n<n>.msh` (`-setnumber n <n>` of "
          "`meshes/turek-hron-{fluid,flag}.geo`; every mesh size halves from n to n + 1). Runs in `%s`, "
          "each with its exact command line in `cmd.txt`, its time series in `probes.csv`." % (
              now, " (source tree at %s)" % state if state else "", rel(args.fsiopt), OPTIONS_FILE % "CASE", ", ".join(cases),
              ", ".join(str(n) for n in args.levels),
              "; ".join(changes) if changes else "dt, T and window: each case's own",
              rel(args.mesh_dir), rel(args.runs_dir)), "",
          "The values are ours, as measured; no reference values are given here. SI units: displacement of the "
          "flag's tip A = (0.6, 0.2) in m, force of the fluid on cylinder and flag per unit depth in N/m. Steady "
          "cases (csm1, csm2, cfd1, cfd2, fsi1) and runs with window 0: the final value. Periodic cases (csm3, "
          "cfd3, fsi2, fsi3): mean ± amplitude [frequency] over the last `window` seconds of the run (%s Hz: "
          "no period found in the window); window*: the window covers the whole run (T too short for it), so "
          "these are not the periodic state's. %s: does not apply. GN its/step: Gauss-Newton "
          "iterations per step of the coupled cases. Wall time: fsiopt's own (summary.json). A run resumed from "
          "its checkpoint (N parts): wall time summed over the parts, including the steps a killed part ran past "
          "its last checkpoint (≈: a part's time estimated from its files' times); GN its/step over all parts "
          "(\"(steps A-B)\": the last part's only, an earlier part's count unknown). Re-used runs keep "
          "their own dates (table.csv: run_date)." % (DASH, DASH), "",
          "| case | n | unknowns | dt [s] | T [s] | window [s] | " +
          " | ".join(h for _, _, h, _ in QUANTITIES) + " | GN its/step | wall time | status |",
          "|" + "---|" * (7 + len(QUANTITIES) + 2)]
    for v, row in zip(runs, rows):
        ok = v.ok
        md.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            row["case"], row["level"], unknowns_cell(row), g(number(row["dt"]), "%.4g") if ok else "",
            g(number(row["t_final"]), "%.4g") if ok else "", window_cell(row),
            " | ".join(value_cell(row, k) for k, _, _, _ in QUANTITIES),
            (gn_cell(row) if row["kind"] == "fsi" else DASH) if ok else "",
            wall_cell(row), status_cell(v, row)))

    md += ["", "## Change from the previous level", "",
           "Relative change (%) of each value above from the same case's previous level that ran "
           "(periodic: of mean, amplitude and frequency).", "",
           "| case | levels | " + " | ".join(h for _, _, h, _ in QUANTITIES) + " |",
           "|" + "---|" * (2 + len(QUANTITIES))]
    n_changes = 0
    for c in cases:
        prev = None
        for row in sorted((r for r in rows if r["case"] == c), key=lambda r: r["level"]):
            if row["status"] == "failed":
                continue
            if prev is not None:
                md.append("| %s | %d → %d | %s |" % (c, prev["level"], row["level"],
                                                      " | ".join(change_cell(row, prev, k) for k, _, _, _ in QUANTITIES)))
                n_changes += 1
            prev = row
    if not n_changes:
        md.append("| (no case ran on two levels) |" + " |" * (1 + len(QUANTITIES)))
    fr.finish_report(md, md_path, [csv_path, md_path],
                     [("%s n = %d" % (v.params["case"], v.params["level"]), v) for v in runs if not v.ok],
                     len(runs), "turek_hron_table", "run(s)", dir_quote="`")


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit(130)
