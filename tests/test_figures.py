"""scripts/probes_figure.py: a figure of every scene's probes.csv, its columns labelled by
their headers (names, points, units), the values plotted those of the file."""
import csv
import os
import subprocess

from harness import CHANNEL, ROOT, WORK, fr, solve, test, turek

SCRIPT = os.path.join(ROOT, "scripts", "probes_figure.py")


@test("probes figure: for a manufactured scene (drag, lift), channel2d (interface displacements), Turek-Hron csm1 "
      "(the flag alone) and the rigid channel (integrals over face sets and regions) it plots every column of "
      "probes.csv under its header as written, the values those of the file")
def test_probes_figure():
    runs = {"mms-fluid": ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.7"],
            "channel2d": CHANNEL + ["-t_final", "0.001"],
            "csm1": turek("csm1"),
            "rigid-channel": ["-options_file", os.path.join(ROOT, "options", "examples", "rigid-channel.yaml")]}
    out = os.path.join(WORK, "figures")
    report = []
    for name, args in runs.items():
        run_dir = os.path.join(WORK, "figure-" + name)
        solve(args, out=run_dir)
        r = subprocess.run(["/usr/bin/python3", SCRIPT, run_dir, "--out", out], capture_output=True, text=True,
                           timeout=120, env=fr.fsiopt_env())
        assert r.returncode == 0, "%s: %s" % (name, r.stderr[-300:])
        base = os.path.join(out, "figure-%s-probes" % name)
        assert os.path.getsize(base + ".png") > 10000, "%s: no figure" % name
        probes = list(csv.reader(open(os.path.join(run_dir, "probes.csv"))))
        plotted = list(csv.reader(open(base + ".csv")))
        assert plotted[0][3:] == probes[0][1:], "%s: plotted %s, probes.csv has %s" % (name, plotted[0][3:], probes[0][1:])
        worst = max(abs(float(a) - float(b)) / max(abs(float(b)), 1e-300)
                    for pr, fr_ in zip(probes[1:], plotted[1:]) for a, b in zip(fr_[3:], pr[1:]))
        assert len(plotted) == len(probes) and worst <= 1e-10, "%s: plotted values off by %.1e" % (name, worst)
        report.append("%s %d columns" % (name, len(probes[0]) - 1))
    return "; ".join(report)
