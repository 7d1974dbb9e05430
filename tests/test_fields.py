"""The fields of -write_fields (src/report/fields.c): what ParaView's XDMF readers make of
them (scripts/check_fields.py), the mesh velocity on moving meshes, and a restart that
continues the fields file of the run it restarts."""
import glob, importlib.util, os, re, shutil, subprocess, sys

import numpy as np

from harness import CHANNEL, ROOT, WORK, probe_rows, run, solve, test

CHECK = os.path.join(ROOT, "scripts", "check_fields.py")
# PyPI's vtk (make deps puts it into the private venv): ParaView's XDMF reader for these tests
VTK_SITE = ([d for d in sorted(glob.glob(os.path.join(ROOT, ".deps", "venv", "lib", "python3*", "site-packages")))
             if os.path.isdir(os.path.join(d, "vtkmodules"))] or [None])[0]
if VTK_SITE and VTK_SITE not in sys.path:
    sys.path.append(VTK_SITE)
MMS_MOVING = ["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "0.6", "-dt", "0.025", "-mms_mesh_motion", "0.1",
              "-write_fields", "-write_fields_interval", "1"]


def check_fields(out, *flags):
    """check_fields.py's summary line; AssertionError with its one line when it fails"""
    env = dict(os.environ, PYTHONPATH=VTK_SITE) if VTK_SITE else None
    p = subprocess.run([sys.executable, CHECK] + list(flags) + [out], capture_output=True, text=True, env=env)
    assert p.returncode == 0, "check_fields %s: %s" % (out, (p.stderr or p.stdout).strip())
    return p.stdout.strip()


def read_fields(out, name="fields.h5"):
    """{grid: {step: {dataset: array, "time": t}}} of out/name"""
    import h5py
    got = {}
    with h5py.File(os.path.join(out, name), "r") as h5:
        for grid in h5:
            got[grid] = {int(k[5:]): dict({d: h5[grid][k][d][()] for d in h5[grid][k]}, time=h5[grid][k].attrs["time"])
                         for k in h5[grid] if k.startswith("step_")}
    return got


def xdmf_times(out):
    return [float(t) for t in re.findall(r'<Time Value="([^"]+)"', open(os.path.join(out, "fields.xdmf")).read())]


def readers_present():
    return bool(importlib.util.find_spec("vtkmodules") and importlib.util.find_spec("vtkmodules.vtkIOXdmf2"))


@test("fields: ParaView's XDMF readers (XDMFReader from PyPI's vtk; Xdmf3ReaderS/T where VTK has them) read every "
      "time as fields.h5 has it", quick=True)
def test_fields_paraview_readers():
    out = os.path.join(WORK, "fields-readers")
    solve(CHANNEL + ["-t_final", "0.001", "-write_fields", "-write_fields_interval", "5"], out=out)
    xml = open(os.path.join(out, "fields.xdmf")).read()
    names = re.findall(r'<Grid Name="([^"]+)" GridType="Uniform"', xml)
    want = ["%s_step_%05d" % (g, s) for s in (0, 5, 10) for g in ("fluid", "structure")]
    assert names == want, "uniform grids %s, expected %s" % (names, want)
    attributes = set(re.findall(r'<Attribute Name="([^"]+)" AttributeType="(\w+)" Center="Node">', xml))
    assert attributes == {("velocity", "Vector"), ("pressure", "Scalar"), ("mesh_velocity", "Vector"),
                          ("displacement", "Vector")}, "attributes %s" % sorted(attributes)
    summary = check_fields(out, "--readers", "require" if readers_present() else "auto")
    verdict = summary.split("; ", 1)[-1]
    assert verdict.startswith("readers XDMFReader" if readers_present() else "readers skipped"), summary
    # the checker refuses what the readers would show as fluid, fluid[1], ...: a name per time
    same = os.path.join(WORK, "fields-same-names")
    shutil.copytree(out, same)
    open(os.path.join(same, "fields.xdmf"), "w").write(re.sub(r'Name="(fluid|structure)_step_\d+"', r'Name="\1"', xml))
    p = subprocess.run([sys.executable, CHECK, "--readers", "off", same], capture_output=True, text=True)
    assert p.returncode == 1 and "used more than once" in p.stderr, "repeated names: %s" % (p.stderr or p.stdout)
    return "3 times, unique grid names, 4 node attributes; %s" % verdict


