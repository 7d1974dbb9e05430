"""Coupled problems: the derivatives (adjoint identity, Taylor remainder), Gauss-Newton,
the coupled rates, the parallel layouts, the explicit Jacobian and the inner solvers (the
step's start and tolerance: test_coupling_start.py; the partitioned methods:
test_partitioned.py)."""
import csv, math, os

from harness import (CHANNEL, NS_STEP, SHORT, WORK, adjoint_difference, check_rates, difference_to_largest,  # noqa: F401
                     fail_text, krylov_iterations, last_rows, out_dir, printed, probes_difference, read_probes, run,
                     same_file, solve, stage_count, test, ITERATIVE_ILU, SOLVER_FILES)


# LU refactored at every Gauss-Newton iteration: exact products, as the iterative solvers'
# fresh operators under a lagged preconditioner (-coupling_lag_preconditioner_only) give them
EXACT_LU = ["-coupling_jacobian_lag", "1"]


def adjoint_cases(nproc):
    worst, done = 0.0, 0
    for control in ("traction", "convective"):
        for order in ("1", "2"):
            for velocity in ("scheme", "difference"):
                args = SHORT + ["-coupling_control", control, "-structure_time_order", order, "-coupling_velocity", velocity,
                                "-coupling_test_adjoint", "-t_final", "0.51"]
                if nproc == 2:
                    args += ["-structure_ranks", "1"]
                rc, stdout, err, _ = run(args, nproc=nproc, tag="adjoint")
                assert rc == 0, fail_text(rc, stdout, err)
                rel = adjoint_difference(stdout)
                assert rel <= 1e-10, "%s, order %s, %s: relative difference %.2e" % (control, order, velocity, rel)
                worst = max(worst, rel)
                done += 1
    return "%d cases, worst %.1e" % (done, worst)


@test("adjoint: <Jh,r> = <h,J^T r>, 1 rank", quick=True)
def test_adjoint_identity_one_rank():
    return adjoint_cases(1)


@test("adjoint: <Jh,r> = <h,J^T r>, fluid | structure")
def test_adjoint_identity_split_ranks():
    return adjoint_cases(2)


@test("the adjoint test checks the run's own Jacobian and leaves the run as it was: tube3d, two steps with and "
      "without -coupling_test_adjoint, the same history and probes to the last digit", quick=True)
def test_adjoint_check_leaves_run():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0002"]
    plain, checked = out_dir("tube3d-plain"), out_dir("tube3d-checked")
    solve(args, out=plain)
    rc, stdout, err, summary = run(args + ["-coupling_test_adjoint"], out=checked)
    assert rc == 0 and summary, fail_text(rc, stdout, err)
    adjoint = adjoint_difference(stdout)
    assert adjoint <= 1e-10, "adjoint identity: relative difference %.2e" % adjoint
    for name in ("history.csv", "probes.csv"):
        assert same_file(os.path.join(plain, name), os.path.join(checked, name)), \
            "%s differs with -coupling_test_adjoint" % name
    return "adjoint %.1e; %d Gauss-Newton iterations either way, history and probes identical" % (
        adjoint, summary["coupling_iterations"])


FIELD_SPLIT = ["-fluid_ksp_type", "fgmres", "-fluid_ksp_rtol", "1e-10", "-fluid_pc_type", "fieldsplit",
               "-fluid_pc_fieldsplit_type", "schur", "-fluid_pc_fieldsplit_schur_fact_type", "full",
               "-fluid_pc_fieldsplit_schur_precondition", "selfp", "-fluid_fieldsplit_velocity_ksp_type", "preonly",
               "-fluid_fieldsplit_velocity_pc_type", "gamg", "-fluid_fieldsplit_pressure_ksp_type", "preonly",
               "-fluid_fieldsplit_pressure_pc_type", "jacobi"]


def preconditioner_applications(log, stage):
    """PCApply count per FluidLinSolve in a -log_view stage (by its name)"""
    return stage_count(log, stage, "PCApply") / stage_count(log, stage, "FluidLinSolve")


@test("iterative fluid (FGMRES, Schur field split, GAMG on the velocity): the split's options are read, the adjoint "
      "identity holds to 10 x the Krylov tolerance, the transposed solves need no more iterations than the forward "
      "ones, the errors are the LU run's (1 and 2 ranks; 1 rank with -fluid_matfree)")
