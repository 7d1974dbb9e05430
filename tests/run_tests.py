#!/usr/bin/python3
"""fsiopt test suite: every test asserts a property (a convergence rate, agreement
between runs, a solver count, a clean refusal of bad input). Run by `make test`.
Last line: 'N passed, M failed'; exit status non-zero on any failure. Arguments select
the tests whose names contain one of them."""
import csv, json, math, os, shutil, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FSIOPT = os.path.join(ROOT, "bin", "fsiopt")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
WORK = tempfile.mkdtemp(prefix="fsiopt-tests-")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from fsiopt_runs import probes_difference  # noqa: E402  (the scripts' comparison of probe series)
results = []


def run(args, nproc=1, tag="run", out=None):
    """Runs fsiopt, returns (returncode, stdout, stderr, summary or None)."""
    out = out or os.path.join(WORK, "%s-%d" % (tag, len(os.listdir(WORK))))
    cmd = ([FSIOPT] if nproc == 1 else ["mpiexec", "-n", str(nproc), FSIOPT]) + args + ["-output_dir", out]
    p = subprocess.run(cmd, cwd=ROOT, env=ENV, capture_output=True, text=True, errors="replace", timeout=600)
    path = os.path.join(out, "summary.json")
    summary = json.load(open(path)) if os.path.exists(path) else None
    return p.returncode, p.stdout, p.stderr, summary


def solve(args, nproc=1, out=None):
    rc, out, err, summary = run(args, nproc, out=out)
    if rc != 0 or summary is None:
        raise AssertionError("run failed (%s): %s" % (" ".join(args), (err or out).strip()[-300:]))
    return summary


def rates(errors, key):
    return [math.log2(errors[i][key] / errors[i + 1][key]) for i in range(len(errors) - 1)]


def test(name):
    def wrap(fn):
        def runner():
            t0 = time.time()
            try:
                detail = fn()
                results.append(True)
                print("PASS %-42s %6.1fs  %s" % (name, time.time() - t0, detail or ""), flush=True)
            except Exception as e:  # a crash or a timeout is a failure, not an abort of the suite
                results.append(False)
                print("FAIL %-42s %6.1fs  %s" % (name, time.time() - t0, e), flush=True)
        runner.__name__ = name
        TESTS.append(runner)
        return runner
    return wrap


TESTS = []


def check_rates(errs, floors):
    got = {k: rates(errs, k) for k in floors}
    for k, floor in floors.items():
        assert min(got[k]) >= floor, "%s rates %s below %.2f (errors %s)" % (
            k, ["%.2f" % r for r in got[k]], floor, ["%.2e" % e[k] for e in errs])
    return "; ".join("%s %s" % (k, " ".join("%.2f" % r for r in v)) for k, v in got.items())


FLUID_SPACE = ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time"]


