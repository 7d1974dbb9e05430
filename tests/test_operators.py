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


BACKEND = re.compile(r"fsiopt: backend check: step (\d+): fluid residual ([0-9.e+-]+) \(the step's start\) ([0-9.e+-]+) "
                     r"\(a random state\), Jacobian ([0-9.e+-]+) ([0-9.e+-]+), libCEED relative to PETSc")


@test("libCEED fluid operators (-fem_backend ceed) = PETSc's to 1e-12 at the first steps' states and at random states: moving meshes with BDF2, loads, Stokes, (Q1,Q1), 3D, forces, 2 ranks")
def test_fluid_backends_agree():
    three = ["-t_final", "3e-4"]
    cases = [(CHANNEL + three, 2, 3),                                                   # moving mesh, backflow, 2 ranks
             (CHANNEL + three + ["-fluid_time_order", "2", "-fem_backend", "ceed"], 1, 3),  # BDF2 on a moving mesh
             (["-options_file", "options/mms-ns.yaml"], 1, 1),                         # fixed mesh, volume loads
             (["-options_file", "options/mms-fluid.yaml", "-fluid_dm_plex_filename", "meshes/square.msh"], 1, 1),  # P2/P1
             (["-options_file", "options/mms-fluid.yaml", "-fluid_velocity_degree", "1",
               "-fluid_pressure_stabilization", "0.1"], 1, 1),                           # (Q1,Q1) stabilized
             (["-options_file", "options/mms-stokes.yaml", "-t_final", "0.65"], 1, 3),    # Stokes
             (["-options_file", "options/tube3d.yaml"] + three + ["-fem_backend", "ceed"], 1, 3),  # hexahedra, moving
             (TUREK + ["-turek_case", "fsi1", "-t_final", "0.3", "-dt", "0.1"], 1, 3)]   # a body force, moving
    worst, checks = 0.0, 0
    for args, nproc, steps in cases:
        rc, stdout, err, _ = run(args + ["-fem_backend_check"], nproc=nproc, out=out_dir("backends"))
        assert rc == 0, "%s: exit %d: %s" % (" ".join(args), rc, (err or stdout)[-300:])
        lines = BACKEND.findall(stdout)
        assert len(lines) == steps, "%s: %d checked steps, expected %d" % (" ".join(args), len(lines), steps)
        for line in lines:
            values = [float(v) for v in line[1:]]
            assert max(values) <= 1e-12, "%s: step %s: %s relative to PETSc" % (" ".join(args), line[0], values)
            worst, checks = max(worst, max(values)), checks + 4
    return "%d residuals and Jacobians on 8 set-ups, worst %.1e relative to PETSc's" % (checks, worst)