def test_field_split_fluid():
    details = []
    for nproc, matfree in ((1, []), (2, []), (1, ["-fluid_matfree"])):
        reference = solve(SHORT + ["-t_final", "0.51"], nproc=nproc)
        log = os.path.join(WORK, "field-split-%d%s.log" % (nproc, "-matfree" if matfree else ""))
        # cgls: its forward and transposed products solve to the same tolerance (gmres, the default
        # with an iterative fluid, relaxes the forward ones and solves no transposed one)
        rc, stdout, err, summary = run(SHORT + FIELD_SPLIT + matfree + ["-coupling_inner", "cgls",
                                                                        "-coupling_test_adjoint", "-t_final", "0.51",
                                                                        "-log_view", ":" + log], nproc=nproc,
                                       tag="field-split")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        # PETSc 3.18's field split applies no true transpose: 7.8 x the forward iterations before the
        # transposed solves got a preconditioner of their own (src/common/fem_linear_solve.c)
        forward, transposed = preconditioner_applications(log, "Sensitivity"), preconditioner_applications(log, "Adjoint")
        assert transposed <= 1.5 * forward, "%d rank(s): %.1f preconditioner applications per transposed solve, " \
            "%.1f per forward one" % (nproc, transposed, forward)
        rel = adjoint_difference(stdout)
        assert rel <= 1e-9, "%d rank(s): adjoint identity %.2e, above 10 x the Krylov tolerance 1e-10" % (nproc, rel)
        worst = max(abs(summary["errors"][k] - v) / v for k, v in reference["errors"].items())
        assert worst <= 1e-8, "%d rank(s): errors %s, LU's %s" % (nproc, summary["errors"], reference["errors"])
        details.append("%d rank%s%s: adjoint %.1e, %.1f/%.1f its per forward/transposed solve, errors within %.1e of "
                       "LU's" % (nproc, "s" if nproc > 1 else "", " matrix-free" if matfree else "", rel, forward,
                                 transposed, worst))
    return "; ".join(details)


@test("options/solvers: iterative fluid, structure and mesh motion solves (field split, CG + GAMG) keep the adjoint "
      "identity to 10 x the Krylov tolerance and the LU run's errors (mms-ns) and probes (channel2d), 1 and 2 ranks")
def test_solver_option_files():
    details = []
    for nproc in (1, 2):
        files = SOLVER_FILES["fluid-schur-gamg"] + SOLVER_FILES["structure-cg-gamg"]
        reference = solve(SHORT + ["-t_final", "0.51"], nproc=nproc)
        rc, stdout, err, summary = run(SHORT + files + ["-coupling_test_adjoint", "-t_final", "0.51"], nproc=nproc,
                                       tag="solver-files")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        adjoint = adjoint_difference(stdout)
        assert adjoint <= 1e-9, "%d rank(s), mms-ns: adjoint test %.2e" % (nproc, adjoint)
        worst = max(abs(summary["errors"][k] - v) / v for k, v in reference["errors"].items())
        assert worst <= 1e-8, "%d rank(s): errors %s, LU's %s" % (nproc, summary["errors"], reference["errors"])
        # channel2d's wall and mesh move: the structure and mesh-motion files
        files = SOLVER_FILES["structure-cg-gamg"] + SOLVER_FILES["mesh-cg-gamg"]
        lu_out, it_out = out_dir("solver-files-lu"), out_dir("solver-files-it")
        solve(CHANNEL + ["-t_final", "0.0005"], nproc=nproc, out=lu_out)
        rc, stdout, err, summary = run(CHANNEL + files + ["-t_final", "0.0005", "-coupling_test_adjoint"], nproc=nproc,
                                       out=it_out)
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        channel_adjoint = adjoint_difference(stdout)
        assert channel_adjoint <= 1e-9, "channel2d: adjoint test %.2e" % channel_adjoint
        _, lu = read_probes(os.path.join(lu_out, "probes.csv"))
        _, it = read_probes(os.path.join(it_out, "probes.csv"))
        diff = difference_to_largest(it, lu)
        assert diff <= 1e-6, "channel2d: probes %.2e from LU's" % diff
        details.append("%d rank%s: adjoint %.1e (mms-ns) %.1e (channel2d), errors within %.1e, probes within %.1e"
                       % (nproc, "s" if nproc > 1 else "", adjoint, channel_adjoint, worst, diff))
    return "; ".join(details)


@test("-coupling_inner defaults to gmres where the fluid's solves iterate, chord where they factor: tube3d with the "
      "iterative solver files, three steps, is then the gmres run byte for byte, with at most 0.8 x the fluid linear "
      "solves of cgls (both preconditioned by the probed J0) at the same Gauss-Newton iterations")