@test("fluid (Q2,Q1) spatial rates")
def _():
    errs = [solve(FLUID_SPACE + ["-refine", str(r)])["errors"] for r in range(3)]
    return check_rates(errs, {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("fluid (P2,P1) gmsh spatial rates")
def _():
    errs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_dm_plex_filename", "meshes/square.msh"])["errors"] for r in range(3)]
    return check_rates(errs, {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("fluid (Q1,Q1) + pressure stabilization spatial rates")
def _():
    errs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_velocity_degree", "1", "-fluid_pressure_degree", "1",
                                 "-fluid_pressure_stabilization", "0.1"])["errors"] for r in (1, 2, 3)]
    return check_rates(errs, {"u_L2": 1.8, "u_H1": 0.9, "p_L2": 1.3})


@test("stokes (Q2,Q1) spatial rates, one factorization")
def _():
    runs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_model", "stokes"]) for r in range(3)]
    for s in runs:
        assert s["factorizations"]["fluid"] == 1, "Stokes factored %d times" % s["factorizations"]["fluid"]
    return check_rates([s["errors"] for s in runs], {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("structure Q2 spatial rates")
def _():
    errs = [solve(["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001",
                   "-refine", str(r)])["errors"] for r in range(3)]
    return check_rates(errs, {"eta_L2": 2.8, "eta_H1": 1.8})


@test("structure P2 gmsh spatial rates")
def _():
    errs = [solve(["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001",
                   "-refine", str(r), "-structure_dm_plex_filename", "meshes/wall.msh"])["errors"] for r in range(3)]
    return check_rates(errs, {"eta_L2": 2.8, "eta_H1": 1.8})


SVK = ["-scene", "mms-structure", "-structure_model", "svk"]


@test("SVK: Q2 spatial and midpoint temporal rates")
def _():
    space = [solve(SVK + ["-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001", "-refine", str(r)])["errors"] for r in range(3)]
    time_ = [solve(SVK + ["-structure_time_order", "2", "-t_start", "0.5", "-t_final", "1", "-dt", str(dt), "-refine", "2"])["errors"]
             for dt in (0.1, 0.05, 0.025)]
    return "space: %s; time: %s" % (check_rates(space, {"eta_L2": 2.8, "eta_H1": 1.8}), check_rates(time_, {"eta_L2": 1.8, "eta_H1": 1.7}))


@test("SVK: Jacobian = finite differences, Newton quadratic")
def _():
    # one step of dt = 0.5 on the coarse mesh: the stiffness, not the mass, dominates the
    # Jacobian, and the manufactured displacement's gradient is of order one
    rc, out, err, _ = run(SVK + ["-refine", "0", "-t_start", "0.5", "-dt", "0.5", "-t_final", "1",
                                 "-structure_snes_test_jacobian", "-structure_snes_monitor"], tag="svk-jac")
    assert rc == 0, "run failed: %s" % (err or out).strip()[-300:]
    fd = [float(l.split("=")[1].split(",")[0]) for l in out.splitlines() if l.strip().startswith("||J - Jfd||_F/||J||_F =")]
    norms = [float(l.split()[-1]) for l in out.splitlines() if "SNES Function norm" in l]
    assert fd and max(fd) <= 1e-6, "||J - Jfd||/||J|| = %s" % fd
    # convergence order log(r_{k+1}/r_k) / log(r_k/r_{k-1}) once the residual is 1e-2 of its start
    orders = [math.log(norms[k + 1] / norms[k]) / math.log(norms[k] / norms[k - 1])
              for k in range(1, len(norms) - 1) if norms[k] <= 1e-2 * norms[0]]
    assert orders and max(orders) >= 1.8, "Newton residuals %s: orders %s" % (norms, orders)
    return "||J - Jfd||/||J|| <= %.1e at %d states, Newton order %.2f (%d its)" % (max(fd), len(fd), max(orders), len(norms) - 1)


@test("SVK under a small load = linear wall to second order")
def _():
    import h5py
    diff = {}
    for amplitude in ("1e-2", "1e-3"):
        wall = {}
        for model in ("linear", "svk"):
            out = os.path.join(WORK, "svk-small-%s-%s" % (model, amplitude))
            solve(["-scene", "mms-structure", "-structure_model", model, "-mms_amplitude", amplitude, "-mms_linear_load",
                   "-t_start", "0.5", "-t_final", "0.6", "-dt", "0.025", "-write_fields"], out=out)
            with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
                last = sorted(k for k in h5["structure"] if k.startswith("step_"))[-1]
                wall[model] = h5["structure/%s/displacement" % last][()]
        diff[amplitude] = ((wall["svk"] - wall["linear"]) ** 2).sum() ** 0.5 / (wall["linear"] ** 2).sum() ** 0.5
    order = 1 + math.log10(diff["1e-2"] / diff["1e-3"])  # of the absolute difference in the amplitude
    assert 1.9 <= order <= 2.1, "relative differences %s: order %.2f" % (diff, order)
    return "relative difference %.1e (amplitude 1e-2), %.1e (1e-3): order %.2f" % (diff["1e-2"], diff["1e-3"], order)


@test("fluid backward Euler temporal rate")
def _():
    errs = [solve(["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-dt", str(dt), "-refine", "1"])["errors"]
            for dt in (0.1, 0.05, 0.025)]
    return check_rates(errs, {"u_L2": 0.9})


@test("fluid BDF2 temporal rate; its restart continues exactly")
def _():
    base = ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-refine", "2", "-fluid_time_order", "2"]
    errs = [solve(base + ["-dt", str(dt)])["errors"] for dt in (0.1, 0.05, 0.025)]
    detail = check_rates(errs, {"u_L2": 1.8, "p_L2": 1.8})
    # a Jacobian kept across steps is rebuilt when the scheme's mass coefficient changes (step 2)
    lagged = solve(base + ["-dt", "0.05", "-fluid_snes_lag_jacobian", "20", "-fluid_snes_lag_jacobian_persists"])
    assert lagged["failed_attempts"] == 0 and all(abs(lagged["errors"][k] - errs[1][k]) <= 1e-6 * errs[1][k] for k in errs[1]), \
        "lagged Jacobian: %d failed attempts, errors %s against %s" % (lagged["failed_attempts"], lagged["errors"], errs[1])
    full = solve(base + ["-dt", "0.05", "-checkpoint_every", "4"], out=os.path.join(WORK, "bdf2-full"))
    again = solve(base + ["-dt", "0.05", "-restart", os.path.join(WORK, "bdf2-full", "checkpoint.h5")])
    assert again["first_step"] == 9 and again["errors"] == full["errors"], "restarted %s, uninterrupted %s" % (again["errors"], full["errors"])
    return detail + "; lagged Jacobian: same errors, %d fluid factorizations; restarted at step 9: same errors" % lagged["factorizations"]["fluid"]


@test("structure first-order temporal rate")
def _():
    runs = [solve(["-scene", "mms-structure", "-structure_time_order", "1", "-t_start", "0.5", "-t_final", "1",
                   "-dt", str(dt), "-refine", "1"]) for dt in (0.02, 0.01, 0.005)]
    assert all(s["factorizations"]["structure"] == 1 for s in runs), "structure factored more than once per run"
    return check_rates([s["errors"] for s in runs], {"eta_L2": 0.9})


@test("structure midpoint temporal rate, one factorization")
def _():
    runs = [solve(["-scene", "mms-structure", "-structure_time_order", "2", "-t_start", "0.5", "-t_final", "1",
                   "-dt", str(dt), "-refine", "2"]) for dt in (0.1, 0.05, 0.025)]
    for s in runs:
        assert s["factorizations"]["structure"] == 1, "structure factored %d times" % s["factorizations"]["structure"]
        assert s["structure_solves"] == s["steps"], "one linear solve per step expected"
    return check_rates([s["errors"] for s in runs], {"eta_L2": 1.8, "eta_H1": 1.8})


def same_errors(args):
    one, two = solve(args), solve(args, nproc=2)
    assert two["ranks"]["fluid"] + two["ranks"]["structure"] >= 2, "the 2-rank run reports ranks %s" % two["ranks"]
    worst = 0.0
    for k, v in one["errors"].items():
        rel = abs(two["errors"][k] - v) / abs(v)
        worst = max(worst, rel)
        assert rel <= 1e-10, "%s: 1 rank %.15e, 2 ranks %.15e (rel %.1e)" % (k, v, two["errors"][k], rel)
    return "max relative difference %.1e" % worst


@test("2 ranks reproduce 1 rank: fluid")
def _():
    return same_errors(FLUID_SPACE + ["-refine", "1"])


@test("2 ranks reproduce 1 rank: structure")
def _():
    return same_errors(["-scene", "mms-structure", "-t_start", "0.5", "-t_final", "0.6", "-dt", "0.05", "-refine", "1"])


# ---- coupled problems (issue 3): derivatives, optimizer, rates, parallel layout ----
NS_STEP = ["-options_file", "options/mms-ns.yaml"]        # one step of 1e-6 from t0 = 0.5
SHORT = ["-scene", "mms-ns", "-t_start", "0.5", "-t_final", "0.52", "-dt", "0.01", "-refine", "1"]


def printed(out, prefix):
    return [l for l in out.splitlines() if l.startswith(prefix)]


def adjoint_cases(nproc):
    worst, done = 0.0, []
    for control in ("traction", "convective"):
        for order in ("1", "2"):
            for velocity in ("scheme", "difference"):
                args = SHORT + ["-coupling_control", control, "-structure_time_order", order, "-coupling_velocity", velocity,
                                "-coupling_test_adjoint", "-t_final", "0.51"]
                if nproc == 2:
                    args += ["-structure_ranks", "1"]
                rc, out, err, summary = run(args, nproc=nproc, tag="adjoint")
                assert rc == 0, "run failed: %s" % (err or out).strip()[-300:]
                line = printed(out, "adjoint test:")
                assert len(line) == 1, "no adjoint test line in %s" % out[-300:]
                rel = float(line[0].split()[-1])
                assert rel <= 1e-10, "%s, order %s, %s: relative difference %.2e" % (control, order, velocity, rel)
                worst = max(worst, rel)
                done.append(1)
    return "%d cases, worst %.1e" % (len(done), worst)


@test("adjoint: <Jh,r> = <h,J^T r>, 1 rank")
def _():
    return adjoint_cases(1)


@test("adjoint: <Jh,r> = <h,J^T r>, fluid | structure")
def _():
    return adjoint_cases(2)


@test("Taylor remainder is second order (mms-ns)")
def _():
    rc, out, err, _ = run(SHORT + ["-coupling_test_taylor", "-t_final", "0.51"], tag="taylor")
    assert rc == 0, "run failed: %s" % (err or out).strip()[-300:]
    ratios = [float(l.split()[-1]) for l in printed(out, "Taylor test:") if "ratio" in l]
    assert len(ratios) >= 4, "too few Taylor lines: %s" % out[-300:]
    assert all(3.8 <= r <= 4.2 for r in ratios), "ratios %s" % ratios
    return "ratios " + " ".join("%.3f" % r for r in ratios)


@test("SVK: adjoint identity and second-order Taylor remainder (mms-ns)")
def _():
    rc, out, err, _ = run(SHORT + ["-structure_model", "svk", "-structure_time_order", "2", "-coupling_test_adjoint",
                                   "-coupling_test_taylor", "-t_final", "0.51"], tag="svk-adjoint")
    assert rc == 0, "run failed: %s" % (err or out).strip()[-300:]
    adjoint = [float(l.split()[-1]) for l in printed(out, "adjoint test:")]
    ratios = [float(l.split()[-1]) for l in printed(out, "Taylor test:") if "ratio" in l]
    assert len(adjoint) == 1 and adjoint[0] <= 1e-10, "adjoint test %s" % adjoint
    assert len(ratios) >= 4 and all(3.8 <= r <= 4.2 for r in ratios), "Taylor ratios %s" % ratios
    return "adjoint %.1e, Taylor ratios %s" % (adjoint[0], " ".join("%.3f" % r for r in ratios))


@test("Gauss-Newton: ||F|| <= 1e-10 in <= 4 its/step (mms-stokes)")
def _():
    out = os.path.join(WORK, "gn")
    s = solve(["-options_file", "options/mms-stokes.yaml"], out=out)
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    last = {}
    for r in rows:
        last[int(r["step"])] = r
    assert len(last) == s["steps"], "history has %d steps of %d" % (len(last), s["steps"])
    for step, r in last.items():
        F = math.sqrt(2 * float(r["objective"]))
        assert int(r["iteration"]) <= 4 and F <= 1e-10 and float(r["jump"]) <= 1e-10, "step %d: %s" % (step, r)
    assert s["factorizations"] == {"fluid": 1, "structure": 1}, "factorizations %s" % s["factorizations"]
    assert s["converged"] is True and s["max_interface_jump"] <= 1e-10
    return "%.2f its/step, %.1f CG its per GN it" % (s["avg_coupling_iterations"], s["inner_iterations"] / s["coupling_iterations"])


@test("mms-ns one-step spatial rates, <= 1 fluid factorization per GN it")
def _():
    runs = [solve(NS_STEP + ["-refine", str(r)]) for r in range(1, 4)]
    for s in runs:
        assert s["factorizations"]["structure"] == 1, "structure factored %d times" % s["factorizations"]["structure"]
        assert s["factorizations"]["fluid"] <= s["coupling_iterations"] + 1, "fluid factored %d times for %d GN its" % (
            s["factorizations"]["fluid"], s["coupling_iterations"])
    return check_rates([s["errors"] for s in runs], {"u_L2": 2.8, "eta_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8, "eta_H1": 1.8})


@test("mms-stokes temporal rate")
def _():
    errs = [solve(["-options_file", "options/mms-stokes.yaml", "-dt", str(dt)])["errors"] for dt in (0.1, 0.05, 0.025)]
    return check_rates(errs, {"u_L2": 0.9, "p_L2": 0.9, "eta_H1": 0.9})


@test("2 ranks (fluid | structure) reproduce 1 rank: mms-ns")
def _():
    one, two = solve(SHORT + ["-coupling_tol", "1e-12"]), solve(SHORT + ["-coupling_tol", "1e-12", "-structure_ranks", "1"], nproc=2)
    assert two["ranks"] == {"fluid": 1, "structure": 1, "total": 2}, "ranks %s" % two["ranks"]
    worst = 0.0
    for k, v in one["errors"].items():
        rel = abs(two["errors"][k] - v) / abs(v)
        worst = max(worst, rel)
        assert rel <= 1e-9, "%s: 1 rank %.15e, 2 ranks %.15e (rel %.1e)" % (k, v, two["errors"][k], rel)
    return "max relative difference %.1e" % worst


# ---- moving meshes (issue 4) ----
@test("geometric conservation: uniform flow on a moving mesh, 2D and 3D, backward Euler and BDF2")
def _():
    details = []
    for name, box in (("quadrilaterals", []), ("hexahedra", ["-fluid_dm_plex_dim", "3", "-fluid_dm_plex_box_faces", "4,4,2"])):
        for order in ("1", "2"):
            s = solve(["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-fluid_time_order", order] + box)
            e = s["errors"]
            assert e["u_L2"] <= 1e-12 and e["p_L2"] <= 1e-12, "%s, order %s: errors %s" % (name, order, e)
            details.append("%s order %s u_L2 %.1e, p_L2 %.1e" % (name, order, e["u_L2"], e["p_L2"]))
    return ", ".join(details) + " after 10 steps"


@test("ALE fluid on a moving mesh: temporal rates (backward Euler, BDF2); BDF2 restarts exactly")
def _():
    errs = [solve(["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-dt", str(dt), "-refine", "1",
                   "-mms_mesh_motion", "0.1"])["errors"] for dt in (0.05, 0.025, 0.0125)]
    detail = "backward Euler " + check_rates(errs, {"u_L2": 0.9, "p_L2": 0.9})
    # to t = 0.8: at t = 1 the BDF2 error of this motion passes near a zero, its ratios scatter
    base = ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "0.8", "-refine", "2", "-mms_mesh_motion", "0.1",
            "-fluid_time_order", "2"]
    errs = [solve(base + ["-dt", str(dt)])["errors"] for dt in (0.05, 0.025, 0.0125)]
    detail += "; BDF2 " + check_rates(errs, {"u_L2": 1.7, "p_L2": 1.8})
    full = solve(base + ["-dt", "0.025"], out=os.path.join(WORK, "ale-bdf2-full"))
    part = solve(base + ["-dt", "0.025", "-t_final", "0.65", "-checkpoint_every", "6"], out=os.path.join(WORK, "ale-bdf2-part"))
    again = solve(base + ["-dt", "0.025", "-restart", os.path.join(WORK, "ale-bdf2-part", "checkpoint.h5")])
    assert part["steps_done"] == 6 and again["first_step"] == 7 and again["errors"] == full["errors"], \
        "restarted at step %d: %s, uninterrupted %s" % (again["first_step"], again["errors"], full["errors"])
    return detail + "; restarted at step 7: same errors"


CHANNEL = ["-options_file", "options/channel2d.yaml"]
CHANNEL_REFERENCE = os.path.join(ROOT, "tests", "reference", "channel2d-50-steps-probes.csv")


def read_probes(path):
    rows = list(csv.reader(open(path)))
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


@test("channel2d 50 steps: jump <= tol every step, probes = reference")
def _():
    out = os.path.join(WORK, "channel")
    s = solve(CHANNEL + ["-t_final", "0.005"], out=out)
    last = {}
    for r in csv.DictReader(open(os.path.join(out, "history.csv"))):
        last[int(r["step"])] = float(r["jump"])
    assert len(last) == 50 and max(last.values()) <= 1e-4, "steps %d, worst final jump %.2e" % (len(last), max(last.values()))
    head, got = read_probes(os.path.join(out, "probes.csv"))
    ref_head, ref = read_probes(CHANNEL_REFERENCE)
    assert head == ref_head and len(got) == len(ref), "probe layout differs from the reference"
    worst = probes_difference(got, ref)
    assert worst <= 1e-8, "probes differ from the reference by %.2e relative" % worst
    return "%.2f GN its/step, probes within %.1e of the reference" % (s["avg_coupling_iterations"], worst)


@test("incremental mesh motion: = the total extension on channel2d (10 x tol), restarts byte for byte")
def _():
    inc = CHANNEL + ["-mesh_motion_incremental"]
    full = os.path.join(WORK, "incremental-full")
    solve(inc + ["-t_final", "0.005", "-checkpoint_every", "25"], out=full)  # a checkpoint resynchronizes the writer too
    head, got = read_probes(os.path.join(full, "probes.csv"))
    diff = probes_difference(got, read_probes(CHANNEL_REFERENCE)[1])
    # the two extensions differ at second order in the (small) displacement, not at all if
    # the operator were not rebuilt on the moved mesh
    assert 1e-12 < diff <= 10 * 1e-4, "probes differ from the total extension's by %.2e of their amplitude" % diff
    part = os.path.join(WORK, "incremental-part")
    solve(inc + ["-t_final", "0.0025", "-checkpoint_every", "25"], out=part)
    again = os.path.join(WORK, "incremental-again")
    s = solve(inc + ["-t_final", "0.005", "-restart", os.path.join(part, "checkpoint.h5")], out=again)
    assert s["first_step"] == 26 and open(os.path.join(again, "probes.csv")).read() == open(os.path.join(full, "probes.csv")).read(), \
        "restarted at step %d: probes.csv differs from the uninterrupted run's" % s["first_step"]
    return "probes within %.1e of the total extension's; restarted at step 26: probes.csv byte for byte" % diff


@test("biharmonic mesh motion: clamped at the wall (half the harmonic's shear), same probes (1 %), 2 fluid ranks")
def _():
    import h5py
    import numpy as np
    # a wall 100 x softer than channel2d's: it moves 4.5 % of the channel's height
    soft = CHANNEL + ["-t_final", "0.01", "-structure_youngs_modulus", "3e4", "-write_fields", "-write_fields_interval", "1000"]
    runs = {}
    for motion in ["harmonic", "biharmonic"]:
        out = os.path.join(WORK, "motion-" + motion)
        s = solve(soft + ["-mesh_motion", motion], out=out)
        assert 0 < s["worst_corner_ratio"] < 1 and 0 < s["worst_corner_time"] <= 0.01 + 1e-12, \
            "%s: worst_corner_ratio %s at t = %s" % (motion, s["worst_corner_ratio"], s["worst_corner_time"])
        with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
            steps = sorted(k for k in h5["fluid"] if k.startswith("step"))
            X = h5["fluid"][steps[0]]["geometry"][:]
            d = h5["fluid"][steps[-1]]["geometry"][:] - X
        # the displacement's change across the layer of cells under the wall (y = 1 to 0.9),
        # relative to the wall's: w = -Delta d tested on the boundary too makes the normal
        # derivative zero there, so the first layer follows the wall nearly rigidly
        wall, below = [np.flatnonzero(np.isclose(X[:, 1], y)) for y in (1.0, 0.9)]
        wall, below = wall[np.argsort(X[wall, 0])], below[np.argsort(X[below, 0])]
        assert len(wall) == len(below) > 10 and np.allclose(X[wall, 0], X[below, 0]), "no vertical grid lines in the channel mesh"
        runs[motion] = (np.abs(d[wall] - d[below]).sum() / np.abs(d[wall]).sum(), read_probes(os.path.join(out, "probes.csv"))[1])
    (shear_h, probes_h), (shear_b, probes_b) = runs["harmonic"], runs["biharmonic"]
    assert shear_b < 0.6 * shear_h, "across the wall's first cell layer: biharmonic %.3f, harmonic %.3f of the wall's motion" % (shear_b, shear_h)
    diff = probes_difference(probes_b, probes_h)
    # the mesh motion changes the discretization only: the wall moves the same
    assert 1e-8 < diff < 1e-2, "probes differ by %.2e of their amplitude" % diff
    # two fluid ranks share the mixed field's vertices
    short = CHANNEL + ["-t_final", "0.002", "-mesh_motion", "biharmonic"]
    one, three = os.path.join(WORK, "biharmonic-1"), os.path.join(WORK, "biharmonic-3")
    solve(short, out=one)
    s = solve(short + ["-structure_ranks", "1"], nproc=3, out=three)
    assert s["ranks"]["fluid"] == 2, "ranks %s" % s["ranks"]
    ranks = probes_difference(read_probes(os.path.join(three, "probes.csv"))[1], read_probes(os.path.join(one, "probes.csv"))[1])
    assert ranks <= 1e-9, "2 fluid ranks differ from 1 by %.2e" % ranks
    return "change across the first layer %.3f (harmonic %.3f) of the wall's; probes within %.1e; 2 fluid ranks = 1 to %.0e" % (
        shear_b, shear_h, diff, ranks)

@test("channel2d: least-squares start saves GN iterations, same probes (10 x tol)")
def _():
    runs = {}
    for points in ["3", "6"]:  # the quadratic through the last 3 steps, fitted to the last 6
        out = os.path.join(WORK, "start-%s" % points)
        s = solve(CHANNEL + ["-t_final", "0.005", "-coupling_extrapolation", "2", "-coupling_extrapolation_points", points], out=out)
        runs[points] = (s["coupling_iterations"], read_probes(os.path.join(out, "probes.csv"))[1])
    (n3, p3), (n6, p6) = runs["3"], runs["6"]
    diff = max(max(abs(a[c] - b[c]) for a, b in zip(p3, p6)) / max(abs(a[c]) for a in p3) for c in (2, 4, 6))
    assert n6 < n3, "GN iterations: %d fitted to 6 steps, %d through 3" % (n6, n3)
    assert diff <= 10 * 1e-4, "probes differ by %.2e of their amplitude" % diff
    return "GN iterations %d (6 steps) vs %d (3 steps), probes within %.1e" % (n6, n3, diff)


@test("channel2d: fluid | structure ranks = 1 rank (opt, iqnils)")
def _():
    worst = {}
    for m in ["opt", "iqnils"]:
        args = CHANNEL + ["-t_final", "0.001", "-coupling", m]
        outs = [os.path.join(WORK, "ch1-" + m), os.path.join(WORK, "ch2-" + m)]
        solve(args, out=outs[0])
        two = solve(args + ["-structure_ranks", "1"], nproc=2, out=outs[1])
        assert two["ranks"] == {"fluid": 1, "structure": 1, "total": 2}, "ranks %s" % two["ranks"]
        (_, a), (_, b) = read_probes(os.path.join(outs[0], "probes.csv")), read_probes(os.path.join(outs[1], "probes.csv"))
        worst[m] = max(abs(x - y) / max(abs(x), 1e-300) for ra, rb in zip(a, b) for x, y in zip(ra[1:], rb[1:]) if x != 0)
        assert worst[m] <= 1e-8, "%s: 2 ranks differ by %.2e relative" % (m, worst[m])
    return "max relative difference: " + ", ".join("%s %.1e" % kv for kv in worst.items())


@test("explicit Jacobian by blocks of controls = one control at a time (1 and 3 ranks)")
def _():
    # rebuilt every step, so that every step's CG is preconditioned by a block-built J
    args = CHANNEL + ["-t_final", "0.001", "-coupling_explicit_jacobian", "1"]
    runs = {}
    for tag, block, nproc in [("single", "1", 1), ("block", "7", 1), ("block-3ranks", "7", 3)]:
        out = os.path.join(WORK, "explicit-" + tag)
        extra = ["-structure_ranks", "1"] if nproc == 3 else []
        solve(args + ["-coupling_explicit_jacobian_block", block] + extra, nproc=nproc, out=out)
        inner = [int(r["inner_iterations"]) for r in csv.DictReader(open(os.path.join(out, "history.csv")))]
        runs[tag] = (inner, read_probes(os.path.join(out, "probes.csv"))[1])
    single_inner, single = runs["single"]
    worst = {}
    for tag in ["block", "block-3ranks"]:
        inner, probes = runs[tag]
        assert inner == single_inner, "%s: inner CG iterations %s, one column at a time %s" % (tag, inner, single_inner)
        # a J0 that differed would change CG's iterates at its tolerance (1e-4), far above this
        worst[tag] = probes_difference(probes, single)
        assert worst[tag] <= 1e-10, "%s: probes differ by %.2e of their amplitude" % (tag, worst[tag])
    return "%d CG iterations in each; probes within %.1e (1 rank), %.1e (3 ranks)" % (sum(single_inner), worst["block"], worst["block-3ranks"])


@test("tube3d: 2 ranks (fluid | structure) = 1 rank, the wave enters")
def _():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0002", "-coupling_explicit_jacobian", "0"]
    outs = [os.path.join(WORK, "tube1"), os.path.join(WORK, "tube2")]
    one = solve(args, out=outs[0])
    two = solve(args + ["-structure_ranks", "1"], nproc=2, out=outs[1])
    assert one["ranks"] == {"fluid": 1, "structure": 1, "total": 1}, "ranks %s" % one["ranks"]
    assert two["ranks"] == {"fluid": 1, "structure": 1, "total": 2}, "ranks %s" % two["ranks"]
    assert one["dim"] == 3 and one["max_interface_jump"] <= 1e-4, "dim %s, jump %s" % (one["dim"], one["max_interface_jump"])
    head, a = read_probes(os.path.join(outs[0], "probes.csv"))
    _, b = read_probes(os.path.join(outs[1], "probes.csv"))
    scale = max(abs(x) for r in a for x in r[1:])
    worst = max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra[1:], rb[1:])) / scale
    assert worst <= 1e-8, "2 ranks differ by %.2e relative" % worst
    radial = head.index("dx(0.5;0.;1.25)")
    assert a[-1][radial] > 0 and a[-1][radial] >= 10 * abs(a[-1][head.index("dx(0.5;0.;3.75)")]), \
        "the wall near the inlet should bulge first: %s" % a[-1]
    return "%d dofs, %.2f GN its/step, radial displacement at z = 1.25: %.2e, 2 ranks within %.1e" % (
        one["fluid_dofs"] + one["structure_dofs"], one["avg_coupling_iterations"], a[-1][radial], worst)


@test("fields: HDF5 + XDMF consistent, fluid mesh follows the wall")
def _():
    import h5py
    out = os.path.join(WORK, "fields")
    solve(CHANNEL + ["-t_final", "0.001", "-write_fields", "-write_fields_interval", "5", "-structure_ranks", "1"], nproc=2, out=out)
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "check_fields.py"), out], capture_output=True, text=True)
    assert p.returncode == 0, "check_fields: %s" % (p.stderr or p.stdout).strip()
    with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
        steps = sorted(k for k in h5["fluid"] if k.startswith("step_"))
        assert steps == ["step_00000", "step_00005", "step_00010"], "written steps %s" % steps
        fluid0, fluid = h5["fluid/step_00000/geometry"][()], h5["fluid/step_00010/geometry"][()]
        wall0, wall = h5["structure/step_00000/geometry"][()], h5["structure/step_00010/geometry"][()]
    on_fluid = {round(x, 9): d for (x, y), d in zip(fluid0, fluid - fluid0) if abs(y - 1) < 1e-12}
    on_wall = {round(x, 9): d for (x, y), d in zip(wall0, wall - wall0) if abs(y - 1) < 1e-12}
    assert len(on_fluid) == 31 and set(on_fluid) == set(on_wall), "interface vertices %d / %d" % (len(on_fluid), len(on_wall))
    worst = max(abs(on_fluid[x] - on_wall[x]).max() for x in on_fluid)
    scale = max(abs(d).max() for d in on_wall.values())
    _, probes = read_probes(os.path.join(out, "probes.csv"))
    probe = abs(on_wall[3.0][1] - probes[-1][4])
    assert scale > 0 and worst <= 1e-12 * scale + 1e-15, "fluid interface moved %.2e away from the wall" % worst
    assert probe <= 1e-10 * scale, "wall field and probes.csv differ by %.2e at (3,1)" % probe
    return "3 times, interface max |d| %.2e, fluid vs wall %.1e" % (scale, worst)


