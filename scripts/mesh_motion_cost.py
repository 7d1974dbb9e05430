#!/usr/bin/python3
"""What each fluid mesh motion costs and how far it keeps the cells from degenerating: the
same Turek-Hron run (default fsi2 level 1, 20 steps) with each -mesh_motion variant,
alternated --repeats times in one invocation. Reported per variant: the median wall time
(summary.json wall_time_s) and the median time of the MeshMotion log stage (-log_view: the
extensions, and for the incremental ones each step's assembly and factorization), both as
ratios to the first variant's, and the smallest area a cell corner kept against its
reference one (summary.json worst_corner_ratio; a step fails below 1e-3), or the time of
a step that failed because of it (the timings then cover a shorter run). With --restart
CHECKPOINT the runs start from a swung flag (a checkpoint of the same case), so that the
ratio says something; the probes of all variants are compared with the first's.

  /usr/bin/python3 scripts/mesh_motion_cost.py [--case fsi2] [--steps 20] [--repeats 3]
      [--restart CHECKPOINT] [--out out/mesh-motion-cost] [-- extra fsiopt options]"""
import argparse, json, os, re, statistics, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402

ROOT = fr.ROOT
VARIANTS = [  # the default of fsi2 and fsi3 first
    ("biharmonic, chi 2", ["-mesh_motion", "biharmonic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "0"]),
    ("harmonic, chi 1", ["-mesh_motion", "harmonic", "-mesh_motion_stiffening", "1", "-mesh_motion_incremental", "0"]),
    ("elastic by increments, chi 2", ["-mesh_motion", "elastic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "1"]),
    ("biharmonic by increments, chi 2", ["-mesh_motion", "biharmonic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "1"]),
]


def run(args, out):
    path = os.path.join(out, "summary.json")
    if os.path.exists(path):  # the previous repeat's: a run that writes none must not read it
        os.remove(path)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run([os.path.join(ROOT, "bin", "fsiopt")] + args + ["-output_dir", out, "-log_view"], cwd=ROOT,
                       env=env, capture_output=True, text=True, errors="replace")
    summary = json.load(open(path)) if os.path.exists(path) else None
    if p.returncode != 0 and not (summary and summary["failure"]):
        err = p.stderr.strip()
        sys.exit("mesh_motion_cost: fsiopt failed: %s" % (err.splitlines()[-1] if err else "exit %d" % p.returncode))
    stage = fr.parse_stages(p.stdout).get("MeshMotion")
    if stage is None:
        sys.exit("mesh_motion_cost: no MeshMotion stage in -log_view's output")
    rows = [line.split(",") for line in open(os.path.join(out, "probes.csv")).read().split("\n")[1:] if line]
    return summary, stage, [[float(v) for v in r] for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default="fsi2")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--restart", help="a checkpoint of the same case to start from")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "mesh-motion-cost"))
    ap.add_argument("extra", nargs="*", help="more fsiopt options (after --)")
    a = ap.parse_args()
    if a.steps < 1 or a.repeats < 1:
        ap.error("--steps and --repeats: 1 or more expected")
    base = ["-options_file", "options/turek-hron.yaml", "-turek_case", a.case] + a.extra
    if a.restart:
        if not os.path.isfile(a.restart):
            ap.error("--restart %s: no such checkpoint file" % a.restart)
        base += ["-restart", os.path.abspath(a.restart)]
    t_end = "%.12g" % (start_time(a, base) + a.steps * case_dt(base))
    wall, stage, worst, probes, failed = {}, {}, {}, {}, {}
    for r in range(a.repeats):
        for name, options in VARIANTS:
            s, t_stage, rows = run(base + options + ["-t_final", t_end], os.path.join(a.out, re.sub(r"[^a-z0-9]+", "-", name)))
            wall.setdefault(name, []).append(s["wall_time_s"])
            stage.setdefault(name, []).append(t_stage)
            worst[name], probes[name] = s["worst_corner_ratio"], rows
            failed[name] = failure_time(s["failure"])
    first = VARIANTS[0][0]
    print("| mesh motion | wall time (s) | ratio | MeshMotion stage (s) | ratio | worst corner ratio | probes vs first (of their largest) |")
    print("|---|---|---|---|---|---|---|")
    for name, _ in VARIANTS:
        w, m = statistics.median(wall[name]), statistics.median(stage[name])
        if failed[name]:  # a mesh this motion cannot follow: a step failed with the smallest dt
            print("| %s | %.2f | %.2f | %.3f | %.2f | failed at t = %s | |" % (
                name, w, w / statistics.median(wall[first]), m, m / statistics.median(stage[first]), failed[name]))
            continue
        diff = fr.probes_difference(probes[name], probes[first]) if not failed[first] else float("nan")
        print("| %s | %.2f | %.2f | %.3f | %.2f | %.4f | %.1e |" % (
            name, w, w / statistics.median(wall[first]), m, m / statistics.median(stage[first]), worst[name], diff))
    print("(%d steps, medians of %d runs each, alternated; %s)" % (a.steps, a.repeats, " ".join(base)))


def failure_time(failure):
    """the time of the step a failed run names, None if it did not fail"""
    if not failure:
        return None
    found = re.search(r"\(t = ([0-9.e+-]+)\)", failure)
    return found.group(1) if found else "? (%s)" % failure[:80]


def case_dt(base):
    """the case's time step, as fsiopt -help reports it"""
    text = subprocess.run([os.path.join(ROOT, "bin", "fsiopt")] + base + ["-help"], cwd=ROOT, capture_output=True,
                          text=True, errors="replace").stdout
    found = re.search(r"^\s*-dt <(\S+)", text, re.M)
    if not found:
        sys.exit("mesh_motion_cost: fsiopt -help does not show -dt")
    return float(found.group(1))


def start_time(a, base):
    """t = 0, or the checkpoint's time"""
    if not a.restart:
        return 0.0
    import h5py
    with h5py.File(a.restart, "r") as h5:
        return float(h5["run"].attrs["dt"]) * int(h5["run"].attrs["step"])


if __name__ == "__main__":
    main()
