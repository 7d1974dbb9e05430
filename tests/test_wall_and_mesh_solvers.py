"""The wall's, the mesh motion's and the velocity block's linear solves in the large-run solver
files: the wall by MUMPS's Cholesky factorization (options/solvers/structure-cholesky.yaml),
the harmonic mesh motion's operator without the zero couplings between components that the
vector field's pattern stores (src/mesh/motion.c), and the velocity block's ILU(0) on a
block-AIJ copy (src/common/pc_ilu_baij.c)."""
import os, re

from harness import (CHANNEL, adjoint_difference, difference_to_largest, fail_text, read_probes, out_dir, run,
                     stage_count, test, ITERATIVE_ILU, SOLVER_FILES)

TUBE = ["-options_file", "options/tube3d.yaml"]


@test("options/solvers/structure-cholesky.yaml: tube3d level 1 with the other iterative-ilu files, two steps, the "
      "wall by MUMPS Cholesky against MUMPS LU: the same Gauss-Newton iterations, probes within 1e-9 (both are direct "
      "solves of the same system); the adjoint identity to 10 x the Krylov tolerance, 1 and 2 ranks")
def test_wall_cholesky():
    cholesky = SOLVER_FILES["structure-cholesky"]
    # the iterative-ilu set without its wall file: the wall by the default MUMPS LU
    wall_lu = SOLVER_FILES["fluid-schur-gamg"] + SOLVER_FILES["fluid-velocity-ilu"] + SOLVER_FILES["mesh-cg-gamg"]
    details = []
    for nproc in (1, 2):
        found = {}
        for name, files in (("lu", wall_lu), ("cholesky", wall_lu + cholesky)):
            out = out_dir("wall-%s-%d" % (name, nproc))
            rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0002", "-structure_ksp_view"] + files, nproc=nproc,
                                           out=out, tag="wall-cholesky")
            assert rc == 0 and summary, fail_text(rc, stdout, err)
            found[name] = (summary, read_probes(os.path.join(out, "probes.csv"))[1], stdout)
        for name, kind in (("cholesky", "cholesky"), ("lu", "lu")):
            assert re.search(r"PC Object: \(structure_\) \d+ MPI process\w*\n\s+type: %s\n" % kind, found[name][2]), \
                "the %s run's -structure_ksp_view shows no %s preconditioner" % (name, kind)
        its = (found["cholesky"][0]["coupling_iterations"], found["lu"][0]["coupling_iterations"])
        assert its[0] == its[1], "%d rank(s): %d Gauss-Newton iterations with Cholesky, %d with LU" % ((nproc,) + its)
        diff = difference_to_largest(found["cholesky"][1], found["lu"][1])
        assert diff <= 1e-9, "%d rank(s): probes %.2e from LU's" % (nproc, diff)
        rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0001", "-coupling_test_adjoint", "-coupling_inner", "cgls"]
                                       + wall_lu + cholesky, nproc=nproc, tag="wall-cholesky-adjoint")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        adjoint = adjoint_difference(stdout)
        assert adjoint <= 1e-9, "%d rank(s): adjoint identity %.2e, above 10 x the Krylov tolerance 1e-10" % (
            nproc, adjoint)
        details.append("%d rank%s: %d GN both, probes within %.1e, adjoint %.1e" % (
            nproc, "s" if nproc > 1 else "", its[0], diff, adjoint))
    return "; ".join(details)


@test("harmonic mesh motion: the free block holds only each component's own couplings, at most 27 entries a row on "
      "tube3d's hexahedra (the vector pattern's 81 less the zero couplings between components), and CG with GAMG "
      "(options/solvers/mesh-cg-gamg.yaml) solves it in as many iterations per solve on 2 ranks as on 1, give or take one; "
      "the incremental motion's operator, assembled each step, keeps its pattern: one symbolic LU factorization, "
      "a numeric one per step (channel2d, five steps)")
def test_mesh_operator_compact():
    per_solve = {}
    for nproc in (1, 2):
        rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0001", "-mesh_ksp_view", "-mesh_ksp_converged_reason"]
                                       + ITERATIVE_ILU, nproc=nproc, tag="mesh-compact")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        # the KSP's own operator: the last 'linear system matrix' block of the mesh KSP's view
        view = stdout[stdout.index("KSP Object: (mesh_)"):]
        tail = view[view.rindex("linear system matrix"):]
        rows = int(re.search(r"rows=(\d+)", tail).group(1))
        nonzeros = int(re.search(r"total: nonzeros=(\d+)", tail).group(1))
        if nproc == 1:
            assert nonzeros <= 27 * rows, "1 rank: %d entries in %d rows of the mesh operator" % (nonzeros, rows)
            density = nonzeros / rows
        its = [int(m) for m in re.findall(r"Linear mesh_ solve converged due to \w+ iterations (\d+)", stdout)]
        assert its, "no converged-reason line of the mesh solves"
        per_solve[nproc] = sum(its) / len(its)
    assert abs(per_solve[2] - per_solve[1]) <= 1.0, "CG iterations per mesh solve: %.2f on 1 rank, %.2f on 2" % (
        per_solve[1], per_solve[2])
    out = out_dir("mesh-compact-incremental")
    log = os.path.join(out, "log_view.txt")
    rc, stdout, err, summary = run(CHANNEL + ["-mesh_motion_incremental", "-t_final", "0.0005",
                                              "-log_view", ":" + log], out=out, tag="mesh-compact")
    assert rc == 0 and summary, fail_text(rc, stdout, err)
    numeric, symbolic = stage_count(log, "MeshMotion", "MatLUFactorNum"), stage_count(log, "MeshMotion", "MatLUFactorSym")
    assert numeric == 5 and symbolic == 0, "incremental motion, five steps: %d numeric and %d symbolic LU " \
        "factorizations of the mesh operator after the set-up's" % (numeric, symbolic)
    return "%.1f entries a row; CG %.2f iterations per solve on 1 rank, %.2f on 2; incremental: %d numeric, %d " \
        "symbolic factorizations after the set-up's" % (density, per_solve[1], per_solve[2], numeric, symbolic)