def test_inner_default_iterative():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0003"]
    runs = {}
    for name, extra in (("default", []), ("gmres", ["-coupling_inner", "gmres"]), ("cgls", ["-coupling_inner", "cgls"])):
        out = out_dir("inner-%s" % name)
        runs[name] = (solve(args + ITERATIVE_ILU + extra, out=out), out)
    lu = solve(args)
    default, gmres, cgls = (runs[n][0] for n in ("default", "gmres", "cgls"))
    assert default["options"]["-coupling_inner"] == "gmres" and lu["options"]["-coupling_inner"] == "chord", \
        "inner: %s with the iterative files, %s with LU" % (default["options"]["-coupling_inner"],
                                                           lu["options"]["-coupling_inner"])
    assert same_file(os.path.join(runs["default"][1], "probes.csv"), os.path.join(runs["gmres"][1], "probes.csv")), \
        "the default's probes differ from the gmres run's"
    assert gmres["coupling_iterations"] == cgls["coupling_iterations"] and \
        gmres["fluid_linear_solves"] <= 0.8 * cgls["fluid_linear_solves"], \
        "gmres %d Gauss-Newton iterations, %d fluid linear solves; cgls %d, %d" % (
            gmres["coupling_iterations"], gmres["fluid_linear_solves"], cgls["coupling_iterations"],
            cgls["fluid_linear_solves"])
    return "default gmres (LU: chord); %d Gauss-Newton iterations both; fluid linear solves gmres %d, cgls %d" % (
        gmres["coupling_iterations"], gmres["fluid_linear_solves"], cgls["fluid_linear_solves"])


@test("tube3d with the iterative solver files for small time steps (field split with ILU(0) on the velocity, CG + "
      "ILU(0) on the wall, CG + GAMG on the mesh): "
      "the adjoint identity to 10 x the Krylov tolerance, the Gauss-Newton iterations of LU refactored at every "
      "iteration (the products exact in both) and probes within 10 x the coupling tolerance (both at 1e-6), 1 and 2 "
      "ranks")
def test_tube3d_iterative():
    # at the scene's -coupling_tol 1e-4 the two runs may stop at jumps anywhere below it, and a probe
    # moves with the jump it stopped at (about 4 x here); at 1e-6 the probes must agree far below 1e-4
    tolerance = 1e-6
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0002", "-coupling_inner", "gmres",
            "-coupling_test_adjoint", "-coupling_tol", "%g" % tolerance]
    files = ITERATIVE_ILU
    details = []
    for nproc in (1, 2):
        lu_out, it_out = out_dir("tube3d-lu-%d" % nproc), out_dir("tube3d-iterative-%d" % nproc)
        lu = solve(args + EXACT_LU, nproc=nproc, out=lu_out)
        rc, stdout, err, summary = run(args + files, nproc=nproc, out=it_out)
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        adjoint = adjoint_difference(stdout)
        assert adjoint <= 1e-9, "%d rank(s): adjoint identity %.2e, above 10 x the Krylov tolerance 1e-10" % (
            nproc, adjoint)
        assert summary["coupling_iterations"] == lu["coupling_iterations"], \
            "%d rank(s): %d Gauss-Newton iterations, LU %d" % (nproc, summary["coupling_iterations"],
                                                              lu["coupling_iterations"])
        _, a = read_probes(os.path.join(lu_out, "probes.csv"))
        _, b = read_probes(os.path.join(it_out, "probes.csv"))
        diff = difference_to_largest(b, a)
        assert diff <= 10 * tolerance, "%d rank(s): probes %.2e from LU's, above 10 x the coupling tolerance" % (
            nproc, diff)
        details.append("%d rank%s: adjoint %.1e, %d GN its as LU, probes within %.1e" % (
            nproc, "s" if nproc > 1 else "", adjoint, lu["coupling_iterations"], diff))
    return "; ".join(details)


@test("the fluid's preconditioner lagged, not its operator (-coupling_lag_preconditioner_only, on with a Krylov fluid "
      "solver): tube3d with the iterative solver files, five steps: the Gauss-Newton iterations of LU refactored at "
      "every iteration and its jumps after each step's first iteration (1 %); the operator lagged too: more "
      "iterations")
