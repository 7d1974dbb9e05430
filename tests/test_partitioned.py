"""The partitioned baselines (dn, aitken, iqnils, iqnimvj): their agreement with the
optimization-based coupling, their sweeps, the kept Dirichlet factors, IQN-IMVJ's restart
modes and parallel layouts."""
import os

from harness import CHANNEL, WORK, probes_difference, read_probes, same_file, solve, test

_partitioned = {}


def partitioned_runs():
    """channel2d, 10 steps, with the optimization-based and two partitioned couplings (the
    latter to a relative traction change of 1e-6, so that opt's tolerance dominates)."""
    if not _partitioned:
        for m in ["opt", "aitken", "iqnils", "iqnimvj"]:
            out = os.path.join(WORK, "pt-" + m)
            s = solve(CHANNEL + ["-t_final", "0.001", "-coupling", m] + (["-coupling_rtol", "1e-6"] if m != "opt" else []), out=out)
            _partitioned[m] = (s, read_probes(os.path.join(out, "probes.csv"))[1])
    return _partitioned


@test("opt, aitken, iqnils, iqnimvj agree on channel2d probes (10 x tol)")
def test_opt_aitken_iqnils_agree():
    runs, tol = partitioned_runs(), 1e-4  # -coupling_tol of options/channel2d.yaml
    _, ref = runs["opt"]
    worst = {}
    for m in ["aitken", "iqnils", "iqnimvj"]:
        _, got = runs[m]
        worst[m] = max(max(abs(g[c] - r[c]) for g, r in zip(got, ref)) / max(abs(r[c]) for r in ref) for c in (2, 4, 6))
        assert worst[m] <= 10 * tol, "%s differs from opt by %.2e of the probe amplitude" % (m, worst[m])
        assert runs[m][0]["max_interface_jump"] <= 1e-10, "%s: velocity jump %.2e" % (m, runs[m][0]["max_interface_jump"])
    return ", ".join("%s %.1e" % kv for kv in worst.items())


@test("iqnimvj: its inverse Jacobian, carried across steps, needs fewer sweeps than iqnils' reused columns over 100 steps; 2 ranks, fluid | structure = 1 rank")
def test_iqnimvj_fewer_sweeps():
    # a factorization every step and the polynomial start: the sweeps then stop at the same
    # iteration on every layout (kept factors converge the Dirichlet solves linearly, and the
    # recurrence-or-polynomial choice of the start can flip on rounding: a stop may move by a sweep)
    args = CHANNEL + ["-t_final", "0.01", "-fluid_dirichlet_snes_lag_jacobian", "-2", "-coupling_extrapolation_points", "6",
                      "-coupling_extrapolation_recurrence", "0"]
    runs = {}
    for m, nproc, extra in (("iqnils", 1, []), ("iqnimvj", 1, []), ("iqnimvj-2", 2, []), ("iqnimvj-split", 2, ["-structure_ranks", "1"])):
        out = os.path.join(WORK, "imvj-" + m)
        s = solve(args + ["-coupling", m.split("-")[0]] + extra, nproc=nproc, out=out)
        runs[m] = (s["avg_coupling_iterations"], read_probes(os.path.join(out, "probes.csv"))[1])
    ils, imvj = runs["iqnils"][0], runs["iqnimvj"][0]
    assert imvj < ils, "sweeps per step: iqnimvj %.2f, iqnils %.2f" % (imvj, ils)
    layouts = max(probes_difference(runs[m][1], runs["iqnimvj"][1]) for m in ("iqnimvj-2", "iqnimvj-split"))
    assert layouts <= 1e-10, "iqnimvj on 2 ranks differs from 1 rank by %.2e" % layouts
    return "sweeps per step: iqnimvj %.2f, iqnils %.2f; 2 ranks within %.1e" % (imvj, ils, layouts)


@test("partitioned fluid factors kept across steps (the default, -fluid_dirichlet_snes_lag_jacobian 20): iqnimvj's "
      "channel2d probes equal those of a factorization per step (10 x its rtol) with fewer fluid factorizations, "
      "on 1 and 2 ranks")
