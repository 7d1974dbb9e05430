#!/usr/bin/python3
"""Manufactured-solution convergence tables for the single-physics solvers.

Runs bin/fsiopt over refinements (space) and time steps (time) and writes
out/convergence/convergence.csv and out/convergence/convergence.md with observed rates.
Usage: scripts/convergence.py [--levels N]   (build first: make all)"""
import argparse, csv, json, math, os, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FSIOPT = os.path.join(ROOT, "bin", "fsiopt")

STUDIES = [
    ("fluid (Q2,Q1) space", ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time"], "refine", ["u_L2", "u_H1", "p_L2"]),
    ("fluid (P2,P1) space", ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time", "-fluid_dm_plex_filename", "meshes/square.msh"], "refine", ["u_L2", "u_H1", "p_L2"]),
    ("structure Q2 space", ["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001"], "refine", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("structure P2 space", ["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001", "-structure_dm_plex_filename", "meshes/wall.msh"], "refine", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("fluid backward Euler time", ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-refine", "2"], "dt", ["u_L2", "u_H1", "p_L2"]),
    ("structure first order time", ["-scene", "mms-structure", "-structure_time_order", "1", "-t_start", "0.5", "-t_final", "1", "-refine", "1"], "dt", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("structure midpoint time", ["-scene", "mms-structure", "-structure_time_order", "2", "-t_start", "0.5", "-t_final", "1", "-refine", "2"], "dt", ["eta_L2", "eta_H1", "etadot_L2"]),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--levels", type=int, default=4)
    args = ap.parse_args()
    outdir = os.path.join(ROOT, "out", "convergence")
    os.makedirs(outdir, exist_ok=True)
    rows, md = [], ["# Manufactured-solution convergence", ""]
    for name, base, knob, keys in STUDIES:
        md += ["## " + name, "", "| %s | %s |" % (knob, " | ".join("%s | rate" % k for k in keys)), "|" + "---|" * (1 + 2 * len(keys))]
        prev = None
        for level in range(args.levels):
            value = str(level) if knob == "refine" else "%g" % (0.1 / 2 ** level)
            with tempfile.TemporaryDirectory() as tmp:
                subprocess.run([FSIOPT] + base + ["-" + knob, value, "-output_dir", tmp], cwd=ROOT, check=True, capture_output=True)
                errors = json.load(open(os.path.join(tmp, "summary.json")))["errors"]
            cells = []
            for k in keys:
                rate = math.log2(prev[k] / errors[k]) if prev else float("nan")
                cells.append("%.3e | %s" % (errors[k], "" if prev is None else "%.2f" % rate))
                rows.append({"study": name, knob if knob == "dt" else "refine": value, "norm": k, "error": errors[k], "rate": rate})
            md.append("| %s | %s |" % (value, " | ".join(cells)))
            prev = errors
        md.append("")
    with open(os.path.join(outdir, "convergence.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["study", "refine", "dt", "norm", "error", "rate"])
        w.writeheader()
        w.writerows(rows)
    open(os.path.join(outdir, "convergence.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))
    print("written: out/convergence/convergence.csv, out/convergence/convergence.md")


if __name__ == "__main__":
    main()