def test_lagged_preconditioner_only():
    # the first jumps compare the products: every Krylov solve runs to the tolerance, not to a
    # forcing term that lets each preconditioner stop at its own linearized jump
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0005", "-coupling_inner", "gmres",
            "-coupling_snes_ksp_ew", "false"]
    exact_out = out_dir("lagged-pc-exact")
    exact = solve(args + EXACT_LU, out=exact_out)
    found = {}
    for name, extra in (("default", []), ("operator lagged", ["-coupling_lag_preconditioner_only", "0"])):
        out = out_dir("lagged-pc-%s" % name.split()[0])
        rc, stdout, err, summary = run(args + ITERATIVE_ILU + extra, out=out)
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        found[name] = (summary, out)
    (default, out), (lagged, _) = found["default"], found["operator lagged"]
    assert default["coupling_iterations"] == exact["coupling_iterations"], \
        "Gauss-Newton iterations %d, exact LU %d" % (default["coupling_iterations"], exact["coupling_iterations"])
    first = {}
    for o in (exact_out, out):
        for r in csv.DictReader(open(os.path.join(o, "history.csv"))):
            if r["iteration"] == "1":
                first.setdefault(int(r["step"]), []).append(float(r["jump"]))
    off = max(abs(b / a - 1) for a, b in first.values())
    assert len(first) == 5 and off <= 0.01, "jumps after the first iterations up to %.1e from exact LU's" % off
    assert lagged["coupling_iterations"] > default["coupling_iterations"], \
        "with the operator lagged %d Gauss-Newton iterations, not more than %d" % (lagged["coupling_iterations"],
                                                                                default["coupling_iterations"])
    return "%d GN as exact LU, first jumps within %.1e of its; %d with the operator lagged" % (
        default["coupling_iterations"], off, lagged["coupling_iterations"])


@test("inexact products (-coupling_inexact_products, GMRES on J), Newton steps and first guesses "
      "(-fluid_newton_ksp_rtol): tube3d "
      "with the iterative solver files, one step: the exact run's Gauss-Newton and GMRES iterations and probes (within "
      "the coupling tolerance, 1e-4), "
      "fewer fluid Krylov iterations with each (at most 0.7 x and 0.8 x those before it)")
def test_inexact_products():
    # one step from rest: the absolute tolerance alone (the relative one would hold this first
    # step to a fraction of a velocity still near zero, and the products to its Krylov tolerance)
    # unpreconditioned: the probed J0's build, whose products have their own tolerance, would
    # dilute the products' relaxation measured here
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0001", "-coupling_inner", "gmres",
            "-coupling_explicit_jacobian", "0", "-coupling_tol_relative", "0", "-fluid_ksp_converged_reason"] + \
        SOLVER_FILES["fluid-schur-gamg"] + SOLVER_FILES["structure-cg-gamg"] + SOLVER_FILES["mesh-cg-gamg"]
    found = {}
    # exact products and exact Newton steps; inexact products; both inexact (the file's
    # -fluid_newton_ksp_rtol)
    for name, extra in (("exact", ["-coupling_inexact_products", "0", "-fluid_newton_ksp_rtol", "0"]),
                        ("products", ["-coupling_inexact_products", "0.01", "-fluid_newton_ksp_rtol", "0"]),
                        ("both", ["-coupling_inexact_products", "0.01"])):
        out = out_dir("inexact-%s" % name)
        rc, stdout, err, summary = run(args + extra, out=out)
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        found[name] = (summary, sum(krylov_iterations(stdout, "fluid")), read_probes(os.path.join(out, "probes.csv"))[1])
    exact, exact_its, a = found["exact"]
    its, diffs = [exact_its], []
    # the products' relaxation removes the most (0.52 x, measured), the Newton steps' tolerance the
    # rest of one step's (0.71 x)
    for name, bound in (("products", 0.7), ("both", 0.8)):
        inexact, inexact_its, b = found[name]
        for key in ("coupling_iterations", "inner_iterations"):
            assert exact[key] == inexact[key], "%s: %s exact, %s %s" % (key, exact[key], inexact[key], name)
        diff = difference_to_largest(b, a)
        # each run stops once its jump is within the coupling tolerance (1e-4): the answers agree to it
        assert diff <= 1e-4, "%s: probes differ by %.2e relative" % (name, diff)
        assert inexact_its <= bound * its[-1], "fluid Krylov iterations: %d (%s), %d before" % (inexact_its, name,
                                                                                             its[-1])
        its.append(inexact_its)
        diffs.append(diff)
    return "%d GN, %d GMRES its; fluid Krylov its %d -> %d (inexact products) -> %d (and Newton steps); probes " \
        "within %.1e" % (exact["coupling_iterations"], exact["inner_iterations"], its[0], its[1], its[2], max(diffs))


@test("recycled products (-coupling_inner_recycle 3, GMRES preconditioned by earlier products): tube3d with the "
      "iterative solver files, six steps: at most 0.9 x the GMRES iterations and products of the unpreconditioned "
      "run, no more Gauss-Newton iterations, the same probes (within 10 x the coupling tolerance); a restart from "
      "step 3 repeats the run byte for byte")