_partitioned = {}


def partitioned_runs():
    """channel2d, 10 steps, with the optimization-based and two partitioned couplings (the
    latter to a relative traction change of 1e-6, so that opt's tolerance dominates)."""
    if not _partitioned:
        for m in ["opt", "aitken", "iqnils"]:
            out = os.path.join(WORK, "pt-" + m)
            s = solve(CHANNEL + ["-t_final", "0.001", "-coupling", m] + (["-coupling_rtol", "1e-6"] if m != "opt" else []), out=out)
            _partitioned[m] = (s, read_probes(os.path.join(out, "probes.csv"))[1])
    return _partitioned


@test("opt, aitken, iqnils agree on channel2d probes (10 x tol)")
def _():
    runs, tol = partitioned_runs(), 1e-4  # -coupling_tol of options/channel2d.yaml
    _, ref = runs["opt"]
    worst = {}
    for m in ["aitken", "iqnils"]:
        _, got = runs[m]
        worst[m] = max(max(abs(g[c] - r[c]) for g, r in zip(got, ref)) / max(abs(r[c]) for r in ref) for c in (2, 4, 6))
        assert worst[m] <= 10 * tol, "%s differs from opt by %.2e of the probe amplitude" % (m, worst[m])
        assert runs[m][0]["max_interface_jump"] <= 1e-10, "%s: velocity jump %.2e" % (m, runs[m][0]["max_interface_jump"])
    return ", ".join("%s %.1e" % kv for kv in worst.items())


