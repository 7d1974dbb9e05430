"""The libCEED bridge (src/ceed/): restrictions from DMPlexGetLocalOffsets, bases
from PETSc's tabulation at PETSc's quadrature and the cells' geometry give libCEED operators
whose assembled mass and Laplacian equal PETSc's on every finite-element space of a scene:
quadrilaterals, triangles and hexahedra, Q1, Q2, P1, P2, on one and two ranks, on each
backend that runs here (opt/blocked, ref/serial)."""
import os, re
from harness import CHANNEL, SHORT, turek, adjoint_difference, out_dir, probes_difference, read_probes, run, test

CHECK = re.compile(r"fsiopt: libCEED check: (\w+) field (\d+) \((\w+), (\d) components, (\dD \w+) cells\): "
                   r"mass ([0-9.e+-]+), Laplacian ([0-9.e+-]+)")


def checked(args, nproc=1):
    rc, stdout, err, _ = run(args + ["-ceed_check_spaces"], nproc=nproc)
    assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
    return [(m[0], m[2], m[4], float(m[5]), float(m[6])) for m in CHECK.findall(stdout)]


@test("libCEED bridge: mass and Laplacian of every space = PETSc's to 1e-14 (quads, triangles, hexes, tets; 2 ranks; 2 backends)")
def test_ceed_spaces_match_petsc():
    cases = [
        (["-options_file", "options/mms-ns.yaml"], 1, 3),                                # Q2, Q1 on quadrilaterals
        (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh"], 1, 2),  # P2, P1
        (["-options_file", "options/tube3d.yaml", "-t_final", "1e-4"], 1, 3),           # hexahedra, 3 components
        (["-options_file", "options/tube3d.yaml", "-t_final", "1e-4", "-fluid_dm_plex_filename",
          "meshes/tube3d-fluid-tets.msh", "-structure_dm_plex_filename", "meshes/tube3d-wall-tets.msh"], 1, 3),  # tetrahedra
        (turek("fsi1") + ["-t_final", "0.1", "-dt", "0.1"], 1, 3),       # unstructured quadrilaterals
        (CHANNEL + ["-t_final", "1e-4"], 2, 3),                                          # 2 ranks: ghosts, global numbers
        (["-options_file", "options/mms-ns.yaml", "-ceed", "/cpu/self/ref/serial"], 1, 3),
    ]
    worst, cells, spaces = 0.0, set(), 0
    for args, nproc, expected in cases:
        found = checked(args, nproc)
        assert len(found) == expected, "%s: %d spaces checked, expected %d" % (" ".join(args), len(found), expected)
        for side, name, cell, mass, laplacian in found:
            assert mass <= 1e-14 and laplacian <= 1e-14, "%s: %s %s (%s): mass %.2e, Laplacian %.2e" % (
                " ".join(args), side, name, cell, mass, laplacian)
            worst = max(worst, mass, laplacian)
            cells.add(cell)
        spaces += len(found)
    rc, stdout, err, _ = run(["-options_file", "options/mms-ns.yaml", "-ceed", "/gpu/none", "-ceed_check_spaces"],
                             out=out_dir("ceed"))
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and "option -ceed /gpu/none: expected one of" in lines[0], "bad -ceed: %s" % lines
    return "%d spaces on %s: worst %.1e; -ceed /gpu/none refused" % (spaces, ", ".join(sorted(cells)), worst)


BACKEND = re.compile(r"fsiopt: backend check: step (\d+): (fluid|structure) residual ([0-9.e+-]+) \(the step's start\) "
                     r"([0-9.e+-]+) \(a random state\), Jacobian ([0-9.e+-]+) ([0-9.e+-]+), libCEED relative to PETSc")
MOTION = re.compile(r"fsiopt: backend check: mesh motion operator ([0-9.e+-]+), libCEED relative to PETSc")
INTERFACE = re.compile(r"fsiopt: backend check: interface mass ([0-9.e+-]+), libCEED relative to PETSc")


@test("libCEED operators (-fem_backend ceed) = PETSc's to 1e-12 at the first steps' states and at random states: fluid (moving meshes, BDF2, loads, Stokes, (Q1,Q1), 3D, forces, face terms, moving triangles and tetrahedra), structure (linear, St. Venant-Kirchhoff, loads), mesh motion (harmonic, elastic, stiffened), interface mass; 2 ranks")
def test_backends_agree():
    three = ["-t_final", "3e-4"]
    # (options, ranks, checked steps of the fluid, of the structure, mesh motion checks). One
    # rank's libCEED Jacobians are added straight into the matrix, two ranks' by COO
    # (src/ceed/ceed_assembly_direct.c): both paths are compared with PETSc's
    cases = [(CHANNEL + three + ["-fem_backend", "petsc"], 2, 3, 3, 1),                      # PETSc's backend, 2 ranks
             (CHANNEL + three + ["-fluid_time_order", "2", "-fem_backend", "ceed", "-mesh_motion", "elastic",
                                 "-mesh_motion_stiffening", "1"], 1, 3, 3, 1),               # BDF2, elastic stiffened
             (["-options_file", "options/channel2d-svk.opts"] + three, 1, 3, 3, 1),       # St. Venant-Kirchhoff
             (["-options_file", "options/mms-ns.yaml"], 1, 1, 1, 0),                       # fixed mesh, volume loads
             (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh"], 1, 1, 0, 0),
             (["-options_file", "options/mms-fluid.yaml", "-fluid_velocity_degree", "1",
               "-fluid_pressure_stabilization", "0.1"], 1, 1, 0, 0),                         # (Q1,Q1) stabilized
             (["-options_file", "options/mms-stokes.yaml", "-t_final", "0.65"], 1, 3, 3, 0),  # Stokes
             (["-options_file", "options/mms-structure.yaml", "-t_final", "0.575"], 1, 0, 3, 0),  # structure loads
             (["-options_file", "options/tube3d.yaml"] + three + ["-fem_backend", "ceed"], 1, 3, 3, 1),  # hexahedra
             (turek("fsi1") + ["-t_final", "0.3", "-dt", "0.1", "-fem_backend", "petsc"], 1, 3, 3, 1),  # forces
             (turek("csm1") + ["-t_final", "0.3", "-dt", "0.1"], 1, 0, 3, 0),  # gravity, equilibria
             # face operators: backflow and the interface's convective term, 2D on 2 ranks, 3D
             (CHANNEL + three + ["-fluid_backflow_stabilization", "-coupling_control", "convective"], 2, 3, 3, 1),
             # simplices on moving meshes: (P2,P1) triangles, tetrahedra with backflow faces
             (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh",
               "-mms_mesh_motion", "0.1", "-t_final", "0.7"], 1, 2, 0, 0),
             (["-options_file", "options/tube3d.yaml", "-t_final", "3e-4", "-fluid_dm_plex_filename",
               "meshes/tube3d-fluid-tets.msh", "-structure_dm_plex_filename", "meshes/tube3d-wall-tets.msh"], 1, 3, 3, 1)]
    worst, checks, interfaces = 0.0, 0, 0
    for args, nproc, fluid, structure, motion in cases:
        rc, stdout, err, _ = run(args + ["-fem_backend_check"], nproc=nproc, out=out_dir("backends"))
        assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
        lines = BACKEND.findall(stdout)
        counts = (sum(1 for l in lines if l[1] == "fluid"), sum(1 for l in lines if l[1] == "structure"),
                  len(MOTION.findall(stdout)))
        assert counts == (fluid, structure, motion), "%s: checks (fluid, structure, mesh motion) %s, expected %s" % (
            " ".join(args), counts, (fluid, structure, motion))
        values = [float(v) for l in lines for v in l[2:]] + [float(v) for v in MOTION.findall(stdout)]
        interface = [float(v) for v in INTERFACE.findall(stdout)]
        values += interface
        interfaces += len(interface)
        assert max(values or [0]) <= 1e-12, "%s: %s relative to PETSc" % (" ".join(args), max(values))
        worst, checks = max([worst] + values), checks + len(values)
    assert interfaces >= 7, "%d interface mass checks, expected one per coupled set-up (7)" % interfaces
    return "%d residuals, Jacobians and operators (%d interface masses) on %d set-ups, worst %.1e relative to PETSc's" % (
        checks, interfaces, len(cases), worst)


MATFREE = re.compile(r"fsiopt: backend check: step (\d+): fluid matrix-free Jacobian product ([0-9.e+-]+) \(the solver's "
                     r"state\) ([0-9.e+-]+) \(a random state\), transposed ([0-9.e+-]+) ([0-9.e+-]+)")
KRYLOV = ["-fem_backend", "ceed", "-fluid_matfree", "-fluid_ksp_type", "gmres", "-fluid_ksp_rtol", "1e-14"]


@test("libCEED matrix-free fluid Jacobian (-fluid_matfree) = the assembled one to 1e-12, transposed too (moving mesh, BDF2, 3D backflow, (Q1,Q1)); GMRES on it: the LU run's probes to 1e-10, the adjoint identity to 1e-10")
def test_matfree_jacobian():
    cases = [CHANNEL + ["-t_final", "3e-4", "-fluid_time_order", "2"],
             ["-options_file", "options/tube3d.yaml", "-t_final", "2e-4"],
             ["-options_file", "options/mms-fluid.yaml", "-fluid_velocity_degree", "1", "-fluid_pressure_stabilization", "0.1"]]
    worst, checks = 0.0, 0
    for args in cases:
        rc, stdout, err, _ = run(args + KRYLOV + ["-fem_backend_check"], out=out_dir("matfree"))
        assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
        values = [float(v) for l in MATFREE.findall(stdout) for v in l[1:]]
        assert values, "%s: no matrix-free check line" % " ".join(args)
        assert max(values) <= 1e-12, "%s: matrix-free against assembled %.2e" % (" ".join(args), max(values))
        worst, checks = max([worst] + values), checks + len(values)
    # GMRES on the matrix-free operator, preconditioned by the LU of the assembled one, solves
    # the same systems as the LU alone (with the operator lagged as LU's factors are): the
    # coupled run gives its probes (with one coupling step for both, cgls preconditioned by J0:
    # each regime's default stops its own iterations elsewhere within the tolerance)
    # the dense J0 for both (an iterative fluid's default probes it: another preconditioner)
    ten = CHANNEL + ["-t_final", "1e-3", "-coupling_inner", "cgls", "-coupling_explicit_jacobian", "50",
                     "-coupling_explicit_jacobian_probing", "0"]
    lu, krylov = out_dir("matfree-lu"), out_dir("matfree-gmres")
    for args, out in ((ten, lu), (ten + KRYLOV + ["-coupling_lag_preconditioner_only", "0"], krylov)):
        rc, stdout, err, _ = run(args, out=out)
        assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
    difference = probes_difference(read_probes(os.path.join(krylov, "probes.csv"))[1],
                                   read_probes(os.path.join(lu, "probes.csv"))[1])
    assert difference <= 1e-10, "channel2d 10 steps: matrix-free GMRES probes differ from LU's by %.2e" % difference
    rc, stdout, err, _ = run(SHORT + KRYLOV + ["-coupling_test_adjoint", "-t_final", "0.51"], out=out_dir("matfree-adjoint"))
    assert rc == 0, "adjoint: exit %d: %s" % (rc, (err or stdout)[-300:])
    adjoint = adjoint_difference(stdout)
    assert adjoint <= 1e-10, "adjoint identity with the matrix-free Jacobian: %.2e" % adjoint
    return "%d products on %d set-ups, worst %.1e; probes %.1e from LU's; adjoint identity %.1e" % (
        checks, len(cases), worst, difference, adjoint)
