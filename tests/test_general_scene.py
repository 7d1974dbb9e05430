"""The general scene: a case from an options file and a mesh (src/scenes/general.c). Its
channel2d on named gmsh meshes, its conditions against closed forms, and its refusals."""
import os

from harness import (CHANNEL, REFERENCE, ROOT, WORK, help_text, inputs_dir, last_rows, own_section, probes_difference,
                     read_probes, refused, solve, test)


GENERAL_CHANNEL = os.path.join(ROOT, "options", "channel2d.yaml")
NAMED_CHANNEL = os.path.join(ROOT, "options", "examples", "channel2d-named.yaml")


def variant(name, replacements):
    """options/channel2d.yaml with some of its lines changed, as a file of its own"""
    text = open(GENERAL_CHANNEL).read()
    for old, new in replacements:
        assert old in text, "%s: no %r in %s" % (name, old, GENERAL_CHANNEL)
        text = text.replace(old, new)
    path = os.path.join(inputs_dir(), name + ".yaml")
    open(path, "w").write(text)
    return ["-options_file", path]


@test("general scene: channel2d on gmsh meshes whose face sets carry names (options/examples/channel2d-named.yaml) "
      "gives the box's 50 steps (options/channel2d.yaml): the same coupling iterations, probes within 1e-8 of the "
      "stored reference (gmsh numbers the nodes otherwise)", quick=True)
def test_general_channel2d():
    out = os.path.join(WORK, "general-channel")
    s = solve(CHANNEL + ["-t_final", "0.005"], out=out)
    ref_head, ref = read_probes(os.path.join(REFERENCE, "channel2d-50-steps-probes.csv"))
    named = os.path.join(WORK, "general-named")
    n = solve(["-options_file", NAMED_CHANNEL, "-t_final", "0.005"], out=named)
    named_head, named_rows = read_probes(os.path.join(named, "probes.csv"))
    named_gap = probes_difference(named_rows, ref)
    assert named_head == ref_head and named_gap <= 1e-8, "named meshes: probes differ from the reference by %.1e" % (
        named_gap)
    assert s["coupling_iterations"] == n["coupling_iterations"], \
        "coupling iterations %s (box), %s (named)" % (s["coupling_iterations"], n["coupling_iterations"])
    return "%d coupling iterations each; probes within %.0e of the reference" % (s["coupling_iterations"], named_gap)


@test("general scene: options/tube3d.yaml run from another directory finds its meshes in the repository and gives "
      "the probes of a run from the repository's root, to the last digit")