def test_recycled_products():
    args = ["-options_file", "options/tube3d.yaml", "-coupling_inner", "gmres", "-coupling_tol", "1e-6"] + ITERATIVE_ILU
    recycle = ["-coupling_inner_recycle", "3", "-checkpoint_every", "3"]
    found = {}
    # both Krylov solves to the tolerance (the forcing is off by default with recycled products)
    for name, extra in (("plain", ["-t_final", "0.0006", "-coupling_explicit_jacobian", "0", "-coupling_snes_ksp_ew",
                                   "false"]),
                        ("recycled", ["-t_final", "0.0006"] + recycle),
                        ("first half", ["-t_final", "0.0003"] + recycle)):
        out = out_dir("recycle-%s" % name.split()[0])
        found[name] = (solve(args + extra, out=out), out)
    (plain, plain_out), (recycled, out) = found["plain"], found["recycled"]
    # 214 of 261 measured (0.82): the recurrence's close starts of steps 4-6 leave fewer
    # iterations for the earlier products to save than the polynomial's far ones (223 of 281)
    for key, name, bound in (("coupling_iterations", "Gauss-Newton", 1.0), ("inner_iterations", "GMRES", 0.9)):
        assert recycled[key] <= bound * plain[key], "%s iterations %d, unpreconditioned %d" % (name, recycled[key],
                                                                                                plain[key])
    # the preconditioner costs no product
    products = [s["linearized_solves"]["forward"] for s in (plain, recycled)]
    assert products[1] <= 0.9 * products[0], "products %d recycled, %d unpreconditioned" % (products[1], products[0])
    diff = difference_to_largest(read_probes(os.path.join(out, "probes.csv"))[1],
                                 read_probes(os.path.join(plain_out, "probes.csv"))[1])
    assert diff <= 1e-5, "probes differ by %.2e relative from the unpreconditioned run's" % diff
    again = out_dir("recycle-restart")
    more = solve(args + ["-t_final", "0.0006"] + recycle +
                 ["-restart", os.path.join(found["first half"][1], "checkpoint.h5")], out=again)
    assert more["first_step"] == 4, "restart at step %s" % more["first_step"]
    assert same_file(os.path.join(out, "probes.csv"), os.path.join(again, "probes.csv")), \
        "the restarted probes differ from the run's by %.1e" % difference_to_largest(
            read_probes(os.path.join(again, "probes.csv"))[1], read_probes(os.path.join(out, "probes.csv"))[1])
    return "GMRES its %d -> %d, products %d -> %d, %d GN (unpreconditioned %d); probes within %.1e; restart = " \
        "the run" % (plain["inner_iterations"], recycled["inner_iterations"], products[0], products[1],
                     recycled["coupling_iterations"], plain["coupling_iterations"], diff)


@test("the last Gauss-Newton step's products (-coupling_inexact_products_last): tube3d with the iterative solver "
      "files and the fluid's operator lagged as LU's factors are, five steps: each step's final jump within 25 % of "
      "the LU run's (the last step's products as loose as the others': twice as far off), LU's Gauss-Newton "
      "iterations")
def test_last_step_products():
    # GMRES on J itself in both (with LU the default would build an explicit J0)
    # the polynomial's starts (the recurrence from 9 controls): every step takes three
    # iterations, the last of which the rule foresees; from the recurrence's closer starts
    # steps 4-5 take two, the second not foreseen (0.014 to 2e-5 in one), and end 17 and 43 %
    # from LU's final jumps, below the tolerance
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0005", "-coupling_inner", "gmres",
            "-coupling_explicit_jacobian", "0", "-coupling_extrapolation_recurrence_from", "9"]
    # the rule predicts linear convergence, which a lagged operator gives (with a fresh one the
    # step from 0.11 to 5e-5 on this level is not foreseen, and needs no sharper products)
    files = ITERATIVE_ILU + ["-coupling_lag_preconditioner_only", "0"]
    lu_out = out_dir("last-products-lu")
    lu = solve(args, out=lu_out)
    lu_jumps = {k: float(r["jump"]) for k, r in last_rows(lu_out).items()}
    found = {}
    for name, extra in (("default", []), ("loose", ["-coupling_inexact_products_last", "0.01"])):
        out = out_dir("last-products-%s" % name)
        rc, stdout, err, summary = run(args + files + extra, out=out)
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        jumps = {k: float(r["jump"]) for k, r in last_rows(out).items()}
        assert sorted(jumps) == sorted(lu_jumps), "steps %s against LU's %s" % (sorted(jumps), sorted(lu_jumps))
        found[name] = (summary, max(abs(jumps[k] / lu_jumps[k] - 1) for k in jumps))
    (default, off), (_, loose_off) = found["default"], found["loose"]
    assert default["coupling_iterations"] == lu["coupling_iterations"], "Gauss-Newton iterations %d, LU %d" % (
        default["coupling_iterations"], lu["coupling_iterations"])
    # ILU's numbering alone moves a final jump by 5-17 % (the preconditioner changes which error
    # the products keep within their tolerance); loose last products move them several times more
    assert off <= 0.25, "final jumps up to %.0f %% from LU's" % (100 * off)
    assert loose_off > 2 * off, "loose last products: final jumps %.0f %% from LU's, not 2 x further than %.0f %%" % (
        100 * loose_off, 100 * off)
    return "%d GN as LU; final jumps within %.1f %% of LU's (%.0f %% with the last products loose)" % (
        lu["coupling_iterations"], 100 * off, 100 * loose_off)


