#!/usr/bin/env python3
"""Whole runs on both operator backends: per case, fsiopt with -fem_backend petsc
and then with -fem_backend ceed, back to back (never two runs at once: they are timed), and
the ratios of their wall times (petsc / ceed) and peak resident memory (ceed / petsc), with
the largest probe difference between them relative to each probe's largest value. Cases:
channel2d refine 1 for 200 steps, tube3d level 1 for 3 steps, turek-hron fsi3 level 1 for
50 steps from rest; --cases to choose, --repeat N to time each pair N times (the fastest
counts: the machine is shared).

  /usr/bin/python3 scripts/bench_backends.py [--cases channel2d-r1,tube3d-n1] [--repeat 1]

Outputs: out/bench-backends/backends.{csv,md} and the runs in out/bench-backends/runs/."""
import argparse, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402
from bench_operators import case_options  # noqa: E402

OUT = os.path.join(fr.ROOT, "out", "bench-backends")
CASES = {"channel2d-r1": 200, "tube3d-n1": 3, "turek-fsi3-n1": 50}
BACKENDS = ("petsc", "ceed")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--bin", default=fr.FSIOPT)
    args = ap.parse_args()
    cases = [c for c in args.cases.split(",") if c]
    for c in cases:
        if c not in CASES:
            raise SystemExit("bench_backends: --cases: unknown case %s (known: %s)" % (c, ", ".join(CASES)))
    if args.repeat < 1:
        raise SystemExit("bench_backends: --repeat: expected at least 1, got %d" % args.repeat)
    mesh_dir = os.path.join(fr.ROOT, "out", "meshes")
    progress = fr.StudyProgress(len(cases) * len(BACKENDS) * args.repeat)
    rows, failed = [], []
    md = ["# Whole runs on both operator backends (-fem_backend petsc, ceed)", "",
          "`%s`, one run at a time; the fastest of %d per backend." % (
              " ".join(["/usr/bin/python3", "scripts/bench_backends.py"] + sys.argv[1:]), args.repeat), "",
          "| case | steps | unknowns fluid / structure | petsc s | ceed s | speed-up | petsc MiB | ceed MiB | "
          "memory ratio | probes differ by | GN its / step petsc, ceed |", "|" + "---|" * 11]
    for case in cases:
        steps = CASES[case]
        options = case_options(case, steps, mesh_dir)
        best, probes, summaries = {}, {}, {}
        for rep in range(args.repeat):
            for backend in BACKENDS:
                out = os.path.join(OUT, "runs", "%s-%s" % (case, backend))
                progress.begin("%s %s (%d of %d)" % (case, backend, rep + 1, args.repeat))
                run = fr.run_fsiopt(options + ["-fem_backend", backend, "-quiet"], out_dir=out, fsiopt=args.bin,
                                    rusage=True)
                progress.end()
                if run.returncode != 0:
                    failed.append(("%s %s" % (case, backend), fr.error_line(run.err, run.returncode)))
                    continue
                summary = fr.read_summary(out)
                seconds = summary.get("wall_time_s", run.elapsed_s)
                if backend not in best or seconds < best[backend][0]:
                    best[backend] = (seconds, run.maxrss_mib)
                probes[backend] = list(zip(*fr.read_table(os.path.join(out, "probes.csv"))[1]))
                summaries[backend] = summary
        if len(best) < 2:
            continue
        (tp, mp), (tc, mc) = best["petsc"], best["ceed"]
        difference = fr.probes_difference(probes["ceed"], probes["petsc"])
        s = summaries["petsc"]
        row = {"case": case, "steps": steps, "fluid_dofs": s["fluid_dofs"], "structure_dofs": s["structure_dofs"],
               "petsc_s": tp, "ceed_s": tc, "speedup": tp / tc, "petsc_mib": mp, "ceed_mib": mc,
               "memory_ratio": mc / mp, "probes_difference": difference,
               "gn_per_step_petsc": s["avg_coupling_iterations"],
               "gn_per_step_ceed": summaries["ceed"]["avg_coupling_iterations"]}
        rows.append(row)
        md.append("| %s | %d | %d / %d | %.2f | %.2f | %.2f | %.0f | %.0f | %.2f | %.1e | %.2f, %.2f |" % (
            case, steps, row["fluid_dofs"], row["structure_dofs"], tp, tc, tp / tc, mp, mc, mc / mp, difference,
            row["gn_per_step_petsc"], row["gn_per_step_ceed"]))
    os.makedirs(OUT, exist_ok=True)
    csv_path, md_path = os.path.join(OUT, "backends.csv"), os.path.join(OUT, "backends.md")
    fr.write_csv(csv_path, rows, list(rows[0]) if rows else ["case"])
    with open(md_path, "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    for name, error in failed:
        print("bench_backends: %s failed: %s" % (name, error), file=sys.stderr)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
