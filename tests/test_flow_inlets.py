"""Flow-rate inlets of the general scene (-fluid_boundary_NAME flow: src/scenes/flow_profile.c):
a parabola scaled to Q(t) against the same profile written as an expression, the discrete
inflow against Q(t) on quadrilaterals, hexahedra and tetrahedra, Womersley's profile against
its closed form as the mesh resolves it, and the refusals."""
import cmath
import math
import os

from harness import ROOT, WORK, inputs_dir, read_probes, refused, solve, test

GENERAL_CHANNEL = os.path.join(ROOT, "options", "channel2d.yaml")
TUBE = os.path.join(ROOT, "options", "tube3d.yaml")
PULSE = '    left_traction: "t <= duration ? amplitude*(1-cos(2*pi*t/duration)) : 0, 0"\n'


def inlet_file(name, base, old_lines, new_lines):
    """an example options file with its inlet's lines replaced"""
    text = open(base).read()
    for old in old_lines:
        assert old in text, "%s lacks %r" % (base, old)
        text = text.replace(old, "")
    anchor = "  boundary:\n"
    text = text.replace(anchor, anchor + "".join("    %s\n" % l for l in new_lines), 1)
    path = os.path.join(inputs_dir(), name + ".yaml")
    open(path, "w").write(text)
    return ["-options_file", path]


def channel_inlet(name, lines):
    return inlet_file(name, GENERAL_CHANNEL, ["    left: traction\n", PULSE], lines)


def tube_inlet(name, lines):
    return inlet_file(name, TUBE, ["    inlet: pressure\n", '    inlet_pressure: "t <= duration*(1+1e-12) ? pressure : 0"\n'],
                      lines)


def columns(out):
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return {name: [r[i] for r in rows] for i, name in enumerate(head)}


def womersley_2d(t, y, coefficients, period, nu, half_width=0.5):
    """the closed form in a channel of half-width R centred at y = R: sum_k Re(c_k e^{ikwt} s_k / int s_k)"""
    w, v = 2 * math.pi / period, 0.0
    for k, c in coefficients.items():
        lam = half_width * math.sqrt(k * w / nu) * cmath.sqrt(1j)
        shape = 1 - cmath.cosh(lam * (y - half_width) / half_width) / cmath.cosh(lam)
        v += (c * cmath.exp(1j * k * w * t) * shape / (2 * half_width * (1 - cmath.tanh(lam) / lam))).real
    return v


@test("flow inlets: a parabolic profile scaled to Q(t) = 10 min(t/0.001, 1) gives the run of the velocity expression "
      "60 y (1 - y) min(t/0.001, 1) to 1e-12, and its discrete inflow is Q(t) to 1e-12", quick=True)
def test_flow_parabolic():
    expression = os.path.join(WORK, "flow-expression")
    solve(channel_inlet("flow-expression", ["left: velocity", 'left_velocity: "60*y*(1-y)*min(t/0.001, 1), 0"'])
          + ["-t_final", "0.002", "-integrals_flow_rate", "left"], out=expression)
    flow = os.path.join(WORK, "flow-parabolic")
    solve(channel_inlet("flow-parabolic", ["left: flow", 'left_flow_rate: "10*min(t/0.001, 1)"'])
          + ["-t_final", "0.002", "-integrals_flow_rate", "left"], out=flow)
    a, b = columns(expression), columns(flow)
    gap = max(abs(x - y) / max(max(abs(v) for v in a[k]), 1e-300) for k in a if k != "t" for x, y in zip(a[k], b[k]))
    inflow = max(abs(q + 10 * min(t / 0.001, 1)) for t, q in zip(b["t"], b["Q(left)"])) / 10
    assert gap <= 1e-12 and inflow <= 1e-12, "probes differ by %.1e; inflow off Q by %.1e of it" % (gap, inflow)
    return "probes the same to %.0e; inflow = Q to %.0e" % (gap, inflow)


@test("flow inlets: the discrete inflow is Q(t) to 1e-10 at every step for plug, parabolic and Womersley profiles on "
      "the tube's circular inlet, hexahedra and tetrahedra (the example's stabilized equal-order elements): each shape is scaled by its flow rate as the "
      "mesh carries it")