@test("the velocity block's ILU(0) on a block-AIJ copy (-fluid_fieldsplit_velocity_sub_pc_type ilubaij, "
      "options/solvers/fluid-velocity-ilu.yaml): tube3d level 1 with the iterative-ilu files, two steps, against "
      "PETSc's ILU(0) of the AIJ block: the pattern is of whole 3 x 3 blocks, so the factors are the same and so are "
      "the Gauss-Newton iterations, the fluid's linear solves and the probes (within 1e-9); the adjoint identity to "
      "10 x the Krylov tolerance through its transpose; 1 and 2 ranks")
def test_velocity_block_ilu():
    details = []
    for nproc in (1, 2):
        found = {}
        for name in ("ilubaij", "ilu"):
            out = out_dir("velocity-%s-%d" % (name, nproc))
            rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0002"] + ITERATIVE_ILU +
                                           ["-fluid_fieldsplit_velocity_sub_pc_type", name], nproc=nproc, out=out,
                                           tag="velocity-block-ilu")
            assert rc == 0 and summary, fail_text(rc, stdout, err)
            found[name] = (summary, read_probes(os.path.join(out, "probes.csv"))[1])
        for key in ("coupling_iterations", "fluid_linear_solves"):
            counts = (found["ilubaij"][0][key], found["ilu"][0][key])
            assert counts[0] == counts[1], "%d rank(s): %s %d with ilubaij, %d with ilu" % ((nproc, key) + counts)
        diff = difference_to_largest(found["ilubaij"][1], found["ilu"][1])
        assert diff <= 1e-9, "%d rank(s): probes %.2e apart" % (nproc, diff)
        rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0001", "-coupling_test_adjoint", "-coupling_inner", "cgls",
                                               "-fluid_ksp_view"] + ITERATIVE_ILU, nproc=nproc,
                                       tag="velocity-block-ilu-adjoint")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        assert "ILU of the operator copied to block AIJ" in stdout, "-fluid_ksp_view shows no ilubaij sub-PC"
        assert re.search(r"type: seqbaij\s+rows=\d+, cols=\d+, bs=3", stdout), "the ILU's operator is not 3 x 3 BAIJ"
        adjoint = adjoint_difference(stdout)
        assert adjoint <= 1e-9, "%d rank(s): adjoint identity %.2e, above 10 x the Krylov tolerance 1e-10" % (
            nproc, adjoint)
        details.append("%d rank%s: %d GN, %d fluid linear solves both, probes within %.1e, adjoint %.1e" % (
            nproc, "s" if nproc > 1 else "", found["ilu"][0]["coupling_iterations"],
            found["ilu"][0]["fluid_linear_solves"], diff, adjoint))
    # a matrix not in whole blocks (the pressure's, one unknown a node) keeps PETSc's ILU of its AIJ
    runs = {}
    for name in ("ilubaij", "ilu"):
        out = out_dir("pressure-%s" % name)
        rc, stdout, err, summary = run(TUBE + ["-t_final", "0.0001"] + ITERATIVE_ILU +
                                       ["-fluid_fieldsplit_pressure_pc_type", name, "-options_allow_unused",
                                        "-fluid_ksp_view"], out=out, tag="pressure-block-ilu")
        assert rc == 0 and summary, fail_text(rc, stdout, err)
        runs[name] = (summary, read_probes(os.path.join(out, "probes.csv"))[1], stdout)
    assert "ILU of the AIJ operator (its rows are not whole blocks)" in runs["ilubaij"][2], \
        "-fluid_ksp_view shows no AIJ fallback for the pressure"
    assert runs["ilubaij"][0]["fluid_linear_solves"] == runs["ilu"][0]["fluid_linear_solves"]
    fallback = difference_to_largest(runs["ilubaij"][1], runs["ilu"][1])
    assert fallback <= 1e-12, "pressure by ilubaij's AIJ fallback: probes %.2e from ilu's" % fallback
    details.append("pressure (not in blocks): the AIJ ILU, probes within %.1e" % fallback)
    return "; ".join(details)
