"""Single-physics solvers: spatial and temporal rates of the fluid and the structure on
manufactured solutions, St. Venant-Kirchhoff (tangent, Newton, small-load limit), the
body forces, 2 ranks = 1 rank."""
import math, os

from harness import (FLUID_SPACE, SVK, WORK, check_rates, fail_text, out_dir, read_probes, run, solve,  # noqa: F401
                     test)


@test("fluid (Q2,Q1) spatial rates", quick=True)
def test_fluid_q2q1_spatial_rates():
    errs = [solve(FLUID_SPACE + ["-refine", str(r)])["errors"] for r in range(3)]
    return check_rates(errs, {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("fluid (P2,P1) gmsh spatial rates")
def test_fluid_p2p1_gmsh_spatial_rates():
    errs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_dm_plex_filename", "meshes/square.msh"])["errors"] for r in range(3)]
    return check_rates(errs, {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("fluid (Q1,Q1) + pressure stabilization spatial rates")
def test_fluid_q1q1_stabilized_spatial_rates():
    errs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_velocity_degree", "1", "-fluid_pressure_degree", "1",
                                 "-fluid_pressure_stabilization", "0.1"])["errors"] for r in (1, 2, 3)]
    return check_rates(errs, {"u_L2": 1.8, "u_H1": 0.9, "p_L2": 1.3})


@test("stokes (Q2,Q1) spatial rates, one factorization")
def test_stokes_spatial_rates_one_factorization():
    runs = [solve(FLUID_SPACE + ["-refine", str(r), "-fluid_model", "stokes"]) for r in range(3)]
    for s in runs:
        assert s["factorizations"]["fluid"] == 1, "Stokes factored %d times" % s["factorizations"]["fluid"]
    return check_rates([s["errors"] for s in runs], {"u_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8})


@test("structure Q2 spatial rates", quick=True)
def test_structure_q2_spatial_rates():
    errs = [solve(["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001",
                   "-refine", str(r)])["errors"] for r in range(3)]
    return check_rates(errs, {"eta_L2": 2.8, "eta_H1": 1.8})


@test("structure P2 gmsh spatial rates")
def test_structure_p2_gmsh_spatial_rates():
    errs = [solve(["-scene", "mms-structure", "-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001",
                   "-refine", str(r), "-structure_dm_plex_filename", "meshes/wall.msh"])["errors"] for r in range(3)]
    return check_rates(errs, {"eta_L2": 2.8, "eta_H1": 1.8})


@test("SVK: Q2 spatial and midpoint temporal rates")
def test_svk_spatial_and_midpoint_rates():
    space = [solve(SVK + ["-dt", "1e-4", "-t_start", "0.5", "-t_final", "0.5001", "-refine", str(r)])["errors"] for r in range(3)]
    time_ = [solve(SVK + ["-structure_time_order", "2", "-t_start", "0.5", "-t_final", "1", "-dt", str(dt), "-refine", "2"])["errors"]
             for dt in (0.1, 0.05, 0.025)]
    return "space: %s; time: %s" % (check_rates(space, {"eta_L2": 2.8, "eta_H1": 1.8}), check_rates(time_, {"eta_L2": 1.8, "eta_H1": 1.7}))


ROUND_OFF = 1e-13   # of the first residual: below it a residual says nothing of Newton's order


@test("SVK: Jacobian = finite differences, Newton quadratic", quick=True)
def test_svk_jacobian_and_newton_order():
    # one step of dt = 0.5 on the coarse mesh: the stiffness, not the mass, dominates the
    # Jacobian, and the manufactured displacement's gradient is of order one
    rc, stdout, err, _ = run(SVK + ["-refine", "0", "-t_start", "0.5", "-dt", "0.5", "-t_final", "1",
                                    "-structure_snes_test_jacobian", "-structure_snes_monitor"], tag="svk-jac")
    assert rc == 0, fail_text(rc, stdout, err)
    fd = [float(l.split("=")[1].split(",")[0]) for l in stdout.splitlines() if l.strip().startswith("||J - Jfd||_F/||J||_F =")]
    norms = [float(l.split()[-1]) for l in stdout.splitlines() if "SNES Function norm" in l]
    assert fd and max(fd) <= 1e-6, "||J - Jfd||/||J|| = %s" % fd
    # the order log(r_{k+1}/r_k) / log(r_k/r_{k-1}) of every iteration from the one whose
    # residual is 1e-2 of the first (Newton's local regime) while r_{k+1} is above round-off:
    # the smallest of them, not one pair
    orders = [math.log(norms[k + 1] / norms[k]) / math.log(norms[k] / norms[k - 1])
              for k in range(1, len(norms) - 1) if norms[k] <= 1e-2 * norms[0] and norms[k + 1] > ROUND_OFF * norms[0]]
    assert len(orders) >= 2, "too few iterations in Newton's local regime: residuals %s" % norms
    assert min(orders) >= 1.8, "Newton residuals %s: orders %s" % (norms, ["%.2f" % o for o in orders])
    return "||J - Jfd||/||J|| <= %.1e at %d states, Newton orders %s (min %.2f; %d its)" % (
        max(fd), len(fd), " ".join("%.2f" % o for o in orders), min(orders), len(norms) - 1)


@test("SVK under a small load = linear wall to second order")
def test_svk_small_load_is_linear():
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


@test("fluid backward Euler temporal rate", quick=True)
def test_fluid_backward_euler_rate():
    errs = [solve(["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "1", "-dt", str(dt), "-refine", "1"])["errors"]
            for dt in (0.1, 0.05, 0.025)]
    return check_rates(errs, {"u_L2": 0.9})


@test("fluid BDF2 temporal rate; its restart continues exactly")
def test_fluid_bdf2_rate_and_restart():
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


@test("structure first-order temporal rate", quick=True)
def test_structure_first_order_rate():
    runs = [solve(["-scene", "mms-structure", "-structure_time_order", "1", "-t_start", "0.5", "-t_final", "1",
                   "-dt", str(dt), "-refine", "1"]) for dt in (0.02, 0.01, 0.005)]
    assert all(s["factorizations"]["structure"] == 1 for s in runs), "structure factored more than once per run"
    return check_rates([s["errors"] for s in runs], {"eta_L2": 0.9})


@test("structure midpoint temporal rate, one factorization")
def test_structure_midpoint_rate_one_factorization():
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


def surface_force_errors(args):
    """mms-fluid's bottom side: |volume-weighted - exact|, |surface integral - exact| and
    |surface - volume| of drag and lift, at the run's last step"""
    out = out_dir("surface-force")
    solve(["-scene", "mms-fluid", "-probes_surface_force"] + args, out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    shead, srows = read_probes(os.path.join(out, "force_surface.csv"))
    errors = {}
    for name in ("drag", "lift"):
        volume, surface = rows[-1][head.index(name)], srows[-1][shead.index(name + "_surface")]
        errors[name + "_surface"] = abs(surface)
        errors[name + "_difference"] = abs(surface - volume)
    return errors


@test("surface force: the boundary integral of sigma n converges at order 2 on a moving mesh (BDF2) and meets the "
      "volume-weighted force to that order")
def test_surface_force():
    # dt = 0.0025 leaves the spatial error dominant up to refinement 3 (the volume-weighted
    # drag's time error is 7e-6 there, the surface drag's spatial one 5.5e-5)
    moving = [surface_force_errors(["-t_start", "0.5", "-t_final", "0.55", "-dt", "0.0025", "-refine", str(r),
                                    "-mms_mesh_motion", "0.1", "-fluid_time_order", "2"]) for r in (1, 2, 3)]
    floors = {"drag_surface": 1.8, "lift_surface": 1.8, "drag_difference": 1.8, "lift_difference": 1.8}
    return check_rates(moving, floors)


@test("2 ranks reproduce 1 rank: fluid", quick=True)
def test_two_ranks_fluid():
    return same_errors(FLUID_SPACE + ["-refine", "1"])


@test("2 ranks reproduce 1 rank: structure")
def test_two_ranks_structure():
    return same_errors(["-scene", "mms-structure", "-t_start", "0.5", "-t_final", "0.6", "-dt", "0.05", "-refine", "1"])


def force_errors(args):
    """|drag| and |lift| of mms-fluid's bottom side: the discrete force minus the exact one."""
    out = out_dir("force")
    solve(["-scene", "mms-fluid"] + args, out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return {"drag": abs(rows[-1][head.index("drag")]), "lift": abs(rows[-1][head.index("lift")])}


@test("body force: volume-weighted drag, lift converge (space, time, moving mesh)")
def test_body_force_rates():
    # refinements 2, 3, 4: from refinement 1 to 2 the lift's rate is 2.71, then 2.92, 2.94
    # (the drag's 2.98, 2.97, 2.98): the pairs from 2 on are in the asymptotic range
    space = [force_errors(FLUID_SPACE[2:] + ["-refine", str(r)]) for r in range(2, 5)]
    time_args = ["-t_start", "0.5", "-t_final", "0.6", "-refine", "2", "-mms_mesh_motion", "0.1"]
    moving = [force_errors(time_args + ["-dt", dt]) for dt in ("0.02", "0.01", "0.005")]
    # BDF2's lift error is at the spatial floor already at dt = 0.02
    bdf2 = [force_errors(time_args + ["-dt", dt, "-fluid_time_order", "2"]) for dt in ("0.02", "0.01", "0.005")]
    return "space " + check_rates(space, {"drag": 2.8, "lift": 2.8}) + "; dt on a moving mesh (backward Euler) " + \
        check_rates(moving, {"drag": 0.9, "lift": 0.9}) + "; with BDF2 " + check_rates(bdf2, {"drag": 1.8})
