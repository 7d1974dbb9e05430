"""-coupling monolithic (src/coupling/monolithic.c, problem_monolithic.c): Newton on the
whole discrete system converges to the solution opt converges to, keeps the manufactured
solution's rates, and restarts exactly."""
import os

import numpy as np

from harness import CHANNEL, NS_STEP, WORK, check_rates, interrupted, read_probes, same_file, solve, test, turek

MONO = ["-coupling", "monolithic"]


def probes(out):
    return np.array(read_probes(os.path.join(out, "probes.csv"))[1], float)


def agreement(args, tag, nproc=1):
    """monolithic against opt at -coupling_tol 1e-9, per probe column, beside opt's own change
    from -coupling_tol 1e-8 to 1e-9: (monolithic - opt, opt's change, the column's largest
    value, Newton iterations per step)"""
    outs = {}
    for name, extra in (("mono", MONO + ["-coupling_tol", "1e-9"]), ("opt", ["-coupling_tol", "1e-9"]),
                        ("opt8", ["-coupling_tol", "1e-8"])):
        outs[name] = os.path.join(WORK, "monolithic-%s-%s-%d" % (tag, name, nproc))
        s = solve(args + extra, nproc=nproc, out=outs[name])
        if name == "mono":
            per_step = s["coupling_iterations"] / s["steps"]
    mono, opt, opt8 = (probes(outs[k])[:, 1:] for k in ("mono", "opt", "opt8"))
    return abs(mono - opt).max(axis=0), abs(opt8 - opt).max(axis=0), abs(opt).max(axis=0), per_step


@test("monolithic = opt: channel2d's 50 steps on 1 and 2 ranks, Turek-Hron fsi1 (level 1, 5 steps), fsi3's ramp "
      "(level 1, 10 steps of 0.01) and tube3d (5 steps): every probe of monolithic Newton within 10 x the tolerance "
      "(1e-9) of the probe's largest value, or within opt's own change from -coupling_tol 1e-8 to 1e-9, of opt's at 1e-9")
def test_monolithic_agrees_with_opt():
    details = []
    unused = ["-options_allow_unused"]   # the scenes' files also set opt's own options
    tight_fluid = ["-fluid_snes_rtol", "1e-10", "-fluid_rhs_rtol", "1e-11"]  # tube3d's own 1e-7 is opt's error there
    for tag, args, nproc in (("channel2d", CHANNEL + ["-t_final", "0.005"], 1),
                             ("channel2d", CHANNEL + ["-t_final", "0.005"], 2),
                             ("fsi1", turek("fsi1") + ["-t_final", "0.5"] + unused, 1),
                             # a retry with a halved dt would compare another discretization
                             ("fsi3", turek("fsi3") + ["-dt", "0.01", "-dt_min", "0.01", "-t_final", "0.1"] + unused, 1),
                             ("tube3d", ["-options_file", "options/tube3d.yaml", "-t_final", "0.0005"] + tight_fluid + unused,
                              1)):
        gap, decade, scale, its = agreement(args, tag, nproc)
        bound = np.maximum(decade, 1e-8 * scale)
        assert (gap <= bound).all() and its <= 8, "%s on %d: monolithic - opt %s, bound %s, %.2f Newton its per step" % (
            tag, nproc, gap, bound, its)
        details.append("%s (%d): %.2f Newton its/step, gap relative %.1e, at most %.2f of the bound" % (
            tag, nproc, its, max(gap / scale), max(gap / bound)))
    return "; ".join(details)


@test("monolithic on PETSc's integration (-fem_backend petsc) = on libCEED's: Turek-Hron fsi3's ramp (level 1, 10 "
      "steps of 0.01, no step retried), every probe within 1e-8 of its largest value, the same Newton iterations +- 10 %")
def test_monolithic_backends():
    args = turek("fsi3") + MONO + ["-dt", "0.01", "-dt_min", "0.01", "-t_final", "0.1", "-coupling_tol", "1e-9",
                                   "-options_allow_unused"]
    runs = {}
    for backend in ("petsc", "ceed"):
        out = os.path.join(WORK, "monolithic-backend-%s" % backend)
        runs[backend] = (solve(args + ["-fem_backend", backend], out=out), probes(out)[:, 1:])
    gap = (abs(runs["petsc"][1] - runs["ceed"][1]).max(axis=0) / abs(runs["ceed"][1]).max(axis=0)).max()
    its = [runs[b][0]["coupling_iterations"] for b in ("petsc", "ceed")]
    assert gap <= 1e-8, "fsi3 monolithic: PETSc's integration against libCEED's, probes differ by %.1e" % gap
    assert abs(its[0] - its[1]) <= 0.1 * its[1], "fsi3 monolithic: Newton iterations %d (petsc) against %d" % tuple(its)
    return "probes within %.1e; %d and %d Newton iterations" % (gap, its[0], its[1])


