"""Moving meshes: geometric conservation, the ALE fluid's temporal rates, the incremental
and the biharmonic mesh motions, the fields written on the moving mesh."""
import os, subprocess, sys

from harness import (CHANNEL, REFERENCE, ROOT, WORK, check_rates, probes_difference, read_probes, same_file,  # noqa: F401
                     solve, test)

CHANNEL_REFERENCE = os.path.join(REFERENCE, "channel2d-50-steps-probes.csv")
# bin/fsiopt -options_file options/channel2d.yaml -mesh_motion_incremental -t_final 0.005
#   -checkpoint_every 25 -output_dir DIR; its DIR/probes.csv (tests/reference/README.md)
INCREMENTAL_REFERENCE = os.path.join(REFERENCE, "channel2d-incremental-50-steps-probes.csv")


@test("geometric conservation: uniform flow on a moving mesh, 2D and 3D, backward Euler and BDF2", quick=True)
def test_geometric_conservation():
    details = []
    for name, box in (("quadrilaterals", []), ("hexahedra", ["-fluid_dm_plex_dim", "3", "-fluid_dm_plex_box_faces", "4,4,2"])):
        for order in ("1", "2"):
            s = solve(["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-fluid_time_order", order] + box)
            e = s["errors"]
            assert e["u_L2"] <= 1e-12 and e["p_L2"] <= 1e-12, "%s, order %s: errors %s" % (name, order, e)
            details.append("%s order %s u_L2 %.1e, p_L2 %.1e" % (name, order, e["u_L2"], e["p_L2"]))
    return ", ".join(details) + " after 10 steps"


@test("ALE fluid on a moving mesh: temporal rates (backward Euler, BDF2); BDF2 restarts exactly")
def test_ale_temporal_rates_and_restart():
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


@test("ALE fluid on moving (P2,P1) triangles: BDF2 temporal rates, on both operator backends alike")
def test_ale_triangles_rates():
    # PETSc 3.18 keeps an affine cell's geometry with the cells; before FEMInvalidateGeometry
    # dropped it with each mesh move, these errors stayed near 0.1
    base = ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "0.8", "-mms_mesh_motion", "0.1",
            "-fluid_time_order", "2", "-fluid_dm_plex_filename", "meshes/square.msh", "-fluid_dm_refine", "2"]
    errs = [solve(base + ["-dt", str(dt)])["errors"] for dt in (0.05, 0.025, 0.0125)]
    detail = check_rates(errs, {"u_L2": 1.7, "p_L2": 1.8})
    petsc = solve(base + ["-dt", "0.0125", "-fem_backend", "petsc"])["errors"]
    worst = max(abs(petsc[k] - errs[-1][k]) / errs[-1][k] for k in ("u_L2", "p_L2"))
    assert worst <= 1e-8, "PETSc's backend: errors %s, libCEED's %s" % (petsc, errs[-1])
    return "BDF2 %s; PETSc's backend within %.1e" % (detail, worst)


@test("incremental mesh motion: channel2d probes = stored reference (5e-8), restarts byte for byte")
def test_incremental_mesh_motion():
    inc = CHANNEL + ["-mesh_motion_incremental"]
    full = os.path.join(WORK, "incremental-full")
    solve(inc + ["-t_final", "0.005", "-checkpoint_every", "25"], out=full)  # a checkpoint resynchronizes the writer too
    head, got = read_probes(os.path.join(full, "probes.csv"))
    ref_head, ref = read_probes(INCREMENTAL_REFERENCE)
    assert head == ref_head and len(got) == len(ref), "probe layout differs from the reference"
    worst = probes_difference(got, ref)
    # the last bits of the factorizations follow the processor (OpenBLAS picks its kernels when
    # it starts): 1.4e-8 on one machine of the same build and packages, below 1e-8 on another
    assert worst <= 5e-8, "probes differ from the stored incremental run's by %.2e relative" % worst
    # and from the total extension's (stored, without checkpoints) by at most the coupling's
    # 10 x tol: 7.2e-5, mostly the checkpoint's (-checkpoint_every 25 alone moves either run's
    # probes by 7.7e-5 after step 25; without checkpoints the two extensions differ by 5.3e-6)
    total = probes_difference(got, read_probes(CHANNEL_REFERENCE)[1])
    assert total <= 10 * 1e-4, "probes differ from the total extension's by %.2e of their amplitude" % total
    part = os.path.join(WORK, "incremental-part")
    solve(inc + ["-t_final", "0.0025", "-checkpoint_every", "25"], out=part)
    again = os.path.join(WORK, "incremental-again")
    s = solve(inc + ["-t_final", "0.005", "-restart", os.path.join(part, "checkpoint.h5")], out=again)
    assert s["first_step"] == 26 and same_file(os.path.join(again, "probes.csv"), os.path.join(full, "probes.csv")), \
        "restarted at step %d: probes.csv differs from the uninterrupted run's" % s["first_step"]
    return "probes within %.1e of the stored reference (%.1e from the total extension's); restarted at step 26: " \
           "probes.csv byte for byte" % (worst, total)


@test("biharmonic mesh motion: clamped at the wall (half the harmonic's shear), same probes (1 %), 2 fluid ranks")
def test_biharmonic_mesh_motion():
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


@test("fields: HDF5 + XDMF consistent, fluid mesh follows the wall at its vertices (its edges are straight, the Q2 "
      "wall's are not: the gap at edge nodes is measured)", quick=True)
def test_fields_follow_the_wall():
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
    assert len(on_fluid) == 61 and set(on_fluid) == set(on_wall), "interface nodes %d / %d" % (len(on_fluid), len(on_wall))
    vertices = [x for x in on_fluid if abs(x / 0.2 - round(x / 0.2)) < 1e-9]   # 30 cells along 6
    assert len(vertices) == 31, "interface vertices %d" % len(vertices)
    worst = max(abs(on_fluid[x] - on_wall[x]).max() for x in vertices)
    edges = max(abs(on_fluid[x] - on_wall[x]).max() for x in on_fluid if x not in vertices)
    scale = max(abs(d).max() for d in on_wall.values())
    _, probes = read_probes(os.path.join(out, "probes.csv"))
    probe = abs(on_wall[3.0][1] - probes[-1][4])
    assert scale > 0 and worst <= 1e-12 * scale + 1e-15, "fluid interface moved %.2e away from the wall" % worst
    assert probe <= 1e-10 * scale, "wall field and probes.csv differ by %.2e at (3,1)" % probe
    return "3 times, interface max |d| %.2e, fluid vs wall %.1e at the vertices, %.1e at the wall's edge nodes" % (
        scale, worst, edges)