def taylor_ratios(stdout):
    return [float(l.split()[-1]) for l in printed(stdout, "Taylor test:") if "ratio" in l]


@test("Taylor remainder is second order (mms-ns)", quick=True)
def test_taylor_remainder_second_order():
    rc, stdout, err, _ = run(SHORT + ["-coupling_test_taylor", "-t_final", "0.51"], tag="taylor")
    assert rc == 0, fail_text(rc, stdout, err)
    ratios = taylor_ratios(stdout)
    assert len(ratios) >= 4, "too few Taylor lines: %s" % stdout[-300:]
    assert all(3.8 <= r <= 4.2 for r in ratios), "ratios %s" % ratios
    return "ratios " + " ".join("%.3f" % r for r in ratios)


@test("Taylor remainder is second order along the start's change from the last control (mms-ns, "
      "-coupling_test_taylor_step 3), and first order on tube3d's moving mesh, where J leaves out the shape derivative",
      quick=True)
def test_taylor_along_the_start():
    rc, stdout, err, _ = run(SHORT + ["-coupling_test_taylor", "-coupling_test_taylor_step", "3", "-t_final", "0.53"],
                             tag="taylor-step")
    assert rc == 0, fail_text(rc, stdout, err)
    ratios = taylor_ratios(stdout)
    assert len(ratios) == 5 and all(3.8 <= r <= 4.2 for r in ratios), "mms-ns, step 3: ratios %s" % ratios
    moving = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0003", "-coupling_test_taylor",
              "-coupling_test_taylor_step", "3", "-coupling_test_taylor_t0", "1e-3", "-fluid_rhs_rtol", "1e-13",
              "-fluid_snes_rtol", "1e-13"]
    rc, stdout, err, _ = run(moving, tag="taylor-step-moving")
    assert rc == 0, fail_text(rc, stdout, err)
    first = taylor_ratios(stdout)
    assert len(first) == 5 and all(1.8 <= r <= 2.2 for r in first), "tube3d, step 3: ratios %s" % first
    return "mms-ns " + " ".join("%.3f" % r for r in ratios) + "; tube3d " + " ".join("%.3f" % r for r in first)


@test("the Taylor test on a moving mesh with the iterative files leaves the run going: tube3d, two steps, the mesh "
      "motion's warm-started CG back at a wall at rest; the same Gauss-Newton iterations and probes within 1e-4 "
      "of the run without it, relative to their largest (its solves start from other guesses)", quick=True)
def test_taylor_check_leaves_run():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0002"] + ITERATIVE_ILU
    plain, checked = out_dir("tube3d-taylor-plain"), out_dir("tube3d-taylor-checked")
    base = solve(args, out=plain)
    rc, stdout, err, summary = run(args + ["-coupling_test_taylor"], out=checked)
    assert rc == 0 and summary, fail_text(rc, stdout, err)
    ratios = taylor_ratios(stdout)
    assert len(ratios) == 5, "Taylor lines: %s" % ratios
    assert summary["coupling_iterations"] == base["coupling_iterations"], "GN iterations %d with the test, %d without" % (
        summary["coupling_iterations"], base["coupling_iterations"])
    diff = difference_to_largest(read_probes(os.path.join(checked, "probes.csv"))[1],
                                 read_probes(os.path.join(plain, "probes.csv"))[1])
    assert diff <= 1e-4, "probes differ by %.2e with -coupling_test_taylor" % diff
    return "%d Gauss-Newton iterations either way, probes within %.1e" % (summary["coupling_iterations"], diff)


def first_jumps(out):
    """{step: the jump after the step's first iteration}"""
    return {int(r["step"]): float(r["jump"]) for r in csv.DictReader(open(os.path.join(out, "history.csv")))
            if r["iteration"] == "1"}


@test("Newton on differences of F (-coupling_snes_mf_operator), which carry the shape derivative J leaves out: "
      "tube3d level 1, six steps, the fluid to 1e-13; its first iteration lands 1.5x or more closer than J's in steps "
      "4-6 (small moves, where that derivative is what J misses), within 30 % of J's in steps 1-3 (large moves, where "
      "the nonlinearity dominates), and on the same probes within 1e-4 of their largest")