def test_dirichlet_factors_across_steps():
    args = CHANNEL + ["-t_final", "0.01", "-coupling", "iqnimvj"]
    runs = {}
    for tag, nproc, extra in (("per-step", 1, ["-fluid_dirichlet_snes_lag_jacobian", "-2"]), ("lagged", 1, []),
                              ("lagged-2", 2, [])):
        out = os.path.join(WORK, "dirichlet-lag-" + tag)
        s = solve(args + extra, nproc=nproc, out=out)
        runs[tag] = (s, read_probes(os.path.join(out, "probes.csv"))[1])
    fresh, lagged = runs["per-step"][0]["factorizations"]["fluid"], runs["lagged"][0]["factorizations"]["fluid"]
    assert lagged < fresh / 2, "fluid factorizations: lagged %d, per step %d" % (lagged, fresh)
    rtol = 1e-5  # the partitioned methods' default -coupling_rtol
    diff = probes_difference(runs["lagged"][1], runs["per-step"][1])
    assert diff <= 10 * rtol, "lagged factors change the probes by %.2e" % diff
    ranks = probes_difference(runs["lagged-2"][1], runs["lagged"][1])
    assert ranks <= 10 * rtol, "lagged factors on 2 ranks differ from 1 rank by %.2e" % ranks
    return "fluid factorizations %d -> %d, probes within %.1e; 2 ranks within %.1e" % (fresh, lagged, diff, ranks)


@test("iqnimvj restart modes: slide over the whole run = no restart byte for byte, svd without truncation = no "
      "restart (1e-10); every 5 steps ls and svd need fewer sweeps than zero; all agree (1e-5); svd on fluid | "
      "structure ranks = 1 rank")
def test_iqnimvj_restart_modes():
    # a factorization every step and the polynomial start: the identities below hold to rounding
    # only with exact Newton solves and the same start on both sides
    args = CHANNEL + ["-t_final", "0.005", "-coupling", "iqnimvj", "-coupling_rtol", "1e-7",
                      "-fluid_dirichlet_snes_lag_jacobian", "-2", "-coupling_extrapolation_points", "6",
                      "-coupling_extrapolation_recurrence", "0"]
    every5 = ["-coupling_imvj_restart", "5", "-coupling_imvj_restart_mode"]
    cases = (("none", 1, []), ("slide-all", 1, ["-coupling_imvj_restart", "200", "-coupling_imvj_restart_mode", "slide",
                                                 "-coupling_iqn_columns", "1000"]),
             ("svd-untruncated", 1, every5 + ["svd", "-coupling_imvj_svd_truncation", "0"]),
             ("zero", 1, every5 + ["zero"]), ("ls", 1, every5 + ["ls"]), ("svd", 1, every5 + ["svd"]),
             ("slide", 1, every5 + ["slide"]), ("svd-split", 2, every5 + ["svd", "-structure_ranks", "1"]))
    runs = {}
    for tag, nproc, extra in cases:
        out = os.path.join(WORK, "imvj-mode-" + tag)
        s = solve(args + extra, nproc=nproc, out=out)
        assert s["converged"], "%s did not converge" % tag
        runs[tag] = (s["coupling_iterations"], read_probes(os.path.join(out, "probes.csv"))[1], out)
    assert same_file(os.path.join(runs["none"][2], "probes.csv"), os.path.join(runs["slide-all"][2], "probes.csv")), \
        "slide over every step differs from no restart"
    untruncated = probes_difference(runs["svd-untruncated"][1], runs["none"][1])
    assert untruncated <= 1e-10, "svd without truncation differs from no restart by %.2e" % untruncated
    its = {t: runs[t][0] for t in runs}
    assert its["ls"] < its["zero"] and its["svd"] < its["zero"], "sweeps with a restart every 5 steps: %s" % its
    worst = max(probes_difference(runs[t][1], runs["none"][1]) for t in ("zero", "ls", "svd", "slide"))
    assert worst <= 1e-5, "a restart mode's probes differ from no restart by %.2e" % worst
    split = probes_difference(runs["svd-split"][1], runs["svd"][1])
    assert split <= 1e-10, "svd on fluid | structure ranks differs from 1 rank by %.2e" % split
    return "sweeps in 50 steps: none %d, every 5 steps zero %d, ls %d, svd %d, slide %d; untruncated svd %.1e from " \
        "none, modes within %.1e, split %.1e" % (its["none"], its["zero"], its["ls"], its["svd"], its["slide"],
                                               untruncated, worst, split)


@test("iqnils needs fewer coupling iterations than aitken")
def test_iqnils_fewer_iterations_than_aitken():
    runs = partitioned_runs()
    a, q = runs["aitken"][0]["avg_coupling_iterations"], runs["iqnils"][0]["avg_coupling_iterations"]
    assert q < a, "iqnils %.2f, aitken %.2f sweeps per step" % (q, a)
    return "sweeps per step: iqnils %.2f, aitken %.2f, opt %.2f GN" % (q, a, runs["opt"][0]["avg_coupling_iterations"])
