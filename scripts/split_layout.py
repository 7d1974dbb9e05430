#!/usr/bin/env python3
"""Rank layouts of fsiopt on the 3D pressure-wave tube (scene tube3d), measured by what does not
depend on how many cores the machine has: iterations, the work and the messages of every rank.

A layout is P:K = MPI ranks : structure ranks (-structure_ranks K: the wall on the last K ranks,
the fluid on the other P - K; K = 0: both on all P ranks, one after the other). Every layout runs

  MPIEXEC -n P bin/fsiopt -options_file options/tube3d.yaml -t_final T
          -fluid_dm_plex_filename F -structure_dm_plex_filename W [-structure_ranks K]
          -log_view :RUN/logview.py:ascii_info_detail [--extra]
          -fluid_ksp_converged_reason -structure_ksp_converged_reason -mesh_ksp_converged_reason

(the same runs as scripts/strong_scaling.py, with PETSc's per-rank log instead of its summary),
one at a time, into <out>/runs/<run>/ (re-used while complete and with the same command line;
--force: run again). --iterative adds the four iterative solver files
(options/solvers/fluid-schur-gamg.yaml, fluid-velocity-ilu.yaml, structure-cg-ilu.yaml,
mesh-cg-gamg.yaml) in front of --extra.

Tabulated per layout (out/split-layout/split.md and split.csv, --out):
  - Gauss-Newton iterations per step, interface GMRES iterations per step (history.csv's
    inner_iterations), and the fluid, structure and mesh KSP iterations per solve (the
    converged_reason lines; a direct solver counts 1);
  - the probes' largest difference from the first layout, relative to the largest probe value,
    and relative to each probe's own largest value (a probe near zero makes the second large);
  - per -log_view stage: the total flop (sum over ranks), the flop balance max/min over the ranks
    that do work in the stage and max/mean over all P ranks (mean/max is the stage's parallel
    efficiency from balance alone), MPI messages and bytes (sends; PETSc counts a message at
    both ends, so its per-rank sums are halved), and the stage time, the largest over the ranks;
  - with a one-rank first layout, two predictions (not measurements):
    "model": a bulk-synchronous estimate of the time stepping on a cluster. Every stage costs
    the largest over the ranks of flop/R + messages*alpha + bytes/beta + reductions*lambda*log2 P,
    R the stage's own flop/s on the one-rank layout (--rate where it has none), alpha, beta,
    lambda from --latency (s, default 2e-6), --bandwidth (bytes/s per rank, default 5e9),
    --reduction (s, default 5e-6); the ranks of a stage wait for its slowest, so fluid and
    structure ranks overlap only where they share a stage (the sensitivity and adjoint
    products). "model vs P:0" is the shared layout's estimate over the layout's.
    "ideal vs P:0": the same ratio if every part scaled perfectly from the one-rank run (fluid
    and mesh on P - K ranks, the structure on K before the fluid, the products' fluid and
    structure solves at the same time, the rest on all P); the report names the best K/P under
    it (it uses times only). Without --iterative the model is left blank: the flop that -log_view
    reports for the direct solvers are not the work done (tube3d level 1, one rank: 7e10 flop/s).

Timings of runs with more ranks than cores are not speed-ups: this script tabulates them, but
the counts are the result.

Examples:
  scripts/split_layout.py --level 1 --layouts 1:0,4:0,4:1,4:2 --mpiexec "mpiexec --oversubscribe"
  scripts/split_layout.py --level 2 --iterative --layouts 1:0,4:0,4:1 --mpiexec "mpiexec --oversubscribe"
  scripts/split_layout.py --level 3 --iterative --mpiexec "srun --cpu-bind=cores" \\
      --layouts 1:0,32:0,32:4,32:8     # in a SLURM job; the one-rank layout calibrates the model"""
import argparse, csv, math, os, re, sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tube3d_table as T   # noqa: E402
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import rel, say   # noqa: E402
from strong_scaling import layouts_argument   # noqa: E402
from cost_growth import REASONS, SOLVERS   # noqa: E402

ITERATIVE = SOLVERS["iterative-ilu"]
STAGES = ("Setup", "Fluid", "Structure", "MeshMotion", "Sensitivity", "Adjoint", "Optimizer", "Main Stage")
STEP_STAGES = STAGES[1:]   # the time stepping: the model leaves the one-off Setup out
LOGVIEW = "logview.py"