@test("fields: mesh velocity = (x^n - x^{n-1})/dt (backward Euler), (3x^n - 4x^{n-1} + x^{n-2})/(2dt) (BDF2); "
      "none on a fixed mesh", quick=True)
def test_fields_mesh_velocity():
    details = []
    for label, args, order in (("mms-fluid BE", MMS_MOVING, 1), ("mms-fluid BDF2", MMS_MOVING + ["-fluid_time_order", "2"], 2),
                               ("channel2d", CHANNEL + ["-t_final", "0.0003", "-write_fields", "-write_fields_interval", "1"], 1)):
        out = os.path.join(WORK, "fields-z-" + label.replace(" ", "-"))
        solve(args, out=out)
        fluid = read_fields(out)["fluid"]
        steps = sorted(fluid)
        assert steps == list(range(len(steps))) and len(steps) >= 4, "%s: steps %s" % (label, steps)
        worst, scale, bound = 0.0, 0.0, 0.0
        for n in steps[1:]:
            x, z, dt = fluid[n]["geometry"], fluid[n]["mesh_velocity"], fluid[n]["time"] - fluid[n - 1]["time"]
            # BDF2's first step is a backward-Euler step (src/fluid/fluid_ale.c)
            fd = (x - fluid[n - 1]["geometry"]) / dt if order == 1 or n == 1 else \
                (3 * x - 4 * fluid[n - 1]["geometry"] + fluid[n - 2]["geometry"]) / (2 * dt)
            d = x.shape[1]
            assert z.shape == (x.shape[0], 3) and not z[:, d:].any(), "%s: mesh_velocity shape %s" % (label, z.shape)
            # the difference of coordinates of size |x| carries rounding of eps |x| / dt
            bound = max(bound, 64 * np.finfo(float).eps * abs(x).max() / dt)
            worst, scale = max(worst, abs(z[:, :d] - fd).max()), max(scale, abs(z).max())
        assert not fluid[0]["mesh_velocity"].any(), "%s: the initial mesh velocity is not zero" % label
        assert scale > 0 and worst <= bound, "%s: mesh velocity vs the geometry's difference %.2e (rounding %.1e), " \
            "max |z| %.2e" % (label, worst, bound, scale)
        details.append("%s %.1e (rounding %.0e) of max |z| %.2e" % (label, worst, bound, scale))
    fixed = os.path.join(WORK, "fields-z-fixed")
    solve(["-scene", "mms-fluid", "-t_start", "0.5", "-t_final", "0.6", "-dt", "0.025", "-write_fields"], out=fixed)
    datasets = set(read_fields(fixed)["fluid"][0])
    assert datasets == {"geometry", "velocity", "pressure", "time"}, "fixed mesh: datasets %s" % sorted(datasets)
    assert "mesh_velocity" not in open(os.path.join(fixed, "fields.xdmf")).read(), "fixed mesh: mesh_velocity in the XDMF"
    return "; ".join(details) + "; fixed mesh: no mesh_velocity"


def same_fields(got, ref, steps):
    """The largest difference of got from ref at the steps, relative to each dataset's size"""
    worst = 0.0
    for grid in ref:
        for s in steps:
            for name, want in ref[grid][s].items():
                scale = max(abs(want).max(), 1e-300) if name != "time" else 1.0
                worst = max(worst, abs(got[grid][s][name] - want).max() / scale)
    return worst