@test("iqnils needs fewer coupling iterations than aitken")
def _():
    runs = partitioned_runs()
    a, q = runs["aitken"][0]["avg_coupling_iterations"], runs["iqnils"][0]["avg_coupling_iterations"]
    assert q < a, "iqnils %.2f, aitken %.2f sweeps per step" % (q, a)
    return "sweeps per step: iqnils %.2f, aitken %.2f, opt %.2f GN" % (q, a, runs["opt"][0]["avg_coupling_iterations"])


def force_errors(args):
    """|drag| and |lift| of mms-fluid's bottom side: the discrete force minus the exact one."""
    out = os.path.join(WORK, "force-%d" % len(os.listdir(WORK)))
    solve(["-scene", "mms-fluid"] + args, out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return {"drag": abs(rows[-1][head.index("drag")]), "lift": abs(rows[-1][head.index("lift")])}


@test("body force: volume-weighted drag, lift converge (space, time, moving mesh)")
def _():
    space = [force_errors(FLUID_SPACE[2:] + ["-refine", str(r)]) for r in range(1, 4)]
    time_args = ["-t_start", "0.5", "-t_final", "0.6", "-refine", "2", "-mms_mesh_motion", "0.1"]
    moving = [force_errors(time_args + ["-dt", dt]) for dt in ("0.02", "0.01", "0.005")]
    # BDF2's lift error is at the spatial floor already at dt = 0.02
    bdf2 = [force_errors(time_args + ["-dt", dt, "-fluid_time_order", "2"]) for dt in ("0.02", "0.01", "0.005")]
    return "space " + check_rates(space, {"drag": 2.5, "lift": 2.5}) + "; dt on a moving mesh " + \
        check_rates(moving, {"drag": 0.7, "lift": 0.9}) + "; with BDF2 " + check_rates(bdf2, {"drag": 1.8})


TUREK = ["-options_file", "options/turek-hron.yaml"]


def turek_mesh(part, level):
    """The Turek-Hron mesh of a refinement level: meshes/ has level 1, finer ones go to WORK."""
    if level == 1:
        return "meshes/turek-hron-%s.msh" % part
    path = os.path.join(WORK, "turek-hron-%s-n%d.msh" % (part, level))
    if not os.path.exists(path):
        subprocess.run(["gmsh", "-2", "-format", "msh22", "-v", "2", "-setnumber", "n", str(level), "-o", path,
                        "meshes/turek-hron-%s.geo" % part], cwd=ROOT, check=True, capture_output=True, timeout=300)
    return path


def turek_levels(case, option, part, columns):
    """Final values of `columns` on mesh levels 1 and 2: the largest relative change, and a description."""
    runs = []
    for level in (1, 2):
        s = solve(TUREK + ["-turek_case", case, option, turek_mesh(part, level)])
        runs.append((s["wall_time_s"], [s["quantities"][c]["final"] for c in columns]))
    changes = [abs(a - b) / abs(b) for a, b in zip(runs[0][1], runs[1][1])]
    assert max(changes) < 0.05, "%s: level 1 %s against level 2 %s" % (case, runs[0][1], runs[1][1])
    return "coarse %.1fs: %s; change to level 2 %s" % (
        runs[0][0], ", ".join("%s %.4e" % (c, v) for c, v in zip(columns, runs[0][1])),
        " ".join("%.2f%%" % (100 * c) for c in changes))


@test("turek-hron CSM1: coarse flag within 5% of the next level")
def _():
    return turek_levels("csm1", "-structure_dm_plex_filename", "flag", ["dx(0.6;0.2)", "dy(0.6;0.2)"])


@test("turek-hron CFD1: coarse drag, lift within 5% of the next level")
def _():
    return turek_levels("cfd1", "-fluid_dm_plex_filename", "fluid", ["drag", "lift"])


@test("turek-hron FSI1 coarse: A moves < 1e-7 m over the last 0.5 s")
def _():
    out = os.path.join(WORK, "fsi1")
    s = solve(TUREK + ["-turek_case", "fsi1"], out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    t_end = rows[-1][0]
    last = [r for r in rows if r[0] >= t_end - 0.5 - 1e-9]
    drift = max(max(r[c] for r in last) - min(r[c] for r in last) for c in (1, 2))
    assert drift < 1e-7, "A still moves by %.2e m over the last 0.5 s" % drift
    assert all(abs(r[3]) > 0 for r in last), "no drag recorded"
    q = s["quantities"]
    return "%.1fs, %.2f GN/step; A (%.4e, %.4e) m, drift %.1e m; drag %.4f, lift %.4f N/m" % (
        s["wall_time_s"], s["avg_coupling_iterations"], q["dx(0.6;0.2)"]["final"], q["dy(0.6;0.2)"]["final"], drift,
        q["drag"]["final"], q["lift"]["final"])


@test("turek-hron CSM3: summary quantities = the probe series' own")
def _():
    out = os.path.join(WORK, "csm3")
    s = solve(TUREK + ["-turek_case", "csm3", "-dt", "0.01", "-t_final", "4", "-quantities_window", "2"], out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    last = [r for r in rows if r[0] >= rows[-1][0] - 2 - 1e-9]
    y = [r[2] for r in last]
    q = s["quantities"]["dy(0.6;0.2)"]
    mean, amplitude = 0.5 * (max(y) + min(y)), 0.5 * (max(y) - min(y))
    # the period from the parabola through each local minimum (the C code counts crossings of the mean)
    troughs = []
    for i in range(1, len(y) - 1):
        if y[i] < y[i - 1] and y[i] <= y[i + 1]:
            a, b, c = y[i - 1], y[i], y[i + 1]
            troughs.append(last[i][0] + 0.5 * (a - c) / (a - 2 * b + c) * (last[i][0] - last[i - 1][0]))
    assert len(troughs) >= 2, "fewer than two oscillations in the window"
    frequency = (len(troughs) - 1) / (troughs[-1] - troughs[0])
    assert abs(q["mean"] - mean) <= 1e-12 and abs(q["amplitude"] - amplitude) <= 1e-12, "mean/amplitude %s against %g, %g" % (q, mean, amplitude)
    assert abs(q["frequency"] - frequency) <= 0.02 * frequency, "frequency %.4f against %.4f from the troughs" % (q["frequency"], frequency)
    assert amplitude > 0.1 * abs(mean), "no oscillation: amplitude %.3e, mean %.3e" % (amplitude, mean)
    # scripts/turek_hron_series.py quantities, over the same window, = summary.json's
    table = os.path.join(out, "series.csv")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "turek_hron_series.py"), "quantities", out,
                        "--from", repr(last[0][0]), "--csv", table], capture_output=True, text=True)
    assert p.returncode == 0, "turek_hron_series.py: %s" % p.stderr.strip()
    row = next(csv.DictReader(open(table)))
    worst = 0
    for column, got in s["quantities"].items():
        if column == "window_s":
            continue
        for key in ("mean", "amplitude", "frequency"):
            if got[key] == -1:  # summary.json's "none"; the script leaves the cell empty
                assert row[column + "_" + key] == "", "%s %s: summary none, script %s" % (column, key, row[column + "_" + key])
            else:
                worst = max(worst, abs(float(row[column + "_" + key]) - got[key]) / max(abs(got[key]), 1e-300))
    assert worst <= 1e-9, "turek_hron_series.py quantities differ from summary.json by %.1e (relative)" % worst
    return "uy(A) %.4e +- %.4e m [%.4f Hz; troughs %.4f Hz]; series script = summary to %.0e" % (
        q["mean"], q["amplitude"], q["frequency"], frequency, worst)


