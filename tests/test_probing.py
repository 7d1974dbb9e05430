"""GMRES on the interface Jacobian J: the probed J0 (-coupling_explicit_jacobian_probing), a
sparse explicit Jacobian from a few products with coloured unit loads, as its preconditioner,
and the Eisenstat-Walker forcing that stops each of its solves."""
import os

from harness import (CHANNEL, adjoint_difference, difference_to_largest, fail_text, read_probes, run, out_dir, solve,
                     test, ITERATIVE_ILU)

PROBED = ["-coupling_explicit_jacobian", "50", "-coupling_explicit_jacobian_probing", "1"]


def colours(stdout):
    words = stdout.split("probed with ", 1)
    assert len(words) == 2, "no probed J0 in the run's description"
    return int(words[1].split()[0])


@test("probed J0 (GMRES on J preconditioned by J0 from one product per colour and component): tube3d with the "
      "iterative solver files, five steps, 1 and 2 ranks: the unpreconditioned run's Gauss-Newton iterations and "
      "probes (within 10 x the coupling tolerance), at most 0.6 x its GMRES iterations, the adjoint identity to "
      "10 x the Krylov tolerance, the same colouring on 2 ranks")
def test_probed_jacobian_tube3d():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0005", "-coupling_inner", "gmres",
            "-coupling_tol", "1e-6"] + ITERATIVE_ILU
    details, ncolours = [], {}
    for nproc in (1, 2):
        plain_out, probed_out = out_dir("probing-plain-%d" % nproc), out_dir("probing-probed-%d" % nproc)
        plain = solve(args + ["-coupling_explicit_jacobian", "0"], nproc=nproc, out=plain_out)
        rc, stdout, err, probed = run(args + PROBED + ["-coupling_test_adjoint"], nproc=nproc, out=probed_out)
        assert rc == 0 and probed, fail_text(rc, stdout, err)
        ncolours[nproc] = colours(stdout)
        adjoint = adjoint_difference(stdout)
        assert adjoint <= 1e-9, "%d rank(s): adjoint test %.2e" % (nproc, adjoint)
        assert probed["coupling_iterations"] <= plain["coupling_iterations"], \
            "%d rank(s): %d Gauss-Newton iterations, unpreconditioned %d" % (
                nproc, probed["coupling_iterations"], plain["coupling_iterations"])
        assert probed["inner_iterations"] <= 0.6 * plain["inner_iterations"], \
            "%d rank(s): %d GMRES iterations, unpreconditioned %d" % (nproc, probed["inner_iterations"],
                                                                     plain["inner_iterations"])
        diff = difference_to_largest(read_probes(os.path.join(probed_out, "probes.csv"))[1],
                                     read_probes(os.path.join(plain_out, "probes.csv"))[1])
        assert diff <= 1e-5, "%d rank(s): probes %.2e from the unpreconditioned run's" % (nproc, diff)
        details.append("%d rank%s: GMRES its %d -> %d, %d GN (unpreconditioned %d), probes within %.1e, adjoint %.1e"
                       % (nproc, "s" if nproc > 1 else "", plain["inner_iterations"], probed["inner_iterations"],
                          probed["coupling_iterations"], plain["coupling_iterations"], diff, adjoint))
    assert ncolours[1] == ncolours[2], "colours %d on 1 rank, %d on 2" % (ncolours[1], ncolours[2])
    return "%d colours; %s" % (ncolours[1], "; ".join(details))


@test("probed J0: its colours (the products of a build) do not grow with the mesh: channel2d refined twice (4 x the "
      "controls) needs at most one colour more; fluid | structure ranks reproduce 1 rank")
def test_probing_colours():
    found = []
    args = CHANNEL + ["-t_final", "0.0002", "-coupling_inner", "gmres"] + PROBED
    for refine in (0, 2):
        rc, stdout, err, summary = run(args + ["-refine", str(refine)], out=out_dir("probing-refine-%d" % refine))
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        found.append((colours(stdout), summary["fluid_dofs"]))
    assert found[1][0] <= found[0][0] + 1, "colours %d at refine 0, %d at refine 2" % (found[0][0], found[1][0])
    one_out, two_out = out_dir("probing-one"), out_dir("probing-split")
    one = solve(args, out=one_out)
    two = solve(args + ["-structure_ranks", "1"], nproc=2, out=two_out)
    assert one["inner_iterations"] == two["inner_iterations"], "GMRES its %d on 1 rank, %d fluid | structure" % (
        one["inner_iterations"], two["inner_iterations"])
    diff = difference_to_largest(read_probes(os.path.join(two_out, "probes.csv"))[1],
                                 read_probes(os.path.join(one_out, "probes.csv"))[1])
    assert diff <= 1e-10, "probes %.2e apart" % diff
    return "colours %d (%d fluid unknowns) and %d (%d); fluid | structure = 1 rank (probes within %.1e)" % (
        found[0][0], found[0][1], found[1][0], found[1][1], diff)


@test("Eisenstat-Walker forcing (on by default with GMRES on J: a step's GMRES stops at a fraction of the "
      "linearized jump the Newton step leaves anyway): tube3d with the iterative solver files, five steps: the "
      "Gauss-Newton iterations of GMRES run to the tolerance, probes within 10 x the coupling tolerance, at most "
      "0.8 x its GMRES iterations and fewer fluid linear solves")
def test_forcing():
    args = ["-options_file", "options/tube3d.yaml", "-t_final", "0.0005"] + ITERATIVE_ILU
    found = {}
    for name, extra in (("forced", []), ("to the tolerance", ["-coupling_snes_ksp_ew", "false"])):
        out = out_dir("forcing-%s" % name.split()[0])
        found[name] = (solve(args + extra, out=out), out)
    (forced, forced_out), (full, full_out) = found["forced"], found["to the tolerance"]
    assert forced["coupling_iterations"] == full["coupling_iterations"], "Gauss-Newton iterations %d, without %d" % (
        forced["coupling_iterations"], full["coupling_iterations"])
    assert forced["inner_iterations"] <= 0.8 * full["inner_iterations"], "GMRES iterations %d, without %d" % (
        forced["inner_iterations"], full["inner_iterations"])
    assert forced["fluid_linear_solves"] < full["fluid_linear_solves"], "fluid linear solves %d, without %d" % (
        forced["fluid_linear_solves"], full["fluid_linear_solves"])
    diff = difference_to_largest(read_probes(os.path.join(forced_out, "probes.csv"))[1],
                                 read_probes(os.path.join(full_out, "probes.csv"))[1])
    assert diff <= 1e-3, "probes %.2e apart, above 10 x the coupling tolerance 1e-4" % diff
    return "%d GN both; GMRES its %d -> %d, fluid linear solves %d -> %d; probes within %.1e" % (
        full["coupling_iterations"], full["inner_iterations"], forced["inner_iterations"], full["fluid_linear_solves"],
        forced["fluid_linear_solves"], diff)
