#!/usr/bin/python3
"""What -write_fields costs a run: the run without fields and with each field-writing variant,
side by side, the least wall time of R rounds each (the variants alternate within a round),
and each variant's time as a ratio to the run without fields.

usage: scripts/fields_cost.py [--rounds R] [--case OPTIONS_FILE] [--t-final T] [--interval K]

By default: options/channel2d.yaml to t = 0.02 (200 steps), fields every 10 steps, 3 rounds;
the variants are every node (the default), vertices only (-write_fields_nodes vertices) and
every node with all the derived fields of the case's sides. Prints one line per variant and
the fsiopt command of each."""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--case", default="options/channel2d.yaml")
    ap.add_argument("--t-final", default="0.02")
    ap.add_argument("--interval", default="10")
    a = ap.parse_args()
    base = [os.path.join(ROOT, "bin", "fsiopt"), "-options_file", a.case, "-t_final", a.t_final]
    fields = ["-write_fields", "-write_fields_interval", a.interval]
    variants = [("no fields", []), ("every node", fields), ("vertices only", fields + ["-write_fields_nodes", "vertices"]),
                ("every node + derived", fields + ["-write_fields_derived",
                                                   "vorticity,q_criterion,stress,von_mises,traction,normal_stress,"
                                                   "wall_shear_stress"])]
    best = {name: float("inf") for name, _ in variants}
    work = tempfile.mkdtemp(prefix="fields-cost-")
    try:
        for _ in range(a.rounds):
            for name, extra in variants:
                out = os.path.join(work, "run")
                shutil.rmtree(out, ignore_errors=True)
                start = time.perf_counter()
                p = subprocess.run(base + extra + ["-output_dir", out], cwd=ROOT, env=ENV, capture_output=True, text=True)
                elapsed = time.perf_counter() - start
                if p.returncode:
                    sys.exit("fields_cost: %s failed: %s" % (name, (p.stderr or p.stdout).strip()[-300:]))
                best[name] = min(best[name], elapsed)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for name, extra in variants:
        print("%-22s %7.3f s  %.3f x  (%s)" % (name, best[name], best[name] / best["no fields"],
                                             " ".join(["bin/fsiopt"] + base[1:] + extra)))


if __name__ == "__main__":
    main()