def interrupted_run(signum, nproc):
    """channel2d stopped by a signal once its probes have a few rows: (returncode, stderr, outputs dir)."""
    import signal
    out = os.path.join(WORK, "signal-%d-%d" % (signum, nproc))
    cmd = ([FSIOPT] if nproc == 1 else ["mpiexec", "-n", str(nproc), FSIOPT]) + CHANNEL + ["-output_dir", out]
    p = subprocess.Popen(cmd, cwd=ROOT, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    partial = os.path.join(out, "probes.csv.partial")
    t0 = time.time()
    while time.time() - t0 < 600 and not (os.path.exists(partial) and len(open(partial).readlines()) > 6):  # a loaded machine starts slowly
        time.sleep(0.2)
    p.send_signal(signum)
    _, err = p.communicate(timeout=120)
    return p.returncode, err, out


@test("SIGINT, SIGTERM: the step ends, outputs complete, converged false, exit != 0")
def _():
    import signal
    details = []
    for signum, name, nproc in ((signal.SIGINT, "SIGINT", 1), (signal.SIGTERM, "SIGTERM", 2)):
        rc, err, out = interrupted_run(signum, nproc)
        lines = [l for l in err.splitlines() if l.strip()]
        assert rc != 0, "%s: exit 0" % name
        assert len(lines) == 1 and lines[0].startswith("fsiopt: error: interrupted by " + name) and "-restart" in lines[0], "%s: stderr %s" % (name, lines)
        s = json.load(open(os.path.join(out, "summary.json")))
        assert s["converged"] is False and s["interrupted"] == name, "%s: summary %s" % (name, s)
        head, rows = read_probes(os.path.join(out, "probes.csv"))  # complete, not .partial
        assert len(rows) == s["steps_done"] + 1 and 5 < s["steps_done"] < s["steps"], "%s: %d probe rows for %d steps" % (name, len(rows), s["steps_done"])
        assert abs(rows[-1][0] - s["steps_done"] * s["dt"]) < 1e-12, "%s: last probe time %g" % (name, rows[-1][0])
        # the checkpoint it left continues the run
        end = s["steps_done"] + 10  # where the signal landed depends on the machine's load
        more = solve(CHANNEL + ["-t_final", repr(end * s["dt"]), "-restart", os.path.join(out, "checkpoint.h5")], nproc=nproc)
        assert more["first_step"] == s["steps_done"] + 1 and more["steps_done"] == end, "%s: restart %s" % (name, more)
        details.append("%s on %d rank%s after step %d, restarted from its checkpoint" % (name, nproc, "s" if nproc > 1 else "", s["steps_done"]))
    return ", ".join(details)


@test("restart from a checkpoint continues exactly, also after SIGKILL")
def _():
    import signal
    every = ["-t_final", "0.01", "-checkpoint_every", "5"]
    full = os.path.join(WORK, "ck-full")
    solve(CHANNEL + every, out=full)
    # killed outright, probably between checkpoints, maybe while writing one
    killed = os.path.join(WORK, "ck-killed")
    p = subprocess.Popen([FSIOPT] + CHANNEL + every + ["-output_dir", killed], cwd=ROOT, env=ENV,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ck = os.path.join(killed, "checkpoint.h5")
    t0 = time.time()
    while time.time() - t0 < 120 and not (os.path.exists(ck) and os.path.getsize(ck) > 0 and
                                          os.path.exists(os.path.join(killed, "probes.csv.partial")) and
                                          len(open(os.path.join(killed, "probes.csv.partial")).readlines()) > 33):
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)
    p.wait()
    restarted = os.path.join(WORK, "ck-restarted")
    s = solve(CHANNEL + every + ["-restart", ck], out=restarted)
    a, b = open(os.path.join(full, "probes.csv")).read(), open(os.path.join(restarted, "probes.csv")).read()
    assert a == b, "the restarted run's probes.csv differs from the uninterrupted run's"
    assert 1 < s["first_step"] <= 100 and s["steps_done"] == 100, "restart at step %s, done %s" % (s["first_step"], s["steps_done"])
    return "killed after step >= 32, restarted at step %d: probes.csv byte for byte the uninterrupted run's" % s["first_step"]


def diverging_cases():
    return [
        ("mesh motion inverting cells", ["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-gcl_amplitude", "0.6"], "inverted or degenerate at step 3"),
        ("mesh motion inverting hexahedra", ["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-gcl_amplitude", "0.6",
                                             "-fluid_dm_plex_dim", "3", "-fluid_dm_plex_box_faces", "4,4,2"], "inverted or degenerate at step 3"),
        # a soft, heavy wall: it bends before the fluid's velocities defeat its solver
        ("over-sized load inverts the channel's cells", CHANNEL + ["-t_final", "0.005", "-channel_inlet_amplitude", "1e6",
                                                                   "-structure_youngs_modulus", "3e3", "-structure_density", "10"],
         "inverted or degenerate at step"),
        ("unrelaxed Dirichlet-Neumann diverges (added mass)", CHANNEL + ["-t_final", "0.001", "-coupling", "dn"], "coupling dn diverged at step 1"),
        ("diverging relaxed descent", ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.6", "-tao_type", "sdrelaxed",
                                       "-coupling_tikhonov", "1e-4", "-tao_sdrelaxed_alpha", "0.5"], "at step 1, iteration"),
        ("structure Newton without retries", ["-options_file", "options/mms-structure.yaml", "-structure_model", "svk", "-dt", "0.05",
                                              "-structure_snes_max_it", "5", "-dt_min", "0.05"], "structure solve failed at step 1"),
    ]