def read_detail(path):
    """PETSc's ascii_info_detail log (Python assignments) -> {stage: [per-rank summary dict]},
    with the per-rank event records under {stage: {event: [...]}} in a second dict."""
    ns = {}
    with open(path) as f:
        exec(compile(f.read(), path, "exec"), {"__builtins__": {}}, ns)   # noqa: S102 (PETSc's own output)
    size = ns["size"]
    stages, events = {}, {}
    for st, table in ns["Stages"].items():
        summary = table.get("summary", {})
        stages[st] = [summary.get(i, {}) for i in range(size)]
        events[st] = {ev: [recs.get(i, {}) for i in range(size)] for ev, recs in table.items() if ev != "summary"}
    return size, stages, events


def stage_numbers(ranks, np):
    """totals and balance of one stage from its per-rank records"""
    flop = [r.get("flop", 0.0) for r in ranks]
    busy = [f for f in flop if f > 0]
    total = sum(flop)
    return {"flop": total,
            "flop_max_min": max(busy) / min(busy) if busy else "",
            "flop_max_mean": max(flop) / (total / np) if total else "",
            "busy_ranks": len(busy),
            "messages": sum(r.get("numMessages", 0.0) for r in ranks) / 2,
            "bytes": sum(r.get("messageLength", 0.0) for r in ranks) / 2,
            "reductions_max": max(r.get("numReductions", 0.0) for r in ranks),
            "time_max": max(r.get("time", 0.0) for r in ranks)}


def stage_rates(path):
    """{stage: flop/s} of the first layout's ranks (one rank: the stage's own speed, dense and
    sparse alike), the calibration of model_time; empty when unreadable"""
    try:
        size, stages, _ = read_detail(path)
    except (OSError, KeyError, SyntaxError):
        return {}
    rates = {}
    for st, ranks in stages.items():
        f, t = sum(r.get("flop", 0.0) for r in ranks), max(r.get("time", 0.0) for r in ranks)
        if f > 0 and t > 0:
            rates[st] = f / t * size   # per rank
    return rates


def model_time(st, ranks, np, a, rates):
    """the bulk-synchronous estimate of one stage (s): the slowest rank's flop at the stage's
    speed on the first layout (--rate where it has none), messages, bytes and reductions at
    the --latency, --bandwidth, --reduction given"""
    rate = rates.get(st, a.rate)
    red = a.reduction * max(1.0, math.log2(np)) if np > 1 else 0.0
    return max(r.get("flop", 0.0) / rate + r.get("numMessages", 0.0) / 2 * a.latency +
               r.get("messageLength", 0.0) / 2 / a.bandwidth + r.get("numReductions", 0.0) * red
               for r in ranks) if ranks else 0.0


def one_rank_parts(path):
    """(fluid, structure, fluid products, structure products, rest) s of a one-rank log's time
    stepping: Fluid + MeshMotion, Structure, FluidLinSolve and StructLinSolve in Sensitivity and
    Adjoint, and the other stages' remainder"""
    _, stages, _ = read_detail(path)
    t = {st: max(r.get("time", 0.0) for r in ranks) for st, ranks in stages.items()}
    fl, sl = product_solves(path)
    f, s = t.get("Fluid", 0.0) + t.get("MeshMotion", 0.0), t.get("Structure", 0.0)
    return f, s, fl, sl, sum(t.get(st, 0.0) for st in STEP_STAGES) - f - s - fl - sl


def ideal_ratio(parts, p, k):
    """the shared layout's time over the split's, every part scaling perfectly: the fluid on
    P - K ranks, the structure on K, the products' solves at the same time, the rest on all P"""
    if not k:
        return 1.0
    f, s, fl, sl, rest = parts
    return (f + s + fl + sl + rest) / p / (f / (p - k) + s / k + max(fl / (p - k), sl / k) + rest / p)


def product_solves(path):
    """(fluid s, structure s): FluidLinSolve and StructLinSolve in the Sensitivity and Adjoint
    stages of a one-rank log, what separate ranks can do at the same time"""
    _, _, events = read_detail(path)
    return tuple(sum(events.get(st, {}).get(ev, [{}])[0].get("time", 0.0) for st in ("Sensitivity", "Adjoint"))
                 for ev in ("FluidLinSolve", "StructLinSolve"))