def test_newton_on_differences_of_F():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0006", "-fluid_rhs_rtol", "1e-13",
            "-fluid_snes_rtol", "1e-13", "-fluid_newton_ksp_rtol", "1e-10", "-mesh_ksp_rtol", "1e-12"] + ITERATIVE_ILU
    with_J, with_differences = out_dir("tube3d-newton-J"), out_dir("tube3d-newton-differences")
    solve(args, out=with_J)
    solve(args + ["-coupling_snes_mf_operator", "-coupling_mat_mffd_err", "1e-6"], out=with_differences)
    J, D = first_jumps(with_J), first_jumps(with_differences)
    assert sorted(J) == sorted(D) == list(range(1, 7)), "steps %s and %s" % (sorted(J), sorted(D))
    gain = {k: J[k] / D[k] for k in J}
    assert all(gain[k] >= 1.5 for k in (4, 5, 6)), "first jumps J / differences, steps 4-6: %s" % gain
    assert all(0.7 <= gain[k] <= 1.3 for k in (1, 2, 3)), "first jumps J / differences, steps 1-3: %s" % gain
    diff = difference_to_largest(read_probes(os.path.join(with_differences, "probes.csv"))[1],
                                 read_probes(os.path.join(with_J, "probes.csv"))[1])
    assert diff <= 1e-4, "probes differ by %.2e" % diff
    return "first jumps J / differences " + " ".join("%.2f" % gain[k] for k in sorted(gain)) + \
        ", probes within %.1e" % diff


@test("SVK: adjoint identity and second-order Taylor remainder (mms-ns)")
def test_svk_adjoint_and_taylor():
    rc, stdout, err, _ = run(SHORT + ["-structure_model", "svk", "-structure_time_order", "2", "-coupling_test_adjoint",
                                      "-coupling_test_taylor", "-t_final", "0.51"], tag="svk-adjoint")
    assert rc == 0, fail_text(rc, stdout, err)
    adjoint = adjoint_difference(stdout)
    ratios = taylor_ratios(stdout)
    assert adjoint <= 1e-10, "adjoint test %.2e" % adjoint
    assert len(ratios) >= 4 and all(3.8 <= r <= 4.2 for r in ratios), "Taylor ratios %s" % ratios
    return "adjoint %.1e, Taylor ratios %s" % (adjoint, " ".join("%.3f" % r for r in ratios))


@test("Gauss-Newton: one iteration per step, ||F|| <= 1e-10 (linear mms-stokes)", quick=True)
def test_gauss_newton_exact_on_linear_stokes():
    # Stokes and a linear wall on fixed domains: F is affine in the control, so the
    # Gauss-Newton model is exact and one iteration solves each step (to CG's tolerance)
    out = os.path.join(WORK, "gn")
    s = solve(["-options_file", "options/mms-stokes.yaml"], out=out)
    last = last_rows(out)
    assert len(last) == s["steps"], "history has %d steps of %d" % (len(last), s["steps"])
    assert s["coupling_iterations"] == s["steps"], "%d Gauss-Newton iterations for %d steps" % (s["coupling_iterations"], s["steps"])
    for step, r in last.items():
        F = math.sqrt(2 * float(r["objective"]))
        assert int(r["iteration"]) == 1 and F <= 1e-10 and float(r["jump"]) <= 1e-10, "step %d: %s" % (step, r)
    assert s["factorizations"] == {"fluid": 1, "structure": 1}, "factorizations %s" % s["factorizations"]
    assert s["converged"] is True and s["max_interface_jump"] <= 1e-10
    return "%d GN iterations for %d steps, %.1f CG its per GN it, max jump %.1e" % (
        s["coupling_iterations"], s["steps"], s["inner_iterations"] / s["coupling_iterations"], s["max_interface_jump"])


@test("mms-ns one-step spatial rates, <= 1 fluid factorization per GN it")
def test_mms_ns_spatial_rates():
    runs = [solve(NS_STEP + ["-refine", str(r)]) for r in range(1, 4)]
    for s in runs:
        assert s["factorizations"]["structure"] == 1, "structure factored %d times" % s["factorizations"]["structure"]
        assert s["factorizations"]["fluid"] <= s["coupling_iterations"] + 1, "fluid factored %d times for %d GN its" % (
            s["factorizations"]["fluid"], s["coupling_iterations"])
    return check_rates([s["errors"] for s in runs], {"u_L2": 2.8, "eta_L2": 2.8, "u_H1": 1.8, "p_L2": 1.8, "eta_H1": 1.8})


