#!/usr/bin/env python3
"""Manufactured-solution convergence tables.

Runs bin/fsiopt over refinements (space), time steps (time) or both (space-time) and
writes out/convergence/convergence.csv and out/convergence/convergence.md with observed
rates. The single-physics studies check the solvers; the coupled ones reproduce the
seed's Tables 5.1-5.6 (mms-ns) and Fig 3.7 (mms-stokes).
Usage: scripts/convergence.py [--levels N] [--set single|coupled|all]   (build first: make all)"""
import argparse, csv, json, math, os, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import ROOT, StudyProgress, run_fsiopt  # noqa: E402  (the binary, its environment, the launch)

STUDIES = [
    ("fluid (Q2,Q1) space", ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time"], "refine", ["u_L2", "u_H1", "p_L2"]),
    ("fluid (P2,P1) space", ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time", "-fluid_dm_plex_filename", "meshes/square.msh"], "refine", ["u_L2", "u_H1", "p_L2"]),
    ("structure Q2 space", ["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001"], "refine", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("structure P2 space", ["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001", "-structure_dm_plex_filename", "meshes/wall.msh"], "refine", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("fluid backward Euler time", ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-refine", "2"], "dt", ["u_L2", "u_H1", "p_L2"]),
    ("structure first order time", ["-scene", "mms-structure", "-structure_time_order", "1", "-t_start", "0.5", "-t_final", "1", "-refine", "1"], "dt", ["eta_L2", "eta_H1", "etadot_L2"]),
    ("structure midpoint time", ["-scene", "mms-structure", "-structure_time_order", "2", "-t_start", "0.5", "-t_final", "1", "-refine", "2"], "dt", ["eta_L2", "eta_H1", "etadot_L2"]),
]

FSI_NORMS = ["u_L2", "u_H1", "p_L2", "eta_L2", "eta_H1", "etadot_L2"]
COUPLED = [
    ("mms-ns one step at t0 = 0.5 (Tables 5.1-5.2)", ["-options_file", "options/mms-ns.yaml", "-t_start", "0.5", "-t_final", "0.500001"], "refine", FSI_NORMS),
    ("mms-ns one step at t0 = 0.8 (Tables 5.3-5.4)", ["-options_file", "options/mms-ns.yaml", "-t_start", "0.8", "-t_final", "0.800001"], "refine", FSI_NORMS),
    ("mms-ns one step at t0 = 0.5, interface velocity (eta^n - eta^{n-1})/dt as in the seed", ["-options_file", "options/mms-ns.yaml", "-coupling_velocity", "difference"], "refine", FSI_NORMS),
    ("mms-ns space-time on [0.5, 1], dt = 0.1 h/h0 (Tables 5.5-5.6)", ["-options_file", "options/mms-ns.yaml", "-t_start", "0.5", "-t_final", "1", "-coupling_tol", "1e-10"], "both", FSI_NORMS),
    ("mms-stokes time steps on [0.5, 1], h = 1/16 (Fig 3.7)", ["-options_file", "options/mms-stokes.yaml", "-refine", "2"], "dt", FSI_NORMS),
]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--levels", type=int, default=4)
    ap.add_argument("--set", choices=["single", "coupled", "all"], default="all")
    args = ap.parse_args()
    studies = (STUDIES if args.set != "coupled" else []) + (COUPLED if args.set != "single" else [])
    outdir = os.path.join(ROOT, "out", "convergence")
    os.makedirs(outdir, exist_ok=True)
    rows, md = [], ["# Manufactured-solution convergence", ""]
    progress = StudyProgress(len(studies) * args.levels)
    for name, base, knob, keys in studies:
        coupled = any(name == c[0] for c in COUPLED)
        extra = ["GN its/step", "inner its/GN it", "factorizations fluid/structure", "wall s"] if coupled else []
        md += ["## " + name, "", "| %s | %s |" % (knob, " | ".join(["%s | rate" % k for k in keys] + extra)), "|" + "---|" * (1 + 2 * len(keys) + len(extra))]
        prev = None
        for level in range(args.levels):
            value = str(level) if knob == "refine" else "%g" % (0.1 / 2 ** level)
            knobs = {"refine": ["-refine", value], "dt": ["-dt", value],
                     "both": ["-refine", str(level), "-dt", "%g" % (0.1 / 2 ** level)]}[knob]
            progress.begin("%s, %s %s" % (name, knob, value))
            with tempfile.TemporaryDirectory() as tmp:
                run_fsiopt(base + knobs, out_dir=tmp, check=True)
                progress.end()
                summary = json.load(open(os.path.join(tmp, "summary.json")))
                errors = summary["errors"]
            cells = []
            for k in keys:
                rate = math.log2(prev[k] / errors[k]) if prev else float("nan")
                cells.append("%.3e | %s" % (errors[k], "" if prev is None else "%.2f" % rate))
                row = {"study": name, "norm": k, "error": errors[k], "rate": rate}
                row.update({"refine": knobs[1]} if knob != "dt" else {"dt": value})
                if knob == "both":
                    row["dt"] = knobs[3]
                rows.append(row)
            if coupled:
                its = summary["coupling_iterations"]
                cells += ["%.2f" % summary["avg_coupling_iterations"], "%.1f" % (summary["inner_iterations"] / max(its, 1)),
                          "%d/%d" % (summary["factorizations"]["fluid"], summary["factorizations"]["structure"]), "%.1f" % summary["wall_time_s"]]
            md.append("| %s | %s |" % (value if knob != "both" else "%s, dt %s" % (knobs[1], knobs[3]), " | ".join(cells)))
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