def ksp_iterations(stdout):
    """{prefix: (solves, iterations per solve)} from the converged_reason lines"""
    its = {}
    for m in re.finditer(r"Linear (fluid|structure|mesh)_ solve (?:converged|did not converge) due to \S+ "
                         r"iterations (\d+)", stdout):
        its.setdefault(m.group(1), []).append(int(m.group(2)))
    return {k: (len(v), sum(v) / len(v)) for k, v in its.items()}


def read_probes(run_dir):
    with open(os.path.join(run_dir, "probes.csv")) as f:
        rows = list(csv.reader(f))[1:]
    return [[float(x) for x in row] for row in rows if row]


def inner_iterations(run_dir):
    with open(os.path.join(run_dir, "history.csv")) as f:
        return sum(int(float(row["inner_iterations"] or 0)) for row in csv.DictReader(f))


def row_of(r, layout, a, ref_probes, rates):
    p, k = layout
    row = {"layout": "%d:%d" % layout, "status": r.status, "error": r.error, "np": p, "k": k, "run_dir": rel(r.run_dir or ""),
           "command": r.cmdline}
    if not r.ok:
        return row, None
    s = r.summary
    steps = s.get("steps") or 1
    row.update({"steps": steps, "gn_per_step": s.get("avg_coupling_iterations", ""),
                "gmres_per_step": inner_iterations(r.run_dir) / steps, "wall_s": s.get("wall_time_s", "")})
    with open(os.path.join(r.run_dir, "stdout.log")) as f:
        its = ksp_iterations(f.read())
    for pre in ("fluid", "structure", "mesh"):
        n, per = its.get(pre, (0, ""))
        row[pre + "_solves"], row[pre + "_ksp_its"] = n, per
    probes = read_probes(r.run_dir)
    row["probes_rel_diff"] = fr.probes_difference(probes, ref_probes) if ref_probes else 0.0
    scale = max((abs(x) for p in ref_probes or probes for x in p[1:]), default=0.0) or 1.0
    row["probes_diff_of_largest"] = max((abs(x - y) for p, q in zip(probes, ref_probes or probes)
                                         for x, y in zip(p[1:], q[1:])), default=0.0) / scale
    size, stages, _ = read_detail(os.path.join(r.run_dir, LOGVIEW))
    model = 0.0
    for st in STAGES:
        n = stage_numbers(stages.get(st, []), size)
        for key, v in n.items():
            row["%s_%s" % (st.replace(" ", ""), key)] = v
        if st in STEP_STAGES:
            t = model_time(st, stages.get(st, []), size, a, rates)
            row["%s_model_s" % st.replace(" ", "")] = t
            model += t
    row["model_stepping_s"] = model
    row["messages"] = sum(row["%s_messages" % st.replace(" ", "")] for st in STAGES)
    row["bytes"] = sum(row["%s_bytes" % st.replace(" ", "")] for st in STAGES)
    return row, probes


def g(v, f="%.3g"):
    return T.fmt(v, f)