@test("fields: a restart after SIGKILL continues the fields file, each time once, later ones = uninterrupted (1e-12)")
def test_fields_restart_after_kill():
    base = CHANNEL + ["-t_final", "0.001", "-write_fields", "-write_fields_interval", "3", "-checkpoint_every", "4"]
    full = os.path.join(WORK, "fields-full")
    solve(base, out=full)
    ref = read_fields(full)
    # killed after step 7: its fields hold step 6, after the checkpoint of step 4
    crashed = os.path.join(WORK, "fields-crashed")
    rc, _, err, _ = run(base + ["-interrupt_test_step", "7", "-interrupt_test_signal", "SIGKILL"], out=crashed)
    assert rc != 0 and not os.path.exists(os.path.join(crashed, "fields.h5")), "the killed run: exit %s" % rc
    partial = read_fields(crashed, "fields.h5.partial")
    assert sorted(partial["fluid"]) == [0, 3, 6], "the killed run wrote steps %s" % sorted(partial["fluid"])
    s = solve(base + ["-restart", os.path.join(crashed, "checkpoint.h5")], out=crashed)
    got = read_fields(crashed)
    assert s["first_step"] == 5 and all(sorted(got[g]) == sorted(ref[g]) == [0, 3, 6, 9, 10] for g in ref), \
        "restarted at step %s: steps %s, uninterrupted %s" % (s["first_step"], {g: sorted(got[g]) for g in got},
                                                              {g: sorted(ref[g]) for g in ref})
    assert xdmf_times(crashed) == xdmf_times(full) == [0, 0.0003, 0.0006, 0.0009, 0.001], \
        "XDMF times %s, uninterrupted %s" % (xdmf_times(crashed), xdmf_times(full))
    left = sorted(f for f in os.listdir(crashed) if f.endswith(".partial"))
    assert not left, "left %s" % left
    same = same_fields(got, ref, [0, 3, 6, 9, 10])
    assert same <= 1e-12, "restarted fields differ from the uninterrupted run's by %.2e" % same
    check_fields(crashed)
    # the completed restart's own checkpoint (step 8) into another directory: its file is copied
    other = os.path.join(WORK, "fields-elsewhere")
    s = solve(base + ["-restart", os.path.join(crashed, "checkpoint.h5")], out=other)
    moved = read_fields(other)
    assert s["first_step"] == 9 and sorted(moved["fluid"]) == [0, 3, 6, 9, 10], "elsewhere: steps %s" % sorted(moved["fluid"])
    same_other = same_fields(moved, ref, [0, 3, 6, 9, 10])
    assert same_other <= 1e-12 and xdmf_times(other) == xdmf_times(full), "elsewhere: differs by %.2e" % same_other
    # a checkpoint without fields cannot continue them: one line, no outputs
    plain, refused = os.path.join(WORK, "fields-plain"), os.path.join(WORK, "fields-refused")
    solve(CHANNEL + ["-t_final", "0.0004", "-checkpoint_every", "4"], out=plain)
    rc, stdout, err, _ = run(base + ["-restart", os.path.join(plain, "checkpoint.h5")], out=refused)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    left = os.listdir(refused) if os.path.isdir(refused) else []
    assert rc != 0 and len(lines) == 1 and "written without -write_fields" in lines[0] and not left, \
        "restart with -write_fields from a checkpoint without: exit %s, %s, left %s" % (rc, lines, left)
    return "killed after step 7 (fields to step 6, checkpoint 4): steps 0 3 6 9 10 once, %.0e from the uninterrupted " \
           "run; restarted elsewhere %.0e; no fields in the checkpoint refused" % (same, same_other)


