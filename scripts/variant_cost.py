#!/usr/bin/env python3
"""What a choice of method costs on a Turek-Hron run, side by side: the same run (default
fsi2 level 1, 20 steps) with each variant of one comparison, alternated --repeats times
in one invocation.

  --compare mesh-motion        the -mesh_motion variants; log stage MeshMotion (the
                               extensions, and for the incremental ones each step's
                               assembly and factorization)
  --compare explicit-jacobian  the number of controls per multi-right-hand-side solve
                               when the CG preconditioner J0 is built
                               (-coupling_explicit_jacobian_block); log stage Sensitivity
  --compare rebuild            when J0 is rebuilt: after a Gauss-Newton iteration whose CG
                               needed more than N iterations
                               (-coupling_explicit_jacobian_rebuild_its); log stage
                               Sensitivity (the builds and CG's products J h)

Reported per variant: the median wall time (summary.json wall_time_s) and the median time
of the comparison's log stage (-log_view), both as ratios to the first variant's (the
default), the smallest area a cell corner kept against its reference one (summary.json
worst_corner_ratio; a step fails below 1e-3) or the time of a step that failed because of
it (the timings then cover a shorter run), and the largest difference of the probes from
the first variant's. With --restart CHECKPOINT the runs start from a swung flag (a
checkpoint of the same case), so that the ratios say something.

  /usr/bin/python3 scripts/variant_cost.py [--compare mesh-motion] [--case fsi2]
      [--steps 20] [--repeats 3] [--restart CHECKPOINT] [--out out/variant-cost]
      [-- extra fsiopt options]"""
import argparse, json, os, re, statistics, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
from fsiopt_logview import parse_stages   # noqa: E402

ROOT = fr.ROOT
COMPARISONS = {  # (log stage, variants with the default first)
    "mesh-motion": ("MeshMotion", [
        ("biharmonic, chi 2", ["-mesh_motion", "biharmonic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "0"]),
        ("harmonic, chi 1", ["-mesh_motion", "harmonic", "-mesh_motion_stiffening", "1", "-mesh_motion_incremental", "0"]),
        ("elastic by increments, chi 2", ["-mesh_motion", "elastic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "1"]),
        ("biharmonic by increments, chi 2", ["-mesh_motion", "biharmonic", "-mesh_motion_stiffening", "2", "-mesh_motion_incremental", "1"]),
    ]),
    "explicit-jacobian": ("Sensitivity", [
        ("blocks of 32 controls", ["-coupling_explicit_jacobian_block", "32"]),
        ("one control at a time", ["-coupling_explicit_jacobian_block", "1"]),
        ("blocks of 8 controls", ["-coupling_explicit_jacobian_block", "8"]),
        ("blocks of 64 controls", ["-coupling_explicit_jacobian_block", "64"]),
    ]),
    "rebuild": ("Sensitivity", [
        ("after > 10 CG iterations", ["-coupling_explicit_jacobian_rebuild_its", "10"]),
        ("after > 20", ["-coupling_explicit_jacobian_rebuild_its", "20"]),
        ("after > 5", ["-coupling_explicit_jacobian_rebuild_its", "5"]),
        ("after > 2", ["-coupling_explicit_jacobian_rebuild_its", "2"]),
    ]),
}


def run(args, out, stage_name):
    path = os.path.join(out, "summary.json")
    if os.path.exists(path):  # the previous repeat's: a run that writes none must not read it
        os.remove(path)
    p = fr.run_fsiopt(args + ["-output_dir", out, "-log_view"])
    summary = json.load(open(path)) if os.path.exists(path) else None
    if p.returncode != 0 and not (summary and summary["failure"]):
        err = (p.stderr or "").strip()
        sys.exit("variant_cost: fsiopt failed: %s" % (err.splitlines()[-1] if err else "exit %s" % p.returncode))
    stage = parse_stages(p.stdout).get(stage_name)
    if stage is None:
        sys.exit("variant_cost: no %s stage in -log_view's output" % stage_name)
    rows = [line.split(",") for line in open(os.path.join(out, "probes.csv")).read().split("\n")[1:] if line]
    return summary, stage, [[float(v) for v in r] for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--compare", choices=sorted(COMPARISONS), default="mesh-motion")
    ap.add_argument("--case", default="fsi2")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--restart", help="a checkpoint of the same case to start from")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "variant-cost"))
    ap.add_argument("extra", nargs="*", help="more fsiopt options (after --)")
    a = ap.parse_args()
    if a.steps < 1 or a.repeats < 1:
        ap.error("--steps and --repeats: 1 or more expected")
    base = ["-options_file", "options/turek-hron/%s.yaml" % a.case] + a.extra
    if a.restart:
        if not os.path.isfile(a.restart):
            ap.error("--restart %s: no such checkpoint file" % a.restart)
        base += ["-restart", os.path.abspath(a.restart)]
    stage_name, variants = COMPARISONS[a.compare]
    t_end = "%.12g" % (start_time(a, base) + a.steps * case_dt(base))
    wall, stage, worst, probes, failed, its = {}, {}, {}, {}, {}, {}
    for r in range(a.repeats):
        for name, options in variants:
            s, t_stage, rows = run(base + options + ["-t_final", t_end], os.path.join(a.out, re.sub(r"[^a-z0-9]+", "-", name)), stage_name)
            wall.setdefault(name, []).append(s["wall_time_s"])
            stage.setdefault(name, []).append(t_stage)
            worst[name], probes[name] = s["worst_corner_ratio"], rows
            its[name] = "%d / %d" % (s["coupling_iterations"], s["inner_iterations"])
            failed[name] = failure_time(s["failure"])
    first = variants[0][0]
    print("| %s | wall time (s) | ratio | %s stage (s) | ratio | GN / CG iterations | worst corner ratio | probes vs first (of their largest) |" % (
        a.compare, stage_name))
    print("|---|---|---|---|---|---|---|---|")
    for name, _ in variants:
        w, m = statistics.median(wall[name]), statistics.median(stage[name])
        if failed[name]:  # e.g. a mesh this motion cannot follow: a step failed with the smallest dt
            print("| %s | %.2f | %.2f | %.3f | %.2f | %s | failed at t = %s | |" % (
                name, w, w / statistics.median(wall[first]), m, m / statistics.median(stage[first]), its[name], failed[name]))
            continue
        diff = fr.probes_difference(probes[name], probes[first]) if not failed[first] else float("nan")
        print("| %s | %.2f | %.2f | %.3f | %.2f | %s | %.4f | %.1e |" % (
            name, w, w / statistics.median(wall[first]), m, m / statistics.median(stage[first]), its[name], worst[name], diff))
    print("(%d steps, medians of %d runs each, alternated; %s)" % (a.steps, a.repeats, " ".join(base)))


def failure_time(failure):
    """the time of the step a failed run names, None if it did not fail"""
    if not failure:
        return None
    found = re.search(r"\(t = ([0-9.e+-]+)\)", failure)
    return found.group(1) if found else "? (%s)" % failure[:80]


def case_dt(base):
    """the case's time step, as fsiopt -help reports it"""
    text = fr.run_fsiopt(base + ["-help"]).stdout or ""
    found = re.search(r"^\s*-dt <(\S+)", text, re.M)
    if not found:
        sys.exit("variant_cost: fsiopt -help does not show -dt")
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
