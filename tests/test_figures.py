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


@test("fields figure: scripts/fields_figure.py draws, off-screen with VTK, one PNG per field of every grid of "
      "channel2d's fields.xdmf (fluid, structure and walls, derived fields included), each coloured over the "
      "field's range; a time outside the run's refused in one line")
def test_fields_figure():
    import numpy as np
    from matplotlib.image import imread
    script = os.path.join(ROOT, "scripts", "fields_figure.py")
    run_dir = os.path.join(WORK, "figure-fields")
    solve(CHANNEL + ["-t_final", "0.002", "-write_fields", "-write_fields_interval", "10", "-write_fields_derived",
                     "vorticity,q_criterion,stress,von_mises,wall_shear_stress,interface_traction"], out=run_dir)
    r = subprocess.run([script, run_dir, "--time", "0.001"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, "fields_figure: %s" % r.stderr.strip()[-300:]
    written = sorted(os.path.basename(p) for p in r.stdout.split())
    want = sorted(["fluid_%s.png" % f for f in ("velocity", "pressure", "mesh_velocity", "vorticity", "q_criterion")] +
                  ["structure_%s.png" % f for f in ("displacement", "velocity", "stress", "von_mises")] +
                  ["walls_%s.png" % f for f in ("wall_shear_stress", "interface_traction")])
    assert written == want, "wrote %s, expected %s" % (written, want)
    colours = {}
    for name in written:
        image = imread(os.path.join(run_dir, "figures", name))[:, :, :3]
        top = image[: int(image.shape[0] * 0.7)]   # the field, above the colour bar
        drawn = top[(top.max(axis=2) < 0.98)]       # not the white background
        colours[name] = len(np.unique(np.round(drawn * 255).astype(int), axis=0))
    few = {k: v for k, v in colours.items() if v < 8}
    assert not few, "figures with fewer than 8 colours where the field is drawn: %s" % few
    bad = subprocess.run([script, run_dir, "--time", "5"], capture_output=True, text=True, timeout=120)
    lines = [l for l in bad.stderr.splitlines() if l.strip() and "WARN" not in l]
    assert bad.returncode == 1 and len(lines) == 1 and "--time" in lines[0], "--time 5: %s %s" % (bad.returncode, lines)
    return "%d PNGs at t = 0.001, %d to %d colours each" % (len(written), min(colours.values()), max(colours.values()))
