#!/usr/bin/env python3
"""What the finite-element operators cost (issue 23): per case, a few time steps of fsiopt
with -log_view, and from it, per stage (Fluid, Structure, MeshMotion), the calls and
seconds of PETSc's DMPlex residual and Jacobian integration (events DMPlexResidualFE,
DMPlexJacobianFE), ms per call and us per unknown and call, their share of the run's wall
time, and the stage split. Cases: channel2d refine 0-2, tube3d levels 1-2, turek-hron fsi3
levels 1-2 (from rest), --cases to choose; --steps K time steps each (default 5). Runs go
one after the other (never two at once: they are timed).

  /usr/bin/python3 scripts/bench_operators.py [--cases channel2d-r0,tube3d-n1] [--steps 5]

Outputs: out/bench-operators/operators.{csv,md}; the runs in out/bench-operators/runs/<case>/
(re-used while their command line is unchanged; --force to time afresh). These are
PETSc's integration (-fem_backend petsc, passed explicitly); scripts/bench_backends.py
times whole runs on both backends."""
import argparse, os, re, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402
import tube3d_table as tube  # noqa: E402
import turek_hron_table as turek  # noqa: E402

OUT = os.path.join(fr.ROOT, "out", "bench-operators")
EVENTS = ("DMPlexResidualFE", "DMPlexJacobianFE")
STAGES = ("Setup", "Fluid", "Structure", "MeshMotion", "Sensitivity", "Adjoint")
CASES = ["channel2d-r0", "channel2d-r1", "channel2d-r2", "tube3d-n1", "tube3d-n2", "turek-fsi3-n1", "turek-fsi3-n2"]


def case_options(case, steps, mesh_dir):
    """fsiopt's options of a case, its steps of the scene's dt."""
    scene, _, level = case.rpartition("-")
    n = int(level[1:])
    if scene == "channel2d":
        return ["-options_file", "options/channel2d.yaml", "-refine", str(n), "-t_final", fr.fmt_num(steps * 1e-4)]
    if scene == "tube3d":
        meshes = tube.ensure_meshes(n, mesh_dir)
        return ["-options_file", "options/tube3d.yaml", "-t_final", fr.fmt_num(steps * 1e-4),
                "-fluid_dm_plex_filename", fr.rel(meshes["fluid"]), "-structure_dm_plex_filename", fr.rel(meshes["wall"])]
    if scene == "turek-fsi3":
        fluid, flag = turek.ensure_mesh("fluid", n, mesh_dir), turek.ensure_mesh("flag", n, mesh_dir)
        dt = 1e-3   # fsi3's default dt (src/scenes/turek_hron.c)
        return ["-options_file", "options/turek-hron.yaml", "-turek_case", "fsi3", "-t_final", fr.fmt_num(steps * dt), "-fluid_dm_plex_filename", fr.rel(fluid),
                "-structure_dm_plex_filename", fr.rel(flag)]
    raise SystemExit("bench_operators: --cases: unknown case %s (known: %s)" % (case, ", ".join(CASES)))


def parse_events(text):
    """{stage: {event: (count, seconds)}} from -log_view's per-stage event tables."""
    events, stage = {}, None
    for line in text.splitlines():
        m = re.match(r"--- Event Stage \d+: (.+)$", line)
        if m:
            stage = m.group(1).strip()
            continue
        m = re.match(r"(\S+)\s+(\d+)\s+[0-9.]+\s+([-+0-9.eE]+)\s", line)
        if stage and m and m.group(1) in EVENTS:
            count, seconds = events.setdefault(stage, {}).get(m.group(1), (0, 0.0))
            events[stage][m.group(1)] = (count + int(m.group(2)), seconds + float(m.group(3)))
    return events


def num(x):
    return "%.3g" % x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--bin", default=fr.FSIOPT)
    ap.add_argument("--force", action="store_true")
    args = ap.parse_args()
    cases = [c for c in args.cases.split(",") if c]
    mesh_dir = os.path.join(fr.ROOT, "out", "meshes")
    runs = []
    for case in cases:
        options = case_options(case, args.steps, mesh_dir) + ["-fem_backend", "petsc", "-log_view"]
        runs.append(fr.Variant(case, case, options, outputs=fr.OUTPUTS + ("stdout.log",)))
    fr.run_all(runs, args.bin, os.path.join(OUT, "runs"), jobs=1, force=args.force)
    rows, md = [], ["# Finite-element operators: PETSc's integration (issue 23 baseline)", "",
                    "`%s`, one run at a time, %d steps each." % (" ".join(["/usr/bin/python3", "scripts/bench_operators.py"] + sys.argv[1:]), args.steps),
                    "", "| case | unknowns fluid / structure | stage | residuals | ms per residual | us per unknown | "
                    "Jacobians | ms per Jacobian | us per unknown | share of the run |", "|" + "---|" * 10]
    failed = []
    for r in runs:
        if not r.summary:
            failed.append((r.name, r))
            continue
        text = open(os.path.join(r.run_dir, "stdout.log")).read()
        events, wall = parse_events(text), r.summary.get("wall_time_s") or float("nan")
        unknowns = {"Fluid": r.summary["fluid_dofs"], "Sensitivity": r.summary["fluid_dofs"],
                    "Adjoint": r.summary["fluid_dofs"], "Structure": r.summary["structure_dofs"]}
        for stage in STAGES:
            got = events.get(stage, {})
            if not got:
                continue
            nres, tres = got.get("DMPlexResidualFE", (0, 0.0))
            njac, tjac = got.get("DMPlexJacobianFE", (0, 0.0))
            n = unknowns.get(stage)
            row = {"case": r.name, "fluid_dofs": r.summary["fluid_dofs"], "structure_dofs": r.summary["structure_dofs"],
                   "stage": stage, "residuals": nres, "residual_ms": 1e3 * tres / nres if nres else float("nan"),
                   "residual_us_per_unknown": 1e6 * tres / nres / n if nres and n else float("nan"),
                   "jacobians": njac, "jacobian_ms": 1e3 * tjac / njac if njac else float("nan"),
                   "jacobian_us_per_unknown": 1e6 * tjac / njac / n if njac and n else float("nan"),
                   "share": (tres + tjac) / wall, "wall_s": wall}
            rows.append(row)
            md.append("| %s | %d / %d | %s | %d | %s | %s | %d | %s | %s | %.0f %% |" % (
                r.name, row["fluid_dofs"], row["structure_dofs"], stage, nres, num(row["residual_ms"]),
                num(row["residual_us_per_unknown"]), njac, num(row["jacobian_ms"]),
                num(row["jacobian_us_per_unknown"]), 100 * row["share"]))
    os.makedirs(OUT, exist_ok=True)
    csv_path, md_path = os.path.join(OUT, "operators.csv"), os.path.join(OUT, "operators.md")
    fr.write_csv(csv_path, rows, list(rows[0]) if rows else ["case"])
    fr.finish_report(md, md_path, [csv_path, md_path], failed, len(runs), "bench_operators", "runs")


if __name__ == "__main__":
    main()