@test("mms-stokes temporal rate")
def test_mms_stokes_temporal_rate():
    errs = [solve(["-options_file", "options/mms-stokes.yaml", "-dt", str(dt)])["errors"] for dt in (0.1, 0.05, 0.025)]
    return check_rates(errs, {"u_L2": 0.9, "p_L2": 0.9, "eta_H1": 0.9})


@test("2 ranks (fluid | structure) reproduce 1 rank: mms-ns", quick=True)
def test_split_ranks_mms_ns():
    one, two = solve(SHORT + ["-coupling_tol", "1e-12"]), solve(SHORT + ["-coupling_tol", "1e-12", "-structure_ranks", "1"], nproc=2)
    assert two["ranks"] == {"fluid": 1, "structure": 1, "total": 2}, "ranks %s" % two["ranks"]
    worst = 0.0
    for k, v in one["errors"].items():
        rel = abs(two["errors"][k] - v) / abs(v)
        worst = max(worst, rel)
        assert rel <= 1e-9, "%s: 1 rank %.15e, 2 ranks %.15e (rel %.1e)" % (k, v, two["errors"][k], rel)
    return "max relative difference %.1e" % worst


@test("channel2d: fluid | structure ranks = 1 rank (opt, iqnils)")
def test_channel2d_split_ranks():
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
def test_explicit_jacobian_blocks():
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


@test("opt's inner solvers: gmres, bicgstab and chord agree with cgls on channel2d's 50-step probes (10 x tol) "
      "without an adjoint solve, gmres with fewer linearized solves; gmres and chord with the learned start on fluid | "
      "structure ranks = 1 rank")
def test_newton_krylov_inner():
    args, tol = CHANNEL + ["-t_final", "0.005"], 1e-4  # -coupling_tol of options/channel2d.yaml
    runs = {}
    for tag, inner, nproc in (("cgls", "cgls", 1), ("gmres", "gmres", 1), ("bicgstab", "bicgstab", 1),
                              ("chord", "chord", 1), ("gmres-split", "gmres", 2)):
        out = os.path.join(WORK, "inner-" + tag)
        extra = ["-structure_ranks", "1"] if nproc == 2 else []
        s = solve(args + ["-coupling_inner", inner] + extra, nproc=nproc, out=out)
        assert s["optimizer"] == ("brgn" if inner == "cgls" else inner), "optimizer %s" % s["optimizer"]
        runs[tag] = (s, read_probes(os.path.join(out, "probes.csv"))[1])
    cgls, ref = runs["cgls"]
    assert cgls["linearized_solves"]["adjoint"] > 0, "cgls solved no adjoint problem: %s" % cgls["linearized_solves"]
    worst = {}
    for tag in ("gmres", "bicgstab", "chord"):
        s, probes = runs[tag]
        worst[tag] = probes_difference(probes, ref)
        assert worst[tag] <= 10 * tol, "%s differs from cgls by %.2e of the probe amplitude" % (tag, worst[tag])
        assert s["linearized_solves"]["adjoint"] == 0, "%s: %d adjoint solves" % (tag, s["linearized_solves"]["adjoint"])
        assert s["max_interface_jump"] <= tol, "%s: jump %.2e" % (tag, s["max_interface_jump"])
    gm, cg = runs["gmres"][0]["linearized_solves"]["forward"], sum(cgls["linearized_solves"].values())
    assert gm < cg, "linearized solves: gmres %d, cgls %d" % (gm, cg)
    assert runs["chord"][0]["inner_iterations"] == 0, "chord: %d inner iterations" % runs["chord"][0]["inner_iterations"]
    split = probes_difference(runs["gmres-split"][1], runs["gmres"][1])
    assert split <= 1e-8, "gmres on fluid | structure ranks differs by %.2e" % split
    # the chord steps with every start option and the secant updates, on 1 and on 2 ranks
    learned = ["-coupling_inner", "chord", "-coupling_start_correction", "-coupling_extrapolation_points", "12",
               "-coupling_extrapolation_recurrence", "6", "-coupling_secant_updates", "20"]
    probes = []
    for nproc, extra in ((1, []), (2, ["-structure_ranks", "1"])):
        out = os.path.join(WORK, "inner-learned-%d" % nproc)
        solve(args + learned + extra, nproc=nproc, out=out)
        probes.append(read_probes(os.path.join(out, "probes.csv"))[1])
    learned_split = probes_difference(probes[1], probes[0])
    assert learned_split <= 1e-8, "chord with the learned start on 2 ranks differs by %.2e" % learned_split
    return "probes within %s of cgls; linearized solves gmres %d, cgls %d; 2 ranks within %.1e (gmres), %.1e (chord, learned start)" % (
        ", ".join("%.1e (%s)" % (v, k) for k, v in worst.items()), gm, cg, split, learned_split)
