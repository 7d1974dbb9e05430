"""The step's start and its tolerance: the control extrapolated from the last steps (least
squares, the fitted recurrence, its start from few controls, the secant updates) and the
coupling tolerance relative to the step's first jump."""
import csv, os

from harness import CHANNEL, WORK, difference_to_largest, out_dir, probes_difference, read_probes, solve, test, ITERATIVE_ILU


@test("channel2d: least-squares start saves GN iterations, same probes (10 x tol)")
def test_least_squares_start():
    runs = {}
    for points in ["3", "6"]:  # the quadratic through the last 3 steps (the plain start), fitted to the last 6
        out = os.path.join(WORK, "start-%s" % points)
        # Gauss-Newton from the polynomial starts alone (the default corrects and fits a recurrence),
        # held to the absolute tolerance alone: what a start saves, not what the rising wall costs
        s = solve(CHANNEL + ["-t_final", "0.005", "-coupling_inner", "cgls", "-coupling_extrapolation_recurrence", "0",
                             "-coupling_tol_relative", "0",
                             "-coupling_extrapolation", "2", "-coupling_extrapolation_points", points], out=out)
        runs[points] = (s["coupling_iterations"], read_probes(os.path.join(out, "probes.csv"))[1])
    (n3, p3), (n6, p6) = runs["3"], runs["6"]
    diff = max(max(abs(a[c] - b[c]) for a, b in zip(p3, p6)) / max(abs(a[c]) for a in p3) for c in (2, 4, 6))
    # a margin, not one iteration: at least a tenth of the plain start's iterations saved
    assert n6 <= 0.9 * n3, "GN iterations: %d fitted to 6 steps, %d through 3 (ratio %.2f > 0.9)" % (n6, n3, n6 / n3)
    assert diff <= 10 * 1e-4, "probes differ by %.2e of their amplitude" % diff
    return "GN iterations %d (6 steps) vs %d (3 steps): ratio %.2f; probes within %.1e" % (n6, n3, n6 / n3, diff)


@test("start variants on channel2d's first 200 steps (chord steps): the recurrence fitted to the corrected controls "
      "saves a tenth of the plain extrapolation's iterations, secant updates of J0^-1 save some; every variant's "
      "probes within 10 x tol")
def test_start_variants():
    args, tol = CHANNEL + ["-t_final", "0.02", "-coupling_inner", "chord"], 1e-4
    # each variant from the plain chord steps: polynomial start on 6 controls, no correction, no secants
    plain = {"-coupling_start_correction": "0", "-coupling_extrapolation_points": "6",
             "-coupling_extrapolation_recurrence": "0", "-coupling_secant_updates": "0"}
    variants = {"plain": {}, "corrected": {"-coupling_start_correction": "1"},
                "recurrence": {"-coupling_start_correction": "1", "-coupling_extrapolation_points": "12",
                               "-coupling_extrapolation_recurrence": "6"},
                "secant": {"-coupling_secant_updates": "20"}}
    runs = {}
    for tag, extra in variants.items():
        out = os.path.join(WORK, "start-" + tag)
        s = solve(args + [w for kv in dict(plain, **extra).items() for w in kv], out=out)
        runs[tag] = (s["coupling_iterations"], read_probes(os.path.join(out, "probes.csv"))[1])
    plain, ref = runs["plain"]
    worst = {}
    for tag in ("corrected", "recurrence", "secant"):
        worst[tag] = probes_difference(runs[tag][1], ref)
        assert worst[tag] <= 10 * tol, "%s start: probes differ by %.2e of their amplitude" % (tag, worst[tag])
    rec, sec = runs["recurrence"][0], runs["secant"][0]
    assert rec <= 0.9 * plain, "iterations: recurrence %d, plain extrapolation %d (ratio %.2f > 0.9)" % (rec, plain, rec / plain)
    # Broyden's corrections of J0^-1 make the chord steps contract more, never less here
    assert sec < plain, "iterations: with secant updates %d, without %d" % (sec, plain)
    return "iterations: plain %d, corrected %d, recurrence %d, secant updates %d; probes within %s" % (
        plain, runs["corrected"][0], rec, sec, ", ".join("%.1e (%s)" % (v, k) for k, v in worst.items()))


@test("the recurrence fitted from four recorded controls on, of the order they allow (-coupling_extrapolation_"
      "recurrence_from 4, the default): tube3d level 1, ten steps, iterative files, against the recurrence fitted "
      "only from P+3 = 9: steps 4-8 start at least 4x closer, no more Gauss-Newton iterations, probes within 10 x tol")
