"""The libCEED bridge (src/ceed/, issue 23): restrictions from DMPlexGetLocalOffsets, bases
from PETSc's tabulation at PETSc's quadrature and the cells' geometry give libCEED operators
whose assembled mass and Laplacian equal PETSc's on every finite-element space of a scene:
quadrilaterals, triangles and hexahedra, Q1, Q2, P1, P2, on one and two ranks, on each
backend that runs here (opt/blocked, ref/serial)."""
import re
from harness import CHANNEL, TUREK, out_dir, run, test

CHECK = re.compile(r"fsiopt: libCEED check: (\w+) field (\d+) \((\w+), (\d) components, (\dD \w+) cells\): "
                   r"mass ([0-9.e+-]+), Laplacian ([0-9.e+-]+)")


def checked(args, nproc=1):
    rc, stdout, err, _ = run(args + ["-ceed_check_spaces"], nproc=nproc)
    assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
    return [(m[0], m[2], m[4], float(m[5]), float(m[6])) for m in CHECK.findall(stdout)]


@test("libCEED bridge: mass and Laplacian of every space = PETSc's to 1e-14 (quads, triangles, hexes; 2 ranks; 2 backends)")
def test_ceed_spaces_match_petsc():
    cases = [
        (["-options_file", "options/mms-ns.yaml"], 1, 3),                                # Q2, Q1 on quadrilaterals
        (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh"], 1, 2),  # P2, P1
        (["-options_file", "options/tube3d.yaml", "-t_final", "1e-4"], 1, 3),           # hexahedra, 3 components
        (TUREK + ["-turek_case", "fsi1", "-t_final", "0.1", "-dt", "0.1"], 1, 3),       # unstructured quadrilaterals
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


FLUID = re.compile(r"fsiopt: libCEED check: fluid volume (residual|Jacobian) \(Navier-Stokes, (\dD)[^)]*\) at a random state: "
                   r"([0-9.e+-]+) relative to PETSc's")


@test("libCEED fluid volume residual and Jacobian (Navier-Stokes, pressure stabilization, COO by blocks) = PETSc's at a random state to 1e-14 (Q2/Q1, P2/P1, Q1/Q1 2D and 3D; 2 ranks)")
def test_ceed_fluid_residual_matches_petsc():
    cases = [(["-options_file", "options/mms-ns.yaml"], 1),
             (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh"], 1),
             (["-options_file", "options/tube3d.yaml", "-t_final", "1e-4"], 1),
             (TUREK + ["-turek_case", "fsi1", "-t_final", "0.1", "-dt", "0.1"], 1),
             (CHANNEL + ["-t_final", "1e-4"], 2),
             # (Q1,Q1) with the pressure stabilization: a flipped sign of its term shows as 3e-4 here
             (["-options_file", "options/mms-fluid.yaml", "-fluid_velocity_degree", "1",
               "-fluid_pressure_stabilization", "0.1"], 1)]
    found = []
    for args, nproc in cases:
        rc, stdout, err, _ = run(args + ["-ceed_check_fluid"], nproc=nproc)
        assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
        lines = FLUID.findall(stdout)
        assert len(lines) == 2 * nproc, "%s: %d check lines on %d ranks" % (" ".join(args), len(lines), nproc)
        for what, dim, difference in lines:
            assert float(difference) <= 1e-14, "%s: %s %s relative to PETSc's" % (" ".join(args), what, difference)
            found.append(float(difference))
    return "%d residuals and Jacobians (6 set-ups, 2 ranks once), worst %.1e relative to PETSc's" % (len(found), max(found))
