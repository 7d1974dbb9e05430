"""Body forces of the general scene (-fluid_body_force, -structure_body_force): the fluid at rest
under gravity balanced by a hydrostatic pressure, and the wall's response to its own."""
import os

from harness import ROOT, WORK, inputs_dir, read_probes, refused, solve, test

GENERAL_CHANNEL = os.path.join(ROOT, "options", "channel2d.yaml")


def hydrostatic_channel():
    """the channel with both ends at the hydrostatic pressure rho g (1 - y) (rho = 1, g = 980 cm/s^2)"""
    text = open(GENERAL_CHANNEL).read()
    for old, new in (("    left: traction\n", "    left: pressure\n"),
                     ('    left_traction: "t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"\n',
                      '    left_pressure: "980*(1-y)"\n'),
                     ("    right: open\n", '    right: pressure\n    right_pressure: "980*(1-y)"\n')):
        assert old in text, "%s lacks %r" % (GENERAL_CHANNEL, old)
        text = text.replace(old, new)
    path = os.path.join(inputs_dir(), "hydrostatic.yaml")
    open(path, "w").write(text)
    return ["-options_file", path]


def last(out):
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return dict(zip(head, rows[-1]))


@test("body forces: the channel's fluid under gravity (0, -980) with both ends at the hydrostatic pressure "
      "980 (1 - y) stays at rest (velocity 1e-10, wall displacement 1e-12) with that pressure at two points that are "
      "no nodes (1e-10 of it); without the gravity the same ends drive a flow; a body force on the wall moves it "
      "its way, twice as far for twice the force (1e-4)", quick=True)
def test_body_forces():
    base = hydrostatic_channel() + ["-t_final", "0.002", "-probes_fluid_velocity", "3.02,0.37",
                                    "-probes_fluid_pressure", "3.02,0.37,1.1,0.9"]
    rest = os.path.join(WORK, "body-hydrostatic")
    solve(base + ["-fluid_body_force", "0, -980"], out=rest)
    v = last(rest)
    speed = max(abs(v["u_x(3.02;0.37)"]), abs(v["u_y(3.02;0.37)"]))
    moved = max(abs(v[k]) for k in v if k.startswith("d"))
    pressure = max(abs(v["p(3.02;0.37)"] - 980 * 0.63) / (980 * 0.63), abs(v["p(1.1;0.9)"] - 98.0) / 98.0)
    assert speed <= 1e-10 and moved <= 1e-12 and pressure <= 1e-10, \
        "at rest? |u| %.1e, wall %.1e, pressure off by %.1e" % (speed, moved, pressure)
    driven = os.path.join(WORK, "body-none")
    solve(base, out=driven)
    flow = abs(last(driven)["u_y(3.02;0.37)"])
    assert flow > 1e3 * max(speed, 1e-12), "without gravity the ends drive no flow (%.1e)" % flow
    sags = []
    for g in ("1e3", "2e3"):
        out = os.path.join(WORK, "body-wall-" + g)
        solve(hydrostatic_channel() + ["-fluid_body_force", "0, -980", "-structure_body_force", "0, -%s" % g,
                                       "-t_final", "0.0002"], out=out)
        sags.append(last(out)["dy(3.;1.)"])
    assert sags[0] < 0 and abs(sags[1] / sags[0] - 2) <= 1e-4, "wall displacements %s for forces 1e3 and 2e3" % sags
    return "at rest to %.0e (pressure to %.0e); the wall sags %.3g, then %.3g for twice the force" % (
        speed, pressure, sags[0], sags[1])


@test("body forces, bad input: an expression of the wrong size or that does not parse: one line each", quick=True)
def test_body_forces_refused():
    short = ["-options_file", GENERAL_CHANNEL, "-t_final", "0.0002"]
    return refused([
        ("one component in 2D", short + ["-fluid_body_force", "1"], "-fluid_body_force"),
        ("does not parse", short + ["-structure_body_force", "0, -(9.8"], "-structure_body_force"),
    ]) or "2 inputs refused in one line each"
