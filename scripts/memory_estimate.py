#!/usr/bin/python3
"""The memory estimate fsiopt makes before refining a mesh (src/common/memory_estimate.c)
beside the peak resident memory the same run then reaches, both from summary.json
(memory_gib: estimate and peak, summed over the ranks). One run at a time, a step or two
each: the estimate is meant to be an upper bound within a small factor, so that a -refine
a node cannot hold is refused (unless -force) and one it can is not.

usage: scripts/memory_estimate.py [--quick] [--json FILE]
Last line: 'N passed, M failed' for estimate/peak within [1, 2.5]; non-zero exit on a failure."""
import argparse, json, os, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import run_fsiopt  # noqa: E402
from cost_growth import SOLVERS  # noqa: E402

CHANNEL = ["-options_file", "options/channel2d.yaml", "-t_final", "0.0002"]
FSI3 = ["-options_file", "options/turek-hron/fsi3.yaml", "-dt", "0.0005", "-t_final", "0.001"]
TUBE = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0001"]
# every subproblem by a Krylov method: cost_growth.py's solver files (options/solvers/)
# cgls, the inner method docs/options.md's memory table was measured with (with an iterative fluid,
# -coupling_inner defaults to gmres)
ITERATIVE = SOLVERS["iterative"] + ["-coupling_inner", "cgls"]
TUBE_ITERATIVE = SOLVERS["iterative-ilu"] + ["-coupling_inner", "gmres"]
CASES = [
    ("channel2d", CHANNEL, 0, 1, True), ("channel2d", CHANNEL, 1, 1, True), ("channel2d", CHANNEL, 2, 1, False),
    ("channel2d", CHANNEL, 2, 2, False), ("turek-hron fsi3", FSI3, 0, 1, True), ("turek-hron fsi3", FSI3, 1, 1, False),
    ("tube3d", TUBE, 0, 1, True), ("tube3d", TUBE, 0, 2, False), ("tube3d", TUBE, 1, 1, False),
    ("channel2d iterative", CHANNEL + ITERATIVE, 1, 1, True), ("channel2d iterative", CHANNEL + ITERATIVE, 2, 1, False),
    ("tube3d iterative", TUBE + TUBE_ITERATIVE, 0, 1, True), ("tube3d iterative", TUBE + TUBE_ITERATIVE, 1, 1, False),
]
LOW, HIGH = 1.0, 2.5


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the small cases only")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args()
    work, rows, failed = tempfile.mkdtemp(prefix="fsiopt-memory-estimate-"), [], 0
    print("%-19s %6s %5s %10s %12s %10s %7s" % ("scene", "refine", "ranks", "unknowns", "estimate GiB", "peak GiB",
                                                "ratio"))
    for name, options, refine, ranks, quick in CASES:
        if args.quick and not quick:
            continue
        out = os.path.join(work, "%s-r%d-n%d" % (name.replace(" ", "-"), refine, ranks))
        run = run_fsiopt(options + ["-refine", str(refine)], nproc=ranks, out_dir=out)
        s = run.summary or {}
        if run.returncode != 0 or "memory_gib" not in s:
            print("%-19s %6d %5d  FAILED: %s" % (name, refine, ranks, (run.stderr or "").strip()[-200:]))
            failed += 1
            continue
        est, peak = s["memory_gib"]["estimate"], s["memory_gib"]["peak"]
        ratio = est / peak if peak > 0 else float("inf")
        ok = LOW <= ratio <= HIGH
        failed += not ok
        unknowns = s["fluid_dofs"] + s["structure_dofs"]
        rows.append(dict(scene=name, refine=refine, ranks=ranks, unknowns=unknowns, estimate_gib=est, peak_gib=peak,
                         ratio=ratio))
        print("%-19s %6d %5d %10d %12.3f %10.3f %7.2f%s" % (name, refine, ranks, unknowns, est, peak, ratio,
                                                            "" if ok else "  outside [%g, %g]" % (LOW, HIGH)),
              flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    print("%d passed, %d failed" % (sum(LOW <= r["ratio"] <= HIGH for r in rows), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