def test_flow_rate_3d():
    tets = ["-fluid_dm_plex_filename", os.path.join(ROOT, "meshes", "tube3d-fluid-tets.msh"),
            "-structure_dm_plex_filename", os.path.join(ROOT, "meshes", "tube3d-wall-tets.msh")]
    rate = "20*sin(2*_pi*t/0.2) + 5*(1-cos(4*_pi*t/0.2))"
    report = []
    for profile in ("plug", "parabolic", "womersley"):
        for mesh, extra in (("hex", []), ("tet", tets)):
            out = os.path.join(WORK, "flow-3d-%s-%s" % (profile, mesh))
            solve(tube_inlet("flow-3d-" + profile, ["inlet: flow", 'inlet_flow_rate: "%s"' % rate,
                                                    "inlet_profile: " + profile, "inlet_period: 0.2",
                                                    "inlet_harmonics: 3"])
                  + ["-t_final", "0.001", "-integrals_flow_rate", "inlet"] + extra, out=out)
            c = columns(out)
            q = [20 * math.sin(2 * math.pi * t / 0.2) + 5 * (1 - math.cos(4 * math.pi * t / 0.2)) for t in c["t"]]
            worst = max(abs(a + b) for a, b in zip(c["Q(inlet)"], q)) / max(abs(v) for v in q)
            assert worst <= 1e-10, "%s on %s: inflow off Q by %.1e of its largest" % (profile, mesh, worst)
            report.append(worst)
    return "6 runs of 10 steps: inflow = Q to %.0e" % max(report)


@test("flow inlets: Womersley's profile of Q = 10 sin(wt) + 4 cos(2wt) (period 0.1 s, Womersley numbers 21 and 30) "
      "at inlet nodes approaches the closed form as the mesh resolves its boundary layer (10 to 40 cells across: "
      "the gap shrinks at least 8-fold), while the discrete inflow is Q to 1e-10 on each mesh")
def test_flow_womersley():
    lines = ["left: flow", 'left_flow_rate: "10*sin(2*_pi*t/0.1) + 4*cos(4*_pi*t/0.1)"', "left_profile: womersley",
             "left_period: 0.1", "left_harmonics: 4"]
    coefficients = {1: -10j, 2: 4}
    gaps = []
    for cells in (10, 40):
        out = os.path.join(WORK, "flow-womersley-%d" % cells)
        solve(channel_inlet("flow-womersley", lines)
              + ["-t_final", "0.003", "-fluid_dm_plex_box_faces", "30,%d" % cells, "-integrals_flow_rate", "left",
                 "-probes_fluid_velocity", "0,0.5,0,0.05"], out=out)
        c = columns(out)
        q = [10 * math.sin(2 * math.pi * t / 0.1) + 4 * math.cos(4 * math.pi * t / 0.1) for t in c["t"]]
        inflow = max(abs(a + b) for a, b in zip(c["Q(left)"], q)) / max(abs(v) for v in q)
        assert inflow <= 1e-10, "%d cells: inflow off Q by %.1e" % (cells, inflow)
        gap = max(abs(c["u_x(%s)" % name][i] - womersley_2d(t, y, coefficients, 0.1, 0.035))
                  for name, y in (("0.;0.5", 0.5), ("0.;0.05", 0.05)) for i, t in enumerate(c["t"]))
        gaps.append(gap / max(abs(v) for v in c["u_x(0.;0.5)"]))
    assert gaps[1] * 8 <= gaps[0], "nodal gap to the closed form %.1e (10 cells), %.1e (40 cells)" % tuple(gaps)
    return "nodal gap to the closed form %.1e (10 cells) -> %.1e (40 cells)" % tuple(gaps)


@test("flow inlets, bad input: no flow rate, a Womersley profile without a period, a Womersley number beyond 60, "
      "harmonics out of range, an unknown profile: one line each", quick=True)
def test_flow_refused():
    short = ["-t_final", "0.0002"]
    womersley = ["left: flow", 'left_flow_rate: "sin(2*_pi*t/0.1)"', "left_profile: womersley"]
    return refused([
        ("no flow rate", channel_inlet("flow-no-rate", ["left: flow"]) + short, "-fluid_boundary_left_flow_rate"),
        ("womersley without period", channel_inlet("flow-no-period", womersley) + short, "-fluid_boundary_left_period"),
        ("womersley number 67", channel_inlet("flow-fast", womersley + ["left_period: 0.01"]) + short,
         "-fluid_boundary_left"),
        ("harmonics 0", channel_inlet("flow-h0", womersley + ["left_period: 0.1", "left_harmonics: 0"]) + short,
         "-fluid_boundary_left_harmonics"),
        ("unknown profile", channel_inlet("flow-unknown", ["left: flow", 'left_flow_rate: "1"',
                                                           "left_profile: poiseuille"]) + short,
         "-fluid_boundary_left_profile"),
    ]) or "5 inputs refused in one line each"
