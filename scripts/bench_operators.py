#!/usr/bin/env python3
"""What the finite-element operators cost on each backend: per case, a few time
steps of fsiopt with -log_view on -fem_backend petsc and then on -fem_backend ceed, back to
back, and from each -log_view the calls and seconds of the fluid's and the structure's
residuals and Jacobians in the Fluid and Structure stages: PETSc's DMPlex integration
(events DMPlexResidualFE, DMPlexJacobianFE) against libCEED's whole operator (FluidResidual,
FluidJacobian, StructResidual, StructJacobian: the volume terms, PETSc's boundary terms,
loads and the local-to-global sum or COO insertion), ms per call, us per unknown and call,
and the ratio petsc / ceed; also libCEED's matrix-free Jacobian product (FluidMatFreeMult):
the libCEED runs refine each LU solve by one Richardson step with it. Cases: channel2d refine 0-2, tube3d levels 1-2, turek-hron fsi3
levels 1-2 (from rest), --cases to choose; --steps K time steps each (default 5). Runs go one
after the other (never two at once: they are timed).

  /usr/bin/python3 scripts/bench_operators.py [--cases channel2d-r0,tube3d-n1] [--steps 5]

Outputs: out/bench-operators/operators.{csv,md}; the runs in
out/bench-operators/runs/<case>-<backend>/ (re-used while their command line is unchanged;
--force to time afresh). scripts/bench_backends.py times whole runs on both backends."""
import argparse, os, re, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402
import tube3d_table as tube  # noqa: E402
import turek_hron_table as turek  # noqa: E402

OUT = os.path.join(fr.ROOT, "out", "bench-operators")
BACKENDS = ("petsc", "ceed")
# (row, stage, unknowns, PETSc's event, libCEED's event)
OPERATORS = (("fluid residual", "Fluid", "fluid_dofs", "DMPlexResidualFE", "FluidResidual"),
             ("fluid Jacobian", "Fluid", "fluid_dofs", "DMPlexJacobianFE", "FluidJacobian"),
             ("structure residual", "Structure", "structure_dofs", "DMPlexResidualFE", "StructResidual"),
             ("structure Jacobian", "Structure", "structure_dofs", "DMPlexJacobianFE", "StructJacobian"))
EVENTS = {e for op in OPERATORS for e in op[3:]} | {"FluidMatFreeMult"}
# the same systems solved (one step of iterative refinement on the LU: a Richardson step with
# the matrix-free product), the matrix-free products timed; the coupling's inner method set to
# cgls (with a Krylov fluid, -coupling_inner would default to gmres)
MATFREE = ["-fluid_matfree", "-fluid_ksp_type", "richardson", "-fluid_ksp_max_it", "2", "-fluid_ksp_norm_type", "none",
           "-coupling_inner", "cgls"]
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
        dt = 1e-3   # fsi3's dt (options/turek-hron/fsi3.yaml)
        return ["-options_file", "options/turek-hron/fsi3.yaml", "-t_final", fr.fmt_num(steps * dt), "-fluid_dm_plex_filename", fr.rel(fluid),
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


def per_call(events, stage, event):
    """(calls, ms per call) of an event in a stage, or None"""
    count, seconds = events.get(stage, {}).get(event, (0, 0.0))
    return (count, 1e3 * seconds / count) if count else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--bin", default=fr.FSIOPT)
    ap.add_argument("--force", action="store_true")
    args = ap.parse_args()
    cases = [c for c in args.cases.split(",") if c]
    mesh_dir = os.path.join(fr.ROOT, "out", "meshes")
    runs = {}
    for case in cases:
        for backend in BACKENDS:
            options = case_options(case, args.steps, mesh_dir) + ["-fem_backend", backend, "-log_view"]
            if backend == "ceed":  # GMRES on the matrix-free Jacobian: its products are timed too
                options += MATFREE
            runs[case, backend] = fr.Variant("%s-%s" % (case, backend), case, options,
                                             outputs=fr.OUTPUTS + ("stdout.log",))
    fr.run_all(list(runs.values()), args.bin, os.path.join(OUT, "runs"), jobs=1, force=args.force)
    rows, md = [], ["# Finite-element operators on both backends (-fem_backend petsc, ceed)", "",
                    "`%s`, one run at a time, %d steps each; ms per call, and us per unknown and call." % (
                        " ".join(["/usr/bin/python3", "scripts/bench_operators.py"] + sys.argv[1:]), args.steps),
                    "", "| case | unknowns | operator | calls petsc, ceed | petsc ms | ceed ms | petsc us/unknown | "
                    "ceed us/unknown | ratio petsc / ceed |", "|" + "---|" * 9]
    failed = []
    for case in cases:
        pair = [runs[case, b] for b in BACKENDS]
        for r in pair:
            if not r.summary:
                failed.append((r.name, r))
        if any(not r.summary for r in pair):
            continue
        events = {b: parse_events(open(os.path.join(runs[case, b].run_dir, "stdout.log")).read()) for b in BACKENDS}
        summary = pair[0].summary
        for name, stage, unknowns_key, petsc_event, ceed_event in OPERATORS + (
                ("fluid Jacobian product (matrix-free)", "Fluid", "fluid_dofs", None, "FluidMatFreeMult"),):
            n = summary[unknowns_key]
            p = per_call(events["petsc"], stage, petsc_event) if petsc_event else None
            c = per_call(events["ceed"], stage, ceed_event)
            if not p and not c:
                continue
            nan = float("nan")
            row = {"case": case, "unknowns": n, "operator": name, "petsc_calls": p[0] if p else 0,
                   "ceed_calls": c[0] if c else 0, "petsc_ms": p[1] if p else nan, "ceed_ms": c[1] if c else nan}
            row["petsc_us_per_unknown"] = 1e3 * row["petsc_ms"] / n
            row["ceed_us_per_unknown"] = 1e3 * row["ceed_ms"] / n
            row["ratio"] = row["petsc_ms"] / row["ceed_ms"]
            rows.append(row)
            md.append("| %s | %d | %s | %d, %d | %s | %s | %s | %s | %s |" % (
                case, n, name, row["petsc_calls"], row["ceed_calls"], num(row["petsc_ms"]), num(row["ceed_ms"]),
                num(row["petsc_us_per_unknown"]), num(row["ceed_us_per_unknown"]),
                "%.1f" % row["ratio"] if p and c else "-"))
    os.makedirs(OUT, exist_ok=True)
    csv_path, md_path = os.path.join(OUT, "operators.csv"), os.path.join(OUT, "operators.md")
    fr.write_csv(csv_path, rows, list(rows[0]) if rows else ["case"])
    fr.finish_report(md, md_path, [csv_path, md_path], failed, len(runs), "bench_operators", "runs")


if __name__ == "__main__":
    main()