def test_general_from_anywhere():
    import shutil
    import subprocess
    import fsiopt_runs as fr
    here, there = os.path.join(WORK, "tube3d-root"), os.path.join(WORK, "tube3d-elsewhere")
    solve(["-options_file", os.path.join(ROOT, "options", "tube3d.yaml"), "-t_final", "3e-4"], out=here)
    shutil.rmtree(there, ignore_errors=True)
    elsewhere = inputs_dir()
    r = subprocess.run(fr.fsiopt_command(["-options_file", os.path.join(ROOT, "options", "tube3d.yaml"), "-t_final",
                                          "3e-4"], out_dir=there), cwd=elsewhere, env=fr.fsiopt_env(),
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, "from %s: exit %d, %s" % (elsewhere, r.returncode, r.stderr[-300:])
    assert open(os.path.join(here, "probes.csv")).read() == open(os.path.join(there, "probes.csv")).read(), \
        "probes differ between the runs from %s and from %s" % (ROOT, elsewhere)
    return "3 steps from %s, the same probes" % elsewhere


@test("general scene: a pressure p on the inlet is the traction (p, 0) there (probes the same to 1e-12); a velocity "
      "inlet's quadratic profile read at a point of the inlet that is no node is the profile to 1e-12")
def test_general_conditions():
    pulse = '"t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"'
    traction = os.path.join(WORK, "general-traction")
    solve(["-options_file", GENERAL_CHANNEL, "-t_final", "0.002"], out=traction)
    pressure = os.path.join(WORK, "general-pressure")
    solve(variant("pressure", [("left: traction", "left: pressure"),
                               ("left_traction: " + pulse,
                                'left_pressure: "t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0"')])
          + ["-t_final", "0.002"], out=pressure)
    same = probes_difference(read_probes(os.path.join(pressure, "probes.csv"))[1],
                             read_probes(os.path.join(traction, "probes.csv"))[1])
    assert same <= 1e-12, "pressure and traction inlets differ by %.1e" % same
    inlet = os.path.join(WORK, "general-velocity")
    solve(variant("velocity", [("left: traction", "left: velocity"),
                               ("left_traction: " + pulse, 'left_velocity: "60*y*(1-y)*min(t/0.001, 1), 0"')])
          + ["-t_final", "0.002", "-probes_fluid_velocity", "0,0.37"], out=inlet)
    head, rows = read_probes(os.path.join(inlet, "probes.csv"))
    u = head.index("u_x(0.;0.37)")
    profile = [60 * 0.37 * 0.63 * min(r[0] / 0.001, 1) for r in rows]
    worst = max(abs(r[u] - p) for r, p in zip(rows, profile)) / max(profile)
    assert worst <= 1e-12, "the inlet velocity at y = 0.37 differs from the profile by %.1e of its peak" % worst
    # -help lists each face set's condition under its side, by the name the mesh gives it
    groups = own_section(help_text(["-options_file", NAMED_CHANNEL]))
    for side, name in (("fluid_", "inlet"), ("fluid_", "inlet_traction"), ("structure_", "outer")):
        assert [l for l in groups.get(side, []) if l.startswith("  -%sboundary_%s " % (side, name))], \
            "-help lists no -%sboundary_%s: %s" % (side, name, groups.get(side))
    return "pressure = traction to %.0e; inlet profile to %.0e; -help lists the face sets' conditions" % (same, worst)


def waveform_file(name, rows, header="t,Q"):
    path = os.path.join(inputs_dir(), name + ".csv")
    with open(path, "w") as f:
        f.write((header + "\n" if header else "") + "".join("%s\n" % r for r in rows))
    return path


def interpolated(table, t):
    """the table's value at t: linear between rows, repeated with the period it spans"""
    t0, t1 = table[0][0], table[-1][0]
    t = t0 + (t - t0) % (t1 - t0)
    for (a, va), (b, vb) in zip(table, table[1:]):
        if a <= t <= b:
            return va + (vb - va) * (t - a) / (b - a)
    raise AssertionError("t = %g outside the table" % t)


@test("general scene: a flow waveform from a CSV file (-waveform_flow FILE), called as flow(t) in a velocity inlet, "
      "is the table interpolated and repeated with its period, to 1e-12, at a point of the inlet that is no node")
def test_general_waveform():
    import math
    table = [(i * 0.0003, 10 * math.sin(math.pi * i / 10) ** 2) for i in range(11)]
    path = waveform_file("flow", ["%.17g,%.17g" % r for r in table])
    out = os.path.join(WORK, "general-waveform")
    solve(variant("waveform", [("left: traction", "left: velocity"),
                               ('left_traction: "t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"',
                                'left_velocity: "flow(t)*6*y*(1-y), 0"')])
          + ["-waveform_flow", path, "-t_final", "0.005", "-probes_fluid_velocity", "0,0.37"], out=out)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    u = head.index("u_x(0.;0.37)")
    expected = [interpolated(table, r[0]) * 6 * 0.37 * 0.63 for r in rows]
    worst = max(abs(r[u] - e) for r, e in zip(rows, expected)) / max(expected)
    assert len(rows) == 51 and worst <= 1e-12, "%d rows; the inlet differs from the waveform by %.1e" % (len(rows), worst)
    return "50 steps over 1.7 periods of the table: the inlet velocity within %.0e of the interpolated waveform" % worst


@test("general scene, bad input: a face set without a condition, an unknown condition, an expression that does not "
      "parse or has the wrong number of components, a missing datum, two interfaces, a face set the mesh lacks, a datum "
      "its condition does not take, a waveform file missing, not numbers, out of order, of one row or not "
      "covering the run, an unknown function, a parameter named as a built-in name or not a number, a face set given "
      "two conditions (by name and by number): one line each", quick=True)
def test_general_refused():
    pulse = '"t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"'
    short = ["-t_final", "0.0002"]
    return refused([
        ("no condition", variant("no-condition", [("    right: open\n", "")]) + short,
         "the fluid face set right (2) has no condition: expected -fluid_boundary_right one of wall, velocity"),
        ("unknown condition", variant("unknown", [("    bottom: wall", "    bottom: wal")]) + short,
         "-fluid_boundary_bottom"),
        ("syntax", variant("syntax", [(pulse, '"1e3*(1-cos(2*_pi*t/0.025), 0"')]) + short,
         'option -fluid_boundary_left_traction: the expression "1e3*(1-cos(2*_pi*t/0.025), 0" does not parse at '
         "position"),
        ("unknown variable", variant("variable", [(pulse, '"1e3*s, 0"')]) + short,
         'option -fluid_boundary_left_traction: the expression "1e3*s, 0" does not parse'),
        ("components", variant("components", [(pulse, '"1e3"')]) + short,
         'option -fluid_boundary_left_traction: the expression "1e3" gives 1 value; expected 2'),
        ("no datum", variant("no-datum", [("    left_traction: " + pulse + "\n", "")]) + short,
         "option -fluid_boundary_left traction: expected -fluid_boundary_left_traction"),
        ("two interfaces", variant("two-interfaces", [("    top: free", "    top: interface")]) + short,
         "option -structure_boundary_top: a second interface face set"),
        ("no such face set", variant("no-face-set", [("    bottom: wall", "    bottom: wall\n    inlet: wall")]) + short,
         "option -fluid_boundary_inlet: the fluid mesh has no face set of that name; its face sets: bottom, right, top, "
         "left"),
        ("waveform missing", ["-options_file", GENERAL_CHANNEL, "-waveform_flow", "no-such.csv"] + short,
         "option -waveform_flow: the waveform file no-such.csv cannot be read"),
        ("waveform not numbers", ["-options_file", GENERAL_CHANNEL, "-waveform_flow",
                                  waveform_file("words", ["0,1", "0.1,one"])] + short, "line 3: expected two numbers"),
        ("waveform unsorted", ["-options_file", GENERAL_CHANNEL, "-waveform_flow",
                               waveform_file("unsorted", ["0,1", "0.2,2", "0.1,3"])] + short,
         "line 4: t = 0.1 does not come after the row before's t = 0.2"),
        ("waveform one row", ["-options_file", GENERAL_CHANNEL, "-waveform_flow",
                              waveform_file("one-row", ["0,1"])] + short, "has one row; expected at least two"),
        ("waveform short", ["-options_file", GENERAL_CHANNEL, "-waveform_flow",
                            waveform_file("short", ["0,1", "0.0001,2"]), "-waveform_flow_extend", "none"] + short,
         "spans t = 0. to 0.0001, not the run's 0. to 0.0002"),
        ("unknown function", variant("function", [('"t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"',
                                                   '"flw(t), 0"')]) + short,
         'option -fluid_boundary_left_traction: the expression "flw(t), 0" does not parse'),
        ("two conditions", ["-options_file", GENERAL_CHANNEL, "-fluid_boundary_2", "wall"] + short,
         "options -fluid_boundary_right and -fluid_boundary_2: two conditions for one face set"),
        ("parameter named t", ["-options_file", GENERAL_CHANNEL, "-parameter_t", "1"] + short,
         "option -parameter_t: t is a name of every expression already"),
        ("parameter not a number", ["-options_file", GENERAL_CHANNEL, "-parameter_amplitude", "big"] + short,
         "-parameter_amplitude"),
        ("datum of another condition", ["-options_file", GENERAL_CHANNEL, "-fluid_boundary_left", "wall"] + short,
         "option -fluid_boundary_left_traction: the condition of the face set left (-fluid_boundary_left) takes no "
         "such datum"),
    ])


@test("general scene: a .geo named as the mesh file is meshed by gmsh beside it (the same mesh as make writes, the "
      "same probes), reused while newer than the .geo, with -fluid_geo_setnumber passed on; a .geo gmsh cannot mesh "
      "stops the run with one line naming the option and gmsh's reason", quick=True)
def test_general_geo():
    import filecmp
    import shutil
    import time
    geo_dir = os.path.join(inputs_dir(), "geo")
    os.makedirs(geo_dir, exist_ok=True)
    for name in ("channel-fluid.geo", "channel-wall.geo"):
        shutil.copy(os.path.join(ROOT, "meshes", name), geo_dir)
    text = open(NAMED_CHANNEL).read()
    for side in ("fluid", "wall"):
        old = "meshes/channel-%s.msh" % side
        assert old in text, "%s lacks %s" % (NAMED_CHANNEL, old)
        text = text.replace(old, os.path.join(geo_dir, "channel-%s.geo" % side))
    case = os.path.join(geo_dir, "case.yaml")
    open(case, "w").write(text)
    out, ref = os.path.join(WORK, "general-geo"), os.path.join(WORK, "general-geo-ref")
    solve(["-options_file", case, "-t_final", "0.001"], out=out)
    solve(["-options_file", NAMED_CHANNEL, "-t_final", "0.001"], out=ref)
    mesh = os.path.join(geo_dir, "channel-fluid.msh")
    assert filecmp.cmp(mesh, os.path.join(ROOT, "meshes", "channel-fluid.msh"), shallow=False), "another mesh than make's"
    assert filecmp.cmp(os.path.join(out, "probes.csv"), os.path.join(ref, "probes.csv"), shallow=False), \
        "the probes differ from the .msh run's"
    stamp = os.path.getmtime(mesh)
    time.sleep(1.1)
    solve(["-options_file", case, "-t_final", "0.0002"], out=out)
    assert os.path.getmtime(mesh) == stamp, "the mesh was made again although newer than its .geo"
    solve(["-options_file", case, "-t_final", "0.0002", "-fluid_geo_setnumber", "unused_number,1"], out=out)
    assert os.path.exists(os.path.join(geo_dir, "channel-fluid-unused_number-1.msh")), "no mesh of the -setnumber variant"
    broken = os.path.join(geo_dir, "broken.geo")
    open(broken, "w").write("// gmsh -2\nPoint(1) = {0, 0, 0\n")
    refused([("a .geo gmsh cannot mesh", ["-options_file", case, "-fluid_dm_plex_filename", broken, "-t_final", "0.0002"],
              "-fluid_dm_plex_filename")])
    return "the .geo's mesh = make's, probes identical; reused; -setnumber variant; a broken .geo refused"