def report(rows, args, extra, dofs, overlap):
    S = [st.replace(" ", "") for st in STAGES]
    md = ["# fsiopt rank layouts: tube3d n = %d" % args.level, "",
          "`-options_file options/tube3d.yaml -t_final %s`%s; %s; launcher `%s -n P`. Layout P:K = ranks : structure "
          "ranks (K = 0: shared). The counts below do not depend on the machine; the times do (more ranks than "
          "cores: indicative only)." % (fr.fmt_num(args.t_final), ", `%s`" % " ".join(extra) if extra else "",
                                        "%d fluid + %d structure unknowns" % dofs if dofs else "", args.mpiexec), "",
          "| layout | GN its/step | GMRES its/step | fluid KSP its/solve (solves) | structure | mesh | probes vs %s: "
          "of the largest, per probe | messages | MiB | model s (stepping) | model vs P:0 | ideal vs P:0 | wall s | "
          "status |" % rows[0]["layout"], "|" + "---|" * 14]
    shared = {row["np"]: row.get("model_stepping_s") for row in rows if row["k"] == 0}
    for row in rows:
        vs = shared.get(row["np"])
        vs = vs / row["model_stepping_s"] if vs and row.get("model_stepping_s") else ""
        md.append("| %s | %s | %s | %s (%s) | %s (%s) | %s (%s) | %s, %s | %s | %s | %s | %s | %s | %s | %s |" % (
            row["layout"], g(row.get("gn_per_step")), g(row.get("gmres_per_step")),
            g(row.get("fluid_ksp_its")), row.get("fluid_solves", ""), g(row.get("structure_ksp_its")),
            row.get("structure_solves", ""), g(row.get("mesh_ksp_its")), row.get("mesh_solves", ""),
            g(row.get("probes_diff_of_largest"), "%.1e"), g(row.get("probes_rel_diff"), "%.1e"),
            g(row.get("messages"), "%.0f"), g(row["bytes"] / 2**20 if "bytes" in row else "", "%.1f"),
            g(row.get("model_stepping_s")), g(vs, "%.2f"), g(row.get("ideal_vs_shared", ""), "%.2f"),
            g(row.get("wall_s")), row["status"] if row["status"] != "failed" else "failed: " + row["error"][:120]))
    md += ["", "## Per stage", "",
           "flop: total over the ranks; max/min over the ranks with work in the stage (busy ranks in brackets); "
           "max/mean over all P ranks; messages and MiB sent; time: the largest over the ranks (s, indicative); "
           "model: the stage's bulk-synchronous estimate (s).", "",
           "| layout | stage | flop | max/min (busy) | max/mean | messages | MiB | time s | model s |", "|" + "---|" * 9]
    for row in rows:
        if row["status"] == "failed":
            continue
        for st, key in zip(STAGES, S):
            if not row.get(key + "_flop") and not row.get(key + "_messages"):
                continue
            md.append("| %s | %s | %s | %s (%s) | %s | %s | %s | %s | %s |" % (
                row["layout"], st, g(row[key + "_flop"]), g(row[key + "_flop_max_min"], "%.2f"),
                row[key + "_busy_ranks"], g(row[key + "_flop_max_mean"], "%.2f"), g(row[key + "_messages"], "%.0f"),
                g(row[key + "_bytes"] / 2**20, "%.2f"), g(row[key + "_time_max"]),
                g(row.get(key + "_model_s")) if args.iterative else ""))
    md += ["", "Model: every stage's flop at the speed the first layout (one rank) ran it at (%s flop/s where it has "
           "none), alpha = %g s per message, beta = %g bytes/s, lambda = %g s per reduction and log2 P; the sum over "
           "the time-stepping stages of the slowest rank's estimate. model vs P:0: the shared layout's estimate "
           "over this one's (> 1: the layout should be faster). A prediction from the counts, not a measurement; "
           "without --iterative the model is left blank (the direct solvers' logged flop are not the work done)." % (
               g(args.rate), args.latency, args.bandwidth, args.reduction)]
    if overlap:
        md += ["", "Overlap bound (first layout, one rank): the products' linearized solves take %.3g s in the fluid and "
               "%.3g s in the structure (FluidLinSolve, StructLinSolve in Sensitivity and Adjoint) of %.3g s of time "
               "stepping (the stages after Setup); separate ranks can do at most %.3g s of them at the same time." %
               overlap]
    if getattr(args, "best_split", None):
        best, ratio, parts = args.best_split
        md += ["", "ideal vs P:0: the shared layout's time over this layout's if every part scaled perfectly (one-rank "
               "parts: fluid and mesh %.3g s, structure %.3g s, the products' fluid and structure solves %.3g s and "
               "%.3g s, the rest %.3g s; the structure runs before the fluid, the products' solves at the same "
               "time). The best split under it puts K/P = %.3f of the ranks on the structure and runs at %.2f of the "
               "shared layout's speed: a split wins only where the shared layout's parallel efficiency falls below "
               "%.2f of the split's." % (parts + (best, ratio, ratio))]
    return md


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--level", type=int, default=1, help="mesh refinement level n (default 1)")
    ap.add_argument("--t-final", type=float, default=0.0003, help="end time (default 0.0003 = 3 steps)")
    ap.add_argument("--layouts", default="1:0,4:0,4:1,4:2", help='comma-separated P:K; the first is the probes\' '
                                                                  'reference (default "1:0,4:0,4:1,4:2")')
    ap.add_argument("--iterative", action="store_true", help="the four iterative solver files in front of --extra")
    T.add_study_args(ap, "split-layout", "-coupling_tol 1e-5")
    ap.add_argument("--bin", default=T.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    ap.add_argument("--retries", type=int, default=1, help="retries of a run that dies (default 1)")
    ap.add_argument("--rate", type=float, default=1e9, help="model: flop/s per rank of a stage the one-rank "
                                                             "layout has no speed for (default 1e9)")
    ap.add_argument("--latency", type=float, default=2e-6, help="model: s per message (default 2e-6)")
    ap.add_argument("--bandwidth", type=float, default=5e9, help="model: bytes/s per rank (default 5e9)")
    ap.add_argument("--reduction", type=float, default=5e-6, help="model: s per reduction and log2 P "
                                                                   "(default 5e-6)")
    args = ap.parse_args()
    layouts = layouts_argument(ap, args.layouts)
    launcher, extra = T.check_study_args(ap, args, "split_layout")
    extra = (ITERATIVE if args.iterative else []) + extra
    runs_dir = os.path.join(args.out, "runs")
    meshes = T.ensure_meshes(args.level, args.mesh_dir, args.gmsh)
    runs = []
    for p, k in layouts:
        r = T.tube3d_run(args.level, args.t_final, meshes, extra + REASONS, p, k, launcher)
        i = r.options.index("-log_view")
        r.options.insert(i + 1, ":%s:ascii_info_detail" % rel(os.path.join(runs_dir, r.name, LOGVIEW)))
        r.outputs = r.outputs + (LOGVIEW,)
        runs.append(r)
    T.run_runs(runs, args.bin, runs_dir, args.force, args.retries)
    rows, ref = [], None
    first = os.path.join(runs[0].run_dir or "", LOGVIEW)
    rates = stage_rates(first) if runs[0].ok and layouts[0][0] == 1 else {}
    for layout, r in zip(layouts, runs):
        try:
            row, probes = row_of(r, layout, args, ref, rates)
        except (OSError, KeyError, ValueError, SyntaxError) as e:
            r.status, r.error = "failed", "unreadable outputs: %s" % e
            row, probes = row_of(r, layout, args, ref, rates)
        if ref is None and probes:
            ref = probes
        rows.append(row)
    if not args.iterative:   # the direct solvers' flop counts are not work: no model
        for row in rows:
            for key in [k for k in row if k.endswith("model_s") or k == "model_stepping_s"]:
                del row[key]
    dofs = next(((r.summary["fluid_dofs"], r.summary["structure_dofs"]) for r in runs if r.ok), None)
    os.makedirs(args.out, exist_ok=True)
    overlap = None
    if rates:
        parts = one_rank_parts(first)
        for row in rows:
            row["ideal_vs_shared"] = ideal_ratio(parts, row["np"], row["k"])
        grid = [i / 1000 for i in range(1, 1000)]
        best = max(grid, key=lambda q: ideal_ratio(parts, 1.0, q))
        say("parts (fluid, structure, fluid products, structure products, rest) s: %s; best K/P %.3f: %.3f"
            % (", ".join("%.3g" % x for x in parts), best, ideal_ratio(parts, 1.0, best)))
        args.best_split = (best, ideal_ratio(parts, 1.0, best), parts)
        fl, sl = product_solves(first)
        stepping = sum(max(r.get("time", 0.0) for r in ranks) for st, ranks in read_detail(first)[1].items()
                       if st in STEP_STAGES)
        overlap = (fl, sl, stepping, min(fl, sl))
    fields = sorted({k for row in rows for k in row}, key=lambda k: (k in ("run_dir", "command"), k))
    fr.write_csv(os.path.join(args.out, "split.csv"), rows, fields)
    md = report(rows, args, extra, dofs, overlap)
    fr.finish_report(md, os.path.join(args.out, "split.md"), [os.path.join(args.out, "split" + e) for e in
                                                               (".csv", ".md")],
                     [(row["layout"], r) for row, r in zip(rows, runs) if not r.ok], len(runs), "split_layout",
                     "layout(s)")


if __name__ == "__main__":
    main()
