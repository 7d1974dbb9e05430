"""The general scene: a case from an options file and a mesh (src/scenes/general.c). Its
channel2d against the built-in scene, its conditions against closed forms, and its refusals."""
import os

from harness import (CHANNEL, REFERENCE, ROOT, WORK, help_text, inputs_dir, last_rows, own_section, probes_difference,
                     read_probes, refused, solve, test)


GENERAL_CHANNEL = os.path.join(ROOT, "options", "examples", "channel2d.yaml")
NAMED_CHANNEL = os.path.join(ROOT, "options", "examples", "channel2d-named.yaml")


def variant(name, replacements):
    """options/examples/channel2d.yaml with some of its lines changed, as a file of its own"""
    text = open(GENERAL_CHANNEL).read()
    for old, new in replacements:
        assert old in text, "%s: no %r in %s" % (name, old, GENERAL_CHANNEL)
        text = text.replace(old, new)
    path = os.path.join(inputs_dir(), name + ".yaml")
    open(path, "w").write(text)
    return ["-options_file", path]


@test("general scene: channel2d from options/examples/channel2d.yaml (a box) and channel2d-named.yaml (gmsh meshes, "
      "face sets by name) give the built-in scene's 50 steps (the same coupling iterations, probes within 1e-8 of "
      "the stored reference: muparser's arithmetic and gmsh's numbering differ from the C scene's in the last bit)",
      quick=True)
def test_general_channel2d():
    out = os.path.join(WORK, "general-channel")
    s = solve(["-options_file", GENERAL_CHANNEL, "-t_final", "0.005"], out=out)
    builtin = os.path.join(WORK, "general-builtin")
    b = solve(CHANNEL + ["-t_final", "0.005"], out=builtin)
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    ref_head, ref = read_probes(os.path.join(REFERENCE, "channel2d-50-steps-probes.csv"))
    assert head == ref_head and len(rows) == len(ref), "probe layout %s, %d rows" % (head, len(rows))
    gap = probes_difference(rows, ref)
    assert gap <= 1e-8, "probes differ from the reference by %.1e" % gap
    named = os.path.join(WORK, "general-named")
    n = solve(["-options_file", NAMED_CHANNEL, "-t_final", "0.005"], out=named)
    named_head, named_rows = read_probes(os.path.join(named, "probes.csv"))
    named_gap = probes_difference(named_rows, ref)
    assert named_head == ref_head and named_gap <= 1e-8, "named meshes: probes differ from the reference by %.1e" % (
        named_gap)
    its = [len([r for r in last_rows(d, "history.csv")]) for d in (out, builtin)]
    assert s["coupling_iterations"] == b["coupling_iterations"] == n["coupling_iterations"], \
        "coupling iterations %s (general), %s (named), %s (built-in)" % (
            s["coupling_iterations"], n["coupling_iterations"], b["coupling_iterations"])
    return "%d steps, %d coupling iterations each; probes within %.0e (box) and %.0e (named) of the reference" % (
        its[0], s["coupling_iterations"], gap, named_gap)


@test("general scene: a pressure p on the inlet is the traction (p, 0) there (probes the same to 1e-12); a velocity "
      "inlet's quadratic profile read at a point of the inlet that is no node is the profile to 1e-12")
def test_general_conditions():
    pulse = '"t <= 0.025 ? 1e3*(1-cos(2*_pi*t/0.025)) : 0, 0"'
    traction = os.path.join(WORK, "general-traction")
    solve(["-options_file", GENERAL_CHANNEL, "-t_final", "0.002"], out=traction)
    pressure = os.path.join(WORK, "general-pressure")
    solve(variant("pressure", [("left: traction", "left: pressure"),
                               ("left_traction: " + pulse,
                                'left_pressure: "t <= 0.025 ? 1e3*(1-cos(2*_pi*t/0.025)) : 0"')])
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


@test("general scene, bad input: a face set without a condition, an unknown condition, an expression that does not "
      "parse or has the wrong number of components, a missing datum, two interfaces, a face set the mesh lacks, a datum "
      "its condition does not take: one line each", quick=True)
def test_general_refused():
    pulse = '"t <= 0.025 ? 1e3*(1-cos(2*_pi*t/0.025)) : 0, 0"'
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
        ("datum of another condition", ["-options_file", GENERAL_CHANNEL, "-fluid_boundary_left", "wall"] + short,
         "option -fluid_boundary_left_traction: the condition of the face set left (-fluid_boundary_left) takes no "
         "such datum"),
    ])