@test("monolithic on mms-ns (one step, convective control): spatial rates u_L2, eta_L2 >= 2.8, u_H1, p_L2, eta_H1 "
      ">= 1.8, each error within 1e-4 of opt's; on mms-stokes (ten steps) each error within 1e-4 of opt's")
def test_monolithic_mms_rates():
    mono = [solve(NS_STEP + MONO + ["-refine", str(r)]) for r in range(1, 4)]
    opt = [solve(NS_STEP + ["-refine", str(r)]) for r in range(1, 4)]
    worst = max(abs(m["errors"][k] - o["errors"][k]) / o["errors"][k] for m, o in zip(mono, opt) for k in o["errors"])
    assert worst <= 1e-4, "monolithic's errors differ from opt's by %.1e, relative" % worst
    # Stokes and linear elasticity over ten steps of the manufactured solution (options/mms-stokes.yaml)
    stokes = {name: solve(["-options_file", "options/mms-stokes.yaml"] + extra)["errors"]
              for name, extra in (("mono", MONO), ("opt", []))}
    worst_stokes = max(abs(stokes["mono"][k] - stokes["opt"][k]) / stokes["opt"][k] for k in stokes["opt"])
    assert worst_stokes <= 1e-4, "mms-stokes: monolithic's errors differ from opt's by %.1e, relative" % worst_stokes
    return check_rates([s["errors"] for s in mono], {"u_L2": 2.8, "eta_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8,
                                                      "eta_H1": 1.8}) + "; relative to opt's %.0e; mms-stokes %.0e" % (
        worst, worst_stokes)


@test("monolithic restarts exactly: killed after step 33, restarted from its checkpoint of step 30, probes.csv byte "
      "for byte the uninterrupted run's")
def test_monolithic_restart():
    every = MONO + ["-t_final", "0.005", "-checkpoint_every", "5"]
    full = os.path.join(WORK, "monolithic-full")
    solve(CHANNEL + every, out=full)
    rc, err, killed = interrupted("SIGKILL", 33, extra=every)
    assert rc == -9, "exit status %s after SIGKILL (stderr %s)" % (rc, err.strip()[-200:])
    restarted = os.path.join(WORK, "monolithic-restarted")
    s = solve(CHANNEL + every + ["-restart", os.path.join(killed, "checkpoint.h5")], out=restarted)
    assert s["first_step"] == 31, "restart at step %s" % s["first_step"]
    assert same_file(os.path.join(full, "probes.csv"), os.path.join(restarted, "probes.csv")), \
        "the restarted run's probes.csv differs from the uninterrupted run's"
    return "restart at step 31 = the uninterrupted run byte for byte"


@test("monolithic with the Schur-complement field split on the interface traction "
      "(options/solvers/monolithic-schur.yaml) = with one LU of the whole system: channel2d's 20 steps, every probe "
      "to 1e-8 of its scale, the same Newton iterations")
def test_monolithic_fieldsplit():
    outs, summaries = {}, {}
    for name, extra in (("lu", []), ("schur", ["-options_file", "options/solvers/monolithic-schur.yaml"])):
        outs[name] = os.path.join(WORK, "monolithic-split-" + name)
        summaries[name] = solve(CHANNEL + MONO + ["-t_final", "0.002"] + extra, out=outs[name])
    lu, schur = probes(outs["lu"])[:, 1:], probes(outs["schur"])[:, 1:]
    gap = (abs(schur - lu).max(axis=0) / abs(lu).max(axis=0)).max()
    its = {k: s["coupling_iterations"] for k, s in summaries.items()}
    assert gap <= 1e-8 and its["lu"] == its["schur"], "gap %.1e of the scale, Newton iterations %s" % (gap, its)
    return "probes within %.1e of the scale, %d Newton iterations each" % (gap, its["lu"])