def wall_against_probes(out, rows):
    """The largest gaps, relative to each probe's largest value, between the wall's displacement
    as VTK's XDMF reader gives it and probes.csv at channel2d's interface probes: at the vertex
    x = 3 (and its velocity) and at the Q2 edge nodes x = 1.5, 4.5 (linear interpolation
    between the written nodes); and the number of written times"""
    from vtkmodules.vtkIOXdmf2 import vtkXdmfReader
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    from vtkmodules.util.numpy_support import vtk_to_numpy
    columns = [k for k in rows[0] if k.startswith("dy(")]   # dy at x = 1.5, 3, 4.5 on y = 1
    scale = {k: max(abs(r[k]) for r in rows) for k in columns}
    reader = vtkXdmfReader()
    reader.SetFileName(os.path.join(out, "fields.xdmf"))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    vertex, edge, velocity = 0.0, 0.0, 0.0
    speed = max(abs(r["etadot_y(3.;1.)"]) for r in rows)
    for t in times[1:]:
        reader.UpdateTimeStep(t)
        blocks = reader.GetOutputDataObject(0)
        wall = [blocks.GetBlock(b) for b in range(blocks.GetNumberOfBlocks())
                if blocks.GetMetaData(b).Get(blocks.NAME()).startswith("structure")][0]
        eta = vtk_to_numpy(wall.GetPointData().GetArray("displacement"))
        etadot = vtk_to_numpy(wall.GetPointData().GetArray("velocity"))
        reference = vtk_to_numpy(wall.GetPoints().GetData())[:, :2] - eta[:, :2]   # the geometry is deformed by it
        row = min(rows, key=lambda r: abs(r["t"] - t))
        on_interface = np.abs(reference[:, 1] - 1.0) < 1e-9
        xs, dys = reference[on_interface, 0], eta[on_interface, 1]
        order = np.argsort(xs)
        for x, column in zip((1.5, 3.0, 4.5), columns):
            gap = abs(np.interp(x, xs[order], dys[order]) - row[column]) / scale[column]
            if x == 3.0:
                vertex = max(vertex, gap)
                at = np.flatnonzero(on_interface)[order][int(np.argmin(np.abs(xs[order] - x)))]
                velocity = max(velocity, abs(etadot[at, 1] - row["etadot_y(3.;1.)"]) / speed)
            else:
                edge = max(edge, gap)
    return vertex, velocity, edge, len(times)


@test("fields read by VTK's XDMF reader (PyPI's vtk): the Q2 wall's displacement at channel2d's interface probes "
      "x = 1.5, 4.5 (edge nodes) and x = 3 (a vertex), and its velocity at x = 3, equal probes.csv's at every written "
      "time to 1e-12; written at the vertices only (-write_fields_nodes vertices), the edge nodes' linear "
      "interpolant misses the probe by the interpolation error (measured)")
def test_fields_vtk_against_probes():
    assert readers_present(), "no VTK XDMF reader: make deps puts PyPI's vtk into .deps/venv"
    got = {}
    for nodes in ("all", "vertices"):
        out = os.path.join(WORK, "fields-vtk-probes-" + nodes)
        solve(CHANNEL + ["-t_final", "0.002", "-write_fields", "-write_fields_interval", "5", "-probes_structure_velocity",
                         "3,1", "-write_fields_nodes", nodes], out=out)
        got[nodes] = wall_against_probes(out, probe_rows(out))
    (vertex, velocity, edge, n), (vvertex, vvelocity, vedge, vn) = got["all"], got["vertices"]
    assert n == vn == 5 and max(vertex, velocity, edge, vvertex, vvelocity) <= 1e-12 and vedge > 1e3 * max(edge, 1e-16), \
        "%d/%d times; all nodes: vertex %.1e, velocity %.1e, edge nodes %.1e; vertices only: vertex %.1e, velocity " \
        "%.1e, edge nodes %.1e" % (n, vn, vertex, velocity, edge, vvertex, vvelocity, vedge)
    return "every node: at the edge nodes x = 1.5, 4.5 %.1e, at the vertex x = 3 %.1e (velocity %.1e); vertices " \
        "only: the edge nodes missed by %.1e of the probe's largest value" % (edge, vertex, velocity, vedge)
