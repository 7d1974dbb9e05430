"""Probes at any point (-probes_fluid_velocity, -probes_fluid_pressure,
-probes_structure_displacement, -probes_structure_velocity): a field's own finite element
evaluated in the cell that holds the point, on whichever rank owns that cell."""
import math, os

from harness import CHANNEL, WORK, probes_difference, read_probes, refused, solve, test

MMS_FLUID = ["-options_file", "options/mms-fluid.yaml"]
POINTS = [(0.33, 0.41), (0.71, 0.13)]  # no vertex of the 4x4 box or its refinements


def mms_velocity(t, x, y):
    """src/scenes/mms_fields.h's u"""
    return math.sin(x + t) * math.cos(y + t), -math.cos(x + t) * math.sin(y + t)


def mms_pressure(t, x, y):
    return math.sin(x + t) * math.sin(y + t)


def column(head, rows, name):
    assert name in head, "probes.csv has no column %s: %s" % (name, head)
    return [r[head.index(name)] for r in rows]


@test("probes at any point: mms-fluid's velocity and pressure at two points that are no vertices converge to the "
      "closed form at the pointwise rates of Q2 (>= 2.5) and Q1 (>= 1.5), refine 1, 2, 3")
def test_point_probes_converge():
    coords = ",".join("%g,%g" % p for p in POINTS)
    errors = []
    for refine in (1, 2, 3):
        out = os.path.join(WORK, "points-mms-%d" % refine)
        s = solve(MMS_FLUID + ["-refine", str(refine), "-probes_fluid_velocity", coords, "-probes_fluid_pressure",
                               coords], out=out)
        head, rows = read_probes(os.path.join(out, "probes.csv"))
        t = rows[-1][0]
        assert abs(t - s["t_final"]) < 1e-12, "last row at t = %g, not the final time %g" % (t, s["t_final"])
        u = max(abs(column(head, rows, "u_%s(%g;%g)" % (c, x, y))[-1] - mms_velocity(t, x, y)[i])
                for x, y in POINTS for i, c in enumerate("xy"))
        # the pressure up to its constant: the difference between the two points
        p = [column(head, rows, "p(%g;%g)" % q)[-1] for q in POINTS]
        dp = abs((p[0] - p[1]) - (mms_pressure(t, *POINTS[0]) - mms_pressure(t, *POINTS[1])))
        errors.append((u, dp))
    rates = [(math.log2(a[0] / b[0]), math.log2(a[1] / b[1])) for a, b in zip(errors, errors[1:])]
    assert all(r[0] >= 2.5 for r in rates) and all(r[1] >= 1.5 for r in rates), \
        "rates (velocity, pressure) %s, errors %s" % (rates, errors)
    return "velocity errors %s (rates %s), pressure %s (rates %s)" % (
        " ".join("%.1e" % e[0] for e in errors), " ".join("%.2f" % r[0] for r in rates),
        " ".join("%.1e" % e[1] for e in errors), " ".join("%.2f" % r[1] for r in rates))


@test("probes at any point: at a wall node that is no vertex (a Q2 edge node) the structure's displacement is the interface probe's to 1e-12; "
      "fluid and structure points of channel2d on 2 ranks (shared, and fluid | structure) within 1e-8 of 1 rank (the two-rank sums differ in order)",
      quick=True)
def test_point_probes_vertex_and_ranks():
    args = CHANNEL + ["-t_final", "0.002", "-probes_structure_displacement", "1.5,1,3.3,1.05",
                      "-probes_structure_velocity", "3.3,1.05", "-probes_fluid_velocity", "3.02,0.5,1.1,0.93",
                      "-probes_fluid_pressure", "3.02,0.5"]
    runs = {}
    for tag, nproc, extra in (("1", 1, []), ("2", 2, []), ("2-split", 2, ["-structure_ranks", "1"])):
        out = os.path.join(WORK, "points-channel-" + tag)
        solve(args + extra, nproc=nproc, out=out)
        runs[tag] = read_probes(os.path.join(out, "probes.csv"))
    head, rows = runs["1"]
    for name in ("eta_x(3.3;1.05)", "etadot_y(3.3;1.05)", "u_x(3.02;0.5)", "p(3.02;0.5)"):
        assert max(abs(v) for v in column(head, rows, name)[1:]) > 0, "%s stays 0" % name
    interface = column(head, rows, "dy(1.5;1.)")
    wall = column(head, rows, "eta_y(1.5;1.)")
    scale = max(abs(v) for v in interface)
    vertex = max(abs(a - b) for a, b in zip(interface, wall)) / scale
    assert scale > 0 and vertex <= 1e-12, "eta_y(1.5;1.) differs from dy(1.5;1.) by %.1e of its largest value" % vertex
    gaps = {}
    for tag in ("2", "2-split"):
        assert runs[tag][0] == head, "%s ranks: other columns %s" % (tag, runs[tag][0])
        gaps[tag] = probes_difference(runs[tag][1], rows)
        assert gaps[tag] <= 1e-8, "%s ranks: probes differ from 1 rank's by %.1e" % (tag, gaps[tag])
    return "%d columns; vertex %.0e; 2 ranks %.0e, fluid | structure %.0e" % (
        len(head) - 1, vertex, gaps["2"], gaps["2-split"])


@test("probes at any point, bad input: a point outside its mesh, coordinates not in whole points, a structure "
      "point in a scene without one: one line each", quick=True)
def test_point_probes_refused():
    return refused([
        ("outside", CHANNEL + ["-t_final", "0.0002", "-probes_fluid_velocity", "7,0.5"],
         "option -probes_fluid_velocity: the point (7., 0.5, 0.) is outside the fluid's mesh"),
        ("odd count", CHANNEL + ["-t_final", "0.0002", "-probes_structure_displacement", "1,1.05,2"],
         "option -probes_structure_displacement: expected the 2 coordinates of each point"),
        ("no structure", MMS_FLUID + ["-probes_structure_velocity", "0.5,0.5"],
         "option -probes_structure_velocity: this scene has no structure"),
    ])