@test("diverging step past -dt_min: says where, converged false, outputs to the step before")
def _():
    problems = []
    cases = diverging_cases()
    for name, args, token in cases:
        out = os.path.join(WORK, "diverging-%d" % len(problems))
        shutil.rmtree(out, ignore_errors=True)
        rc, stdout, err, s = run(args, out=out)
        lines = [l for l in err.splitlines() if l.strip()]
        why = []
        if rc == 0: why.append("exit 0")
        if "PETSC ERROR" in stdout + err: why.append("PETSc traceback")
        if len(lines) != 1 or not lines[0].startswith("fsiopt: error: ") or token not in lines[0] or "from t = " not in lines[0]:
            why.append("stderr %s lacks one error line with '%s' and 'from t = '" % (lines, token))
        if s is None: why.append("no summary.json")
        else:
            if s["converged"] is not False or token not in (s["failure"] or ""): why.append("summary converged %s, failure %s" % (s["converged"], s["failure"]))
            if not 0 <= s["steps_done"] < s["steps"]: why.append("steps_done %s of %s" % (s["steps_done"], s["steps"]))
            if s["errors"]: why.append("errors of a failed state reported")
            probes = os.path.join(out, "probes.csv")
            if os.path.exists(probes) and len(read_probes(probes)[1]) != s["steps_done"] + 1:
                why.append("probes.csv rows != steps_done + 1")
            retries = "no retries" not in lines[0] if lines else False
            if retries and ("-dt_min" not in lines[0] or s["failed_attempts"] < 2): why.append("not retried down to -dt_min")
        if why: problems.append("%s: %s" % (name, ", ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d cases" % len(cases)


@test("diverging steps retried with dt/2: = the run at dt/2 (SVK), near the smallest dt's run (channel2d)")
def _():
    svk = ["-options_file", "options/mms-structure.yaml", "-structure_model", "svk"]
    # Newton needs 6-7 iterations per step at dt 0.05, 5 at 0.025: every step fails once
    retried = solve(svk + ["-dt", "0.05", "-structure_snes_max_it", "5"])
    half = solve(svk + ["-dt", "0.025", "-structure_snes_max_it", "5"])
    full = solve(svk + ["-dt", "0.05"])
    assert retried["retried_steps"] == retried["steps"] == retried["failed_attempts"] and retried["smallest_dt"] == 0.025, \
        "retried %d of %d steps, %d failed attempts, smallest dt %g" % (retried["retried_steps"], retried["steps"], retried["failed_attempts"], retried["smallest_dt"])
    assert half["failed_attempts"] == 0 and retried["converged"], "the dt/2 run failed too"
    for k in retried["errors"]:
        a, b, c = retried["errors"][k], half["errors"][k], full["errors"][k]
        assert abs(a - b) <= 1e-8 * b, "%s: retried %.10e, dt/2 %.10e" % (k, a, b)
        assert c > 2 * b, "%s: dt and dt/2 runs too close to tell apart (%.3e, %.3e)" % (k, c, b)
    # coupled (opt): one Gauss-Newton iteration allowed; the steps that need two at dt are halved
    base = CHANNEL + ["-t_final", "0.0015", "-coupling_tol", "1e-6"]
    out = os.path.join(WORK, "retry-coupled")
    s = solve(base + ["-dt", "5e-4", "-coupling_max_it", "1"], out=out)
    assert s["converged"] and s["retried_steps"] >= 1 and s["max_interface_jump"] <= 1e-6, "coupled: %s" % s
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    retries = [r for r in rows if r["event"] == "retry"]
    assert len(retries) == s["failed_attempts"] and all(float(r["dt"]) > s["smallest_dt"] for r in retries), "history retry rows"
    last = {}
    for r in rows:
        if r["event"] == "": last[int(r["step"])] = float(r["jump"])
    assert sorted(last) == [1, 2, 3] and max(last.values()) <= 1e-6, "last jumps %s" % last
    head, got = read_probes(os.path.join(out, "probes.csv"))
    assert [r[0] for r in got] == [0, 5e-4, 1e-3, 1.5e-3], "probe times %s" % [r[0] for r in got]
    split = os.path.join(WORK, "retry-split")
    solve(base + ["-dt", "5e-4", "-coupling_max_it", "1", "-structure_ranks", "1"], nproc=2, out=split)
    assert open(os.path.join(split, "probes.csv")).read() == open(os.path.join(out, "probes.csv")).read(), \
        "fluid | structure ranks retry differently from 1 rank"
    ends = []
    for tag, dt in (("fine", repr(s["smallest_dt"])), ("coarse", "5e-4")):
        solve(base + ["-dt", dt], out=os.path.join(WORK, "retry-" + tag))
        ends.append(read_probes(os.path.join(WORK, "retry-" + tag, "probes.csv"))[1][-1])
    fine, coarse = ends
    # most of the retried run's steps were taken at the smallest dt: its end is near that run's
    scale = [max(abs(fine[c]), abs(coarse[c])) for c in range(len(head))]
    to_fine = sum(abs(got[-1][c] - fine[c]) / scale[c] for c in range(1, len(head)))
    to_coarse = sum(abs(got[-1][c] - coarse[c]) / scale[c] for c in range(1, len(head)))
    assert to_fine < 0.25 * to_coarse, "retried run's probes: %.3f from the smallest-dt run, %.3f from the dt run" % (to_fine, to_coarse)
    return "SVK: all %d steps halved = dt/2 run to 1e-8; channel2d: %d steps retried (dt down to %g; 2 ranks identical), probes %.3f from that dt's run, %.3f from dt's" % (
        retried["steps"], s["retried_steps"], s["smallest_dt"], to_fine, to_coarse)


@test("summary.json has every DESIGN key")
def _():
    s = solve(FLUID_SPACE)
    keys = ["scene", "coupling", "optimizer", "dim", "steps", "dt", "t_final", "wall_time_s", "fluid_solves",
            "fluid_linear_solves", "structure_solves", "coupling_iterations", "avg_coupling_iterations",
            "work_factor", "max_interface_jump", "factorizations", "converged", "errors", "quantities", "ranks"]
    missing = [k for k in keys if k not in s]
    assert not missing, "missing keys %s" % missing
    assert s["scene"] == "mms-fluid" and s["dim"] == 2 and s["steps"] == 1 and s["converged"] is True
    assert s["fluid_solves"] == 1 and s["structure_solves"] == 0 and s["coupling"] == "none"
    assert s["worst_corner_ratio"] is None and s["worst_corner_time"] is None, "a fixed mesh has no worst corner"
    return "%d keys" % len(keys)


def bad_input_cases():
    d = os.path.join(WORK, "inputs")
    os.makedirs(d, exist_ok=True)
    empty = os.path.join(d, "empty.yaml"); open(empty, "w").close()
    junk = os.path.join(d, "junk.msh"); open(junk, "w").write("this is not a mesh\n")
    nolabel_geo = os.path.join(d, "nolabels.geo")
    open(nolabel_geo, "w").write("Point(1)={0,0,0,0.5};Point(2)={1,0,0,0.5};Point(3)={1,1,0,0.5};Point(4)={0,1,0,0.5};"
                                 "Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Curve Loop(1)={1,2,3,4};"
                                 "Plane Surface(1)={1};Physical Curve(1)={1};Physical Surface(1)={1};\n")
    nolabel = os.path.join(d, "nolabels.msh")
    subprocess.run(["gmsh", "-2", "-format", "msh22", "-v", "0", "-o", nolabel, nolabel_geo], check=True, capture_output=True)
    # two quadrilaterals on the unit square with the face sets 1-4; the second listed clockwise
    inverted = os.path.join(d, "inverted.msh")
    open(inverted, "w").write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 0.5 0 0\n3 1 0 0\n"
                              "4 1 1 0\n5 0.5 1 0\n6 0 1 0\n$EndNodes\n$Elements\n8\n1 1 2 1 1 1 2\n2 1 2 1 1 2 3\n"
                              "3 1 2 2 2 3 4\n4 1 2 3 3 4 5\n5 1 2 3 3 5 6\n6 1 2 4 4 6 1\n7 3 2 1 1 1 2 5 6\n"
                              "8 3 2 1 1 2 5 4 3\n$EndElements\n")
    truncated = os.path.join(d, "truncated.msh")
    open(truncated, "w").write(open(os.path.join(ROOT, "meshes", "wall.msh")).read()[:600])
    F, S = ["-scene", "mms-fluid"], ["-scene", "mms-structure"]
    empty_h5 = os.path.join(d, "junk.h5"); open(empty_h5, "w").write("not hdf5\n")
    solve(CHANNEL + ["-t_final", "0.0002", "-checkpoint_every", "1"], out=os.path.join(d, "ck"))
    checkpoint = os.path.join(d, "ck", "checkpoint.h5")
    return [
        ("unknown scene", ["-scene", "nosuchscene"], "-scene"),
        ("no scene", ["-dt", "0.1"], "-scene"),
        ("unknown coupling", F + ["-coupling", "magic"], "-coupling"),
        ("missing options file", ["-options_file", "options/nosuch.yaml"], "nosuch.yaml"),
        ("options file is a directory", ["-options_file", "options"], "-options_file"),
        ("empty options file", ["-options_file", empty], "empty.yaml"),
        ("missing mesh file", F + ["-fluid_dm_plex_filename", "meshes/nosuch.msh"], "nosuch.msh"),
        ("unreadable mesh file", F + ["-fluid_dm_plex_filename", junk], "junk.msh"),
        ("mesh lacking labels", F + ["-fluid_dm_plex_filename", nolabel], "Face Sets"),
        ("mesh with an inverted cell", F + ["-fluid_dm_plex_filename", inverted], "inverted or degenerate"),
        ("truncated mesh file", S + ["-structure_dm_plex_filename", truncated], "truncated.msh"),
        ("3D mesh for a 2D scene", F + ["-fluid_dm_plex_filename", "meshes/tube3d-fluid.msh"], "expected a 2D mesh"),
        ("zero fluid density", F + ["-fluid_density", "0"], "-fluid_density"),
        ("negative fluid viscosity", F + ["-fluid_viscosity", "-1"], "-fluid_viscosity"),
        ("zero viscosity", F + ["-fluid_viscosity", "0"], "-fluid_viscosity"),
        ("zero structure density", S + ["-structure_density", "0"], "-structure_density"),
        ("negative Young's modulus", S + ["-structure_youngs_modulus", "-5"], "-structure_youngs_modulus"),
        ("Poisson ratio 0.5", S + ["-structure_poisson_ratio", "0.5"], "-structure_poisson_ratio"),
        ("Poisson ratio above 0.5", S + ["-structure_poisson_ratio", "0.7"], "-structure_poisson_ratio"),
        ("zero dt", F + ["-dt", "0"], "-dt"),
        ("negative dt", F + ["-dt", "-0.01"], "-dt"),
        ("dt not dividing the interval", F + ["-dt", "0.03", "-t_start", "0", "-t_final", "0.1"], "-dt"),
        ("t_final before t_start", F + ["-t_start", "1", "-t_final", "0.5"], "-t_final"),
        ("unstable element pair", F + ["-fluid_pressure_degree", "2"], "-fluid_pressure_degree"),
        ("negative refine", F + ["-refine", "-1"], "-refine"),
        ("non-conforming interface (counts)", ["-scene", "mms-stokes", "-structure_dm_plex_box_faces", "5,2"], "do not conform"),
        ("non-conforming interface (shifted)", ["-scene", "mms-stokes", "-structure_dm_plex_box_lower", "0.01,1", "-structure_dm_plex_box_upper", "1.01,1.5"], "fluid node (0"),
        ("Dirichlet-Neumann with the convective control", CHANNEL + ["-coupling", "aitken", "-coupling_control", "convective"], "-coupling_control"),
        ("Dirichlet-Neumann on an enclosed fluid", ["-scene", "mms-stokes", "-coupling", "iqnils"], "incompressibility"),
        ("too few extrapolation points", CHANNEL + ["-coupling_extrapolation", "2", "-coupling_extrapolation_points", "2"], "-coupling_extrapolation_points"),
        ("elastic projection of a St. Venant-Kirchhoff wall", ["-scene", "mms-structure", "-structure_model", "svk", "-structure_initial_projection"], "-structure_initial_projection"),
        ("unknown structure model", ["-scene", "mms-structure", "-structure_model", "neo-hookean"], "-structure_model"),
        ("zero relaxation", ["-scene", "mms-stokes", "-coupling", "dn", "-coupling_omega", "0"], "-coupling_omega"),
        ("too many structure ranks", ["-scene", "mms-stokes", "-structure_ranks", "3"], "-structure_ranks"),
        ("negative Tikhonov weight", ["-scene", "mms-stokes", "-coupling_tikhonov", "-1"], "-coupling_tikhonov"),
        ("zero coupling tolerance", ["-scene", "mms-stokes", "-coupling_tol", "0"], "-coupling_tol"),
        ("relaxed descent without Tikhonov", ["-scene", "mms-stokes", "-tao_type", "sdrelaxed"], "-coupling_tikhonov"),
        ("restart from a file that is not HDF5", CHANNEL + ["-restart", empty_h5], "not an HDF5 file"),
        ("restart from a missing file", CHANNEL + ["-restart", os.path.join(d, "nosuch.h5")], "-restart"),
        ("restart with another dt", CHANNEL + ["-t_final", "0.001", "-dt", "5e-5", "-restart", checkpoint], "dt"),
        ("restart of another mesh", CHANNEL + ["-t_final", "0.002", "-refine", "1", "-restart", checkpoint], "-restart"),
        ("restart with a partitioned method", CHANNEL + ["-t_final", "0.002", "-coupling", "iqnils", "-restart", checkpoint], "-coupling opt"),
        ("restart past the end", CHANNEL + ["-t_final", "0.0001", "-restart", checkpoint], "-restart"),
        ("BDF2 with a backward-Euler forcing", F + ["-mms_discrete_time", "-fluid_time_order", "2"], "-mms_discrete_time"),
        ("third-order fluid time scheme", F + ["-fluid_time_order", "3"], "-fluid_time_order"),
        ("zero -dt_min", F + ["-dt_min", "0"], "-dt_min"),
        ("negative -dt_min", F + ["-dt_min", "-1e-3"], "-dt_min"),
        ("-dt_min above -dt", F + ["-dt", "0.1", "-dt_min", "0.2"], "-dt_min"),
        ("unknown Turek-Hron case", TUREK + ["-turek_case", "fsi4"], "-turek_case"),
        ("negative inflow velocity", TUREK + ["-turek_case", "cfd1", "-turek_mean_velocity", "-1"], "-turek_mean_velocity"),
        ("steady fluid on a moving mesh", TUREK + ["-turek_case", "fsi1", "-fluid_steady"], "-fluid_steady"),
        ("negative mesh stiffening", TUREK + ["-turek_case", "fsi1", "-mesh_motion_stiffening", "-1"], "-mesh_motion_stiffening"),
        ("unknown mesh motion", CHANNEL + ["-mesh_motion", "biharmonc"], "-mesh_motion. Available options: harmonic elastic biharmonic"),
        ("negative quantities window", TUREK + ["-turek_case", "csm1", "-quantities_window", "-1"], "-quantities_window"),
    ]


@test("bad input: one line, non-zero exit, no summary")
def _():
    problems = []
    cases = bad_input_cases()
    for name, args, token in cases:
        rc, out, err, summary = run(args, tag="bad")
        lines = [l for l in (out + err).splitlines() if l.strip()]
        why = []
        if rc == 0: why.append("exit 0")
        if summary is not None: why.append("summary.json written")
        if "PETSC ERROR" in out + err: why.append("PETSc traceback")
        if len(lines) != 1: why.append("%d lines" % len(lines))
        elif token not in lines[0] or not lines[0].startswith("fsiopt: error:"): why.append("message '%s' lacks '%s'" % (lines[0], token))
        if why: problems.append("%s: %s" % (name, ", ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d cases" % len(cases)


@test("-help lists scenes and options")
def _():
    # errors="replace": PETSc 3.18 prints an uninitialized buffer as the default of
    # -<prefix>dm_plex_boundary_label in DMPlex's own -help lines.
    p = subprocess.run([FSIOPT, "-help", "-scene", "mms-fluid"], cwd=ROOT, env=ENV, capture_output=True, text=True,
                       errors="replace", timeout=60)
    assert p.returncode == 0, "exit %d" % p.returncode
    for opt in ["-scene", "-coupling", "-refine", "-dt", "-t_start", "-t_final", "-output_dir", "-fluid_density",
                "-fluid_viscosity", "-fluid_model", "-mms_discrete_time", "-write_fields", "-write_fields_interval",
                "-fluid_rhs_rtol", "-fluid_extrapolate"]:
        assert opt in p.stdout, "%s not in -help" % opt
    # a coupled moving-mesh scene with a partitioned method lists the coupling's options too
    p = subprocess.run([FSIOPT, "-help", "-options_file", "options/channel2d.yaml", "-coupling", "iqnils"], cwd=ROOT, env=ENV,
                       capture_output=True, text=True, errors="replace", timeout=60)
    assert p.returncode == 0, "exit %d" % p.returncode
    for opt in ["-coupling_domain", "-coupling_predictor", "-coupling_mesh_extrapolate", "-coupling_extrapolation",
                "-coupling_extrapolation_points",
                "-coupling_omega", "-coupling_rtol", "-coupling_atol", "-coupling_iqn_reuse", "-mesh_motion",
                "-channel_inlet_amplitude", "-fluid_backflow_stabilization", "-structure_model"]:
        assert opt in p.stdout, "%s not in -help of channel2d with -coupling iqnils" % opt
    p = subprocess.run([FSIOPT, "-help"] + TUREK, cwd=ROOT, env=ENV, capture_output=True, text=True, errors="replace", timeout=60)
    assert p.returncode == 0, "exit %d" % p.returncode
    for opt in ["-turek_case", "-turek_mean_velocity", "-turek_ramp_time", "-turek_gravity", "-turek_gravity_ramp",
                "-quantities_window", "-checkpoint_every", "-checkpoint_file", "-restart", "-fluid_steady",
                "-mesh_motion_stiffening", "-mesh_motion_incremental", "-dt_min", "-fluid_time_order",
                "-coupling_explicit_jacobian_rebuild_its"]:
        assert opt in p.stdout, "%s not in -help of turek-hron" % opt
    return ""


if __name__ == "__main__":
    t0 = time.time()
    # arguments: run only the tests whose names contain one of them (all without)
    for t in TESTS:
        if len(sys.argv) == 1 or any(a in t.__name__ for a in sys.argv[1:]):
            t()
    shutil.rmtree(WORK, ignore_errors=True)
    passed, failed = results.count(True), results.count(False)
    print("total time %.0fs" % (time.time() - t0))
    print("%d passed, %d failed" % (passed, failed))
    sys.exit(1 if failed else 0)