def test_recurrence_from_short_history():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.001"] + ITERATIVE_ILU
    found = {}
    for start in ("4", "9"):
        out = out_dir("recurrence-from-" + start)
        s = solve(args + ["-coupling_extrapolation_recurrence_from", start], out=out)
        with open(os.path.join(out, "history.csv")) as fh:
            first = {int(r["step"]): float(r["jump"]) for r in csv.DictReader(fh) if r["iteration"] == "0"}
        found[start] = (s, first, read_probes(os.path.join(out, "probes.csv"))[1])
    (short, short_jumps, short_probes), (full, full_jumps, full_probes) = found["4"], found["9"]
    early = [sum(jumps[k] for k in range(4, 9)) for jumps in (short_jumps, full_jumps)]
    assert early[0] <= 0.25 * early[1], "steps 4-8 start %.3g from their controls, %.3g with the recurrence from 9" % tuple(early)
    # from step 9 on both fit the same recurrence to the same (converged) controls
    assert abs(short_jumps[10] - full_jumps[10]) <= 0.1 * full_jumps[10], "step 10 starts %.3g against %.3g" % (
        short_jumps[10], full_jumps[10])
    its = (short["coupling_iterations"], full["coupling_iterations"])
    assert its[0] <= its[1], "Gauss-Newton iterations %d, recurrence from 9: %d" % its
    # relative to the largest displacement: the probes' y components are zero by symmetry
    diff = difference_to_largest(short_probes, full_probes)
    assert diff <= 10 * 1e-4, "probes differ by %.2e of the largest" % diff
    return "steps 4-8 start %.3g against %.3g from their controls; %d against %d Gauss-Newton iterations; probes within %.1e" % (
        early[0], early[1], its[0], its[1], diff)


@test("the relative coupling tolerance, on by default: from rest at dt = 1e-6 on channel2d the absolute one "
      "alone accepts every start and the wall does not move; the default iterates every step and meets a tight run")
def test_relative_tolerance():
    args = CHANNEL + ["-dt", "1e-6", "-t_final", "5e-6"]
    runs = {}
    for tag, extra in (("absolute", ["-coupling_tol_relative", "0"]), ("default", []),
                       ("tight", ["-coupling_tol_relative", "1e-8"])):
        out = os.path.join(WORK, "tol-" + tag)
        s = solve(args + extra, out=out)
        rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
        steps = {}
        for r in rows:
            steps.setdefault(int(r["step"]), []).append((int(r["iteration"]), float(r["jump"])))
        runs[tag] = (s["coupling_iterations"], steps, read_probes(os.path.join(out, "probes.csv"))[1])
    assert runs["absolute"][0] == 0, "the absolute tolerance iterated %d times" % runs["absolute"][0]
    its, steps, probes = runs["default"]
    assert len(steps) == 5 and all(len(v) >= 2 for v in steps.values()), "default: iterations per step %s" % {
        k: len(v) - 1 for k, v in steps.items()}
    worst = max(v[-1][1] / v[0][1] for v in steps.values())
    assert worst <= 1e-3, "default: a step ended at %.1e of its first jump" % worst
    # the wall's displacement after 5 steps: the absolute test leaves it where the
    # extrapolation put it, the default within 1e-3 of the tight run's
    absolute = difference_to_largest(runs["absolute"][2], runs["tight"][2])
    default = difference_to_largest(probes, runs["tight"][2])
    assert absolute >= 0.5 and default <= 1e-3, \
        "probes against the tight run: absolute %.2e (expected >= 0.5), default %.2e (expected <= 1e-3)" % (
            absolute, default)
    # the relative tolerance alone, from a developed state (the wall moving): every step
    # converges, none stalls above it (the velocity scale is the structure's, not a work vector's)
    ck = os.path.join(WORK, "tol-developed")
    solve(CHANNEL + ["-t_final", "0.005", "-checkpoint_every", "50"], out=ck)
    out = os.path.join(WORK, "tol-relative-developed")
    d = solve(CHANNEL + ["-t_final", "0.0053", "-restart", os.path.join(ck, "checkpoint.h5"), "-coupling_tol", "1e30",
                         "-coupling_tol_relative", "1e-5"], out=out)
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    dev = {}
    for r in rows:
        dev.setdefault(int(r["step"]), []).append(float(r["jump"]))
    assert d["converged"] and len(dev) == 3 and d["avg_coupling_iterations"] <= 3, \
        "relative only, developed: converged %s, iterations %s" % (d["converged"], {k: len(v) - 1 for k, v in dev.items()})
    return "absolute tolerance: 0 iterations in 5 steps, probes %.2f off; default: %d, each step's jump reduced to at " \
        "most %.1e of its first, probes %.1e off; relative alone from a developed state: %.2f per step, converged" % (
            absolute, its, worst, default, d["avg_coupling_iterations"])
