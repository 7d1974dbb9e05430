"""Integrals over face sets (-integrals_*, src/report/face_integrals.c) and the 0D outlets of the
general scene (resistance, RCR: src/fluid/fluid_outlets.c): mass conservation, the outlet laws
as their discrete closed forms, the RCR outlet against its continuous closed form, Newton's
iterations with the outlets' Jacobian term, an exact restart, and the refusals."""
import math
import os

from harness import ROOT, WORK, inputs_dir, read_probes, refused, solve, test

GENERAL_CHANNEL = os.path.join(ROOT, "options", "channel2d.yaml")
DT = 1e-4


def channel(*extra):
    return ["-options_file", GENERAL_CHANNEL] + list(extra)


def columns(out):
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return {name: [r[i] for r in rows] for i, name in enumerate(head)}


@test("integrals: the flow rates out of the channel's four face sets sum to zero at every step to 1e-8 of the "
      "inflow (the discrete continuity equation tested with q = 1, on the moving mesh); the mean pressure of the "
      "inlet follows its pulse", quick=True)
def test_integrals_conservation():
    out = os.path.join(WORK, "integrals-conservation")
    solve(channel("-t_final", "0.003", "-integrals_flow_rate", "left,right,bottom,top",
                  "-integrals_mean_pressure", "left", "-integrals_force", "top"), out=out)
    c = columns(out)
    flows = [c["Q(%s)" % s] for s in ("left", "right", "bottom", "top")]
    inflow = max(abs(q) for q in flows[0])
    worst = max(abs(sum(q[k] for q in flows)) for k in range(len(flows[0]))) / inflow
    assert inflow > 0 and worst <= 1e-8, "flow rates sum to %.1e of the inflow %.3g" % (worst, inflow)
    assert all(q <= 0 for q in flows[0]) and max(flows[3]) > 0, "the inlet's flow is not inward, or the wall's outward"
    assert "F_x(top)" in c and "F_y(top)" in c and len(c["F_y(top)"]) == 31, "force columns: %s" % sorted(c)
    # the pulse 1e3 (1 - cos(2 pi t / 0.025)) pushes in: the inlet's mean pressure follows it within 2 %
    pulse = [1e3 * (1 - __import__("math").cos(2 * __import__("math").pi * t / 0.025)) for t in c["t"]]
    gap = max(abs(p - q) for p, q in zip(c["p_mean(left)"], pulse)) / max(pulse)
    assert gap <= 0.02, "the inlet's mean pressure differs from the pulse by %.1e of its peak" % gap
    return "30 steps: flow rates sum to %.0e of the inflow; inlet mean pressure within %.1e of the pulse" % (
        worst, gap)


@test("0D outlets: a resistance's p = R Q and an RCR's P_c^{n+1} = (P_c^n + dt/C (Q^{n+1} + P_d/R_d)) / "
      "(1 + dt/(R_d C)) hold at every step to 1e-10 (the model implicit in the step: Q of the new state); "
      "Q_outlet is the face set's flow rate; the fluid's linear solves with R = 1e5 stay within 5 % of R = 0 "
      "(the model's rank-one Jacobian term), on both operator backends")
def test_outlet_laws():
    report = []
    counts = {}
    for R in ("0", "1e5"):
        out = os.path.join(WORK, "outlet-resistance-%s" % R)
        s = solve(channel("-t_final", "0.005", "-fluid_boundary_right", "resistance",
                          "-fluid_boundary_right_resistance", R, "-integrals_flow_rate", "right"), out=out)
        c = columns(out)
        q, p = c["Q_outlet(right)"], c["p_outlet(right)"]
        scale = max(abs(x) for x in q) * max(float(R), 1)
        worst = max(abs(pk - float(R) * qk) for pk, qk in zip(p, q)) / scale
        same = max(abs(a - b) for a, b in zip(q, c["Q(right)"])) / max(abs(x) for x in q)
        assert worst <= 1e-12 and same <= 1e-12, "R = %s: p - R Q %.1e, Q_outlet - Q %.1e" % (R, worst, same)
        counts[R] = s["fluid_linear_solves"]
    growth = counts["1e5"] / counts["0"]
    assert growth <= 1.05, "fluid linear solves %d (R = 1e5) against %d (R = 0)" % (counts["1e5"], counts["0"])
    report.append("resistance exact; linear solves %d (R = 1e5) vs %d (R = 0)" % (counts["1e5"], counts["0"]))
    Rp, C, Rd, Pd = 1000.0, 1e-4, 1e4, 5.0
    for backend in ("petsc", "ceed"):
        out = os.path.join(WORK, "outlet-rcr-" + backend)
        solve(channel("-t_final", "0.005", "-fluid_boundary_right", "rcr", "-fluid_boundary_right_rcr",
                      "%g,%g,%g" % (Rp, C, Rd), "-fluid_boundary_right_distal_pressure", "%g" % Pd,
                      "-fem_backend", backend), out=out)
        c = columns(out)
        pc = [p - Rp * q for p, q in zip(c["p_outlet(right)"], c["Q_outlet(right)"])]
        assert abs(pc[0] - Pd) <= 1e-12 * Pd, "P_c at rest %.17g, expected P_d = %g" % (pc[0], Pd)
        law = max(abs(pc[k] - (pc[k - 1] + DT / C * (c["Q_outlet(right)"][k] + Pd / Rd)) / (1 + DT / (Rd * C)))
                  for k in range(1, len(pc))) / max(abs(x) for x in pc)
        assert law <= 1e-10, "%s: the RCR law holds to %.1e only" % (backend, law)
        report.append("RCR law to %.0e (%s)" % (law, backend))
    return "; ".join(report)


@test("0D outlets: a run restarted from a checkpoint at step 20 gives the uninterrupted run's outlet pressure and "
      "probes to 1e-6 at -coupling_tol 1e-8 (the capacitor's pressure is in the checkpoint; the coupling's own start "
      "after a restart differs within its tolerance, and the capacitor integrates that difference)")
def test_outlet_restart():
    rcr = ["-fluid_boundary_right", "rcr", "-fluid_boundary_right_rcr", "1000,1e-4,1e4",
           "-fluid_boundary_right_distal_pressure", "5", "-coupling_tol", "1e-8"]
    whole = os.path.join(WORK, "outlet-whole")
    solve(channel(*rcr, "-t_final", "0.004"), out=whole)
    first = os.path.join(WORK, "outlet-first")
    solve(channel(*rcr, "-t_final", "0.002", "-checkpoint_every", "20"), out=first)
    again = os.path.join(WORK, "outlet-again")
    solve(channel(*rcr, "-t_final", "0.004", "-restart", os.path.join(first, "checkpoint.h5")), out=again)
    a, b = columns(whole), columns(again)
    n = len(a["t"])
    assert len(b["t"]) == n and b["t"][-1] == a["t"][-1], "rows: %d restarted, %d whole" % (len(b["t"]), n)
    worst = max(abs(x - y) / max(max(abs(v) for v in a[k]), 1e-300)
                for k in a if k != "t" for x, y in zip(a[k][21:], b[k][21:]))
    assert worst <= 1e-6, "the restarted run differs by %.1e" % worst
    return "steps 21-40 restarted = uninterrupted to %.0e" % worst


@test("0D outlets and integrals, bad input: an outlet without its parameters, with the wrong count, negative, an "
      "RCR without capacitance, a distal pressure not finite, an integral over a face set the mesh lacks: one line "
      "each", quick=True)
def test_outlets_refused():
    short = ["-t_final", "0.0002"]
    right = ["-fluid_boundary_right"]
    return refused([
        ("resistance without R", channel(*right, "resistance", *short), "-fluid_boundary_right_resistance"),
        ("rcr of two numbers", channel(*right, "rcr", "-fluid_boundary_right_rcr", "1,2", *short),
         "-fluid_boundary_right_rcr"),
        ("negative resistance", channel(*right, "resistance", "-fluid_boundary_right_resistance", "-3", *short),
         "-fluid_boundary_right_resistance"),
        ("rcr without capacitance", channel(*right, "rcr", "-fluid_boundary_right_rcr", "1,0,2", *short),
         "-fluid_boundary_right_rcr"),
        ("distal pressure nan", channel(*right, "resistance", "-fluid_boundary_right_resistance", "10",
                                        "-fluid_boundary_right_distal_pressure", "nan", *short),
         "-fluid_boundary_right_distal_pressure"),
        ("integral over a missing face set", channel("-integrals_flow_rate", "left,outlet", *short),
         "-integrals_flow_rate"),
        ("integral over no face set", channel("-integrals_mean_pressure", "", *short), "-integrals_mean_pressure"),
    ]) or "7 inputs refused in one line each"


@test("integrals in 3D: the flow rates through the tube's inlet, outlet and moving wall sum to zero at every step to "
      "1e-7 of the inflow, on hexahedra (bilinear faces: normals from the cell's own Jacobian) and on tetrahedra, "
      "with an RCR outlet")
def test_integrals_3d():
    example = os.path.join(ROOT, "options", "tube3d.yaml")
    tets = ["-fluid_dm_plex_filename", os.path.join(ROOT, "meshes", "tube3d-fluid-tets.msh"),
            "-structure_dm_plex_filename", os.path.join(ROOT, "meshes", "tube3d-wall-tets.msh")]
    report = []
    for name, mesh in (("hexahedra", []), ("tetrahedra", tets)):
        out = os.path.join(WORK, "integrals-3d-" + name)
        # the fluid solved to 1e-8 of its right-hand side, so that the balance measures the
        # integrals, not the solve (the scene's 1e-6 leaves about 4e-6 of the inflow)
        solve(["-options_file", example, "-t_final", "0.004", "-integrals_flow_rate", "inlet,outlet,interface",
               "-fluid_boundary_outlet", "rcr", "-fluid_boundary_outlet_rcr", "100,1e-4,1000",
               "-fluid_snes_rtol", "1e-7", "-fluid_rhs_rtol", "1e-8"] + mesh, out=out)
        c = columns(out)
        flows = [c["Q(%s)" % s] for s in ("inlet", "outlet", "interface")]
        inflow = max(abs(q) for q in flows[0])
        worst = max(abs(sum(q[k] for q in flows)) for k in range(len(flows[0]))) / inflow
        assert worst <= 1e-7, "%s: flow rates sum to %.1e of the inflow" % (name, worst)
        report.append("%s %.0e" % (name, worst))
    return "40 steps: flow rates sum to " + ", ".join(report) + " of the inflow"


@test("bifurcation example (options/examples/bifurcation.yaml: a 3D vessel branching in two, a Womersley inflow "
      "from a waveform file, two RCR outlets, meshes from .geo at run time), its first 10 steps: the flow rates "
      "through inlet, outlets and wall sum to zero to 1e-6 of the inflow (the fluid's Newton tolerance), each outlet follows its RCR law to 1e-10, "
      "and the two symmetric daughters carry the same flow to 1e-3")
def test_bifurcation_example():
    out = os.path.join(WORK, "bifurcation")
    solve(["-options_file", os.path.join(ROOT, "options", "examples", "bifurcation.yaml"), "-t_final", "0.02",
           "-integrals_flow_rate", "inlet,outlet_left,outlet_right,interface"], out=out)
    c = columns(out)
    flows = [c["Q(%s)" % s] for s in ("inlet", "outlet_left", "outlet_right", "interface")]
    inflow = max(abs(q) for q in flows[0])
    # from step 1: the state at t = 0 is the fluid at rest with the inlet's velocity inserted
    worst = max(abs(sum(q[k] for q in flows)) for k in range(1, len(flows[0]))) / inflow
    assert inflow > 0 and worst <= 1e-6, "flow rates sum to %.1e of the inflow" % worst
    Rp, C, Rd, dt = 5e3, 1e-5, 4.3e4, 2e-3
    for side in ("left", "right"):
        q, p = c["Q_outlet(outlet_%s)" % side], c["p_outlet(outlet_%s)" % side]
        pc = [pk - Rp * qk for pk, qk in zip(p, q)]
        law = max(abs(pc[k] - (pc[k - 1] + dt / C * q[k]) / (1 + dt / (Rd * C))) for k in range(1, len(pc)))
        assert law <= 1e-10 * max(abs(x) for x in pc), "outlet_%s: the RCR law holds to %.1e only" % (side, law)
    split = max(abs(a - b) for a, b in zip(flows[1], flows[2])) / max(abs(x) for x in flows[1])
    assert split <= 1e-3, "the symmetric daughters' flows differ by %.1e" % split
    return "10 steps: flow rates sum to %.0e of the inflow; RCR laws hold; daughters' flows within %.0e" % (worst, split)


@test("RCR outlet under a constant inflow (the rigid channel, the fluid alone): the outlet pressure follows the "
      "closed form R_p Q + R_d Q (1 - e^{-t/(R_d C)}) to 1 % at every step (Delta t = R_d C / 50) and reaches "
      "(R_p + R_d) Q to 1e-4 after ten time constants")
def test_rcr_closed_form():
    rp, c, rd = 100.0, 1e-3, 100.0
    text = open(os.path.join(ROOT, "options", "examples", "rigid-channel.yaml")).read()
    old = '    right: traction\n    right_traction: "0, 0.035*4*(1-2*y)"\n'
    assert old in text, "rigid-channel.yaml lacks its outlet's traction"
    path = os.path.join(inputs_dir(), "rigid-channel-rcr.yaml")
    open(path, "w").write(text.replace(old, "    right: rcr\n    right_rcr: %g,%g,%g\n" % (rp, c, rd)))
    out = os.path.join(WORK, "rcr-closed-form")
    solve(["-options_file", path, "-fluid_steady", "0", "-dt", "2e-3", "-t_final", "1"], out=out)
    c_ = columns(out)
    tau, worst = rd * c, 0.0
    for t, q, p in zip(c_["t"][1:], c_["Q_outlet(right)"][1:], c_["p_outlet(right)"][1:]):
        worst = max(worst, abs(p - (rp * q + rd * q * (1 - math.exp(-t / tau)))) / ((rp + rd) * q))
    final = abs(c_["p_outlet(right)"][-1] / ((rp + rd) * c_["Q_outlet(right)"][-1]) - 1)
    assert worst <= 1e-2 and final <= 1e-4, "off the closed form by %.1e of (R_p + R_d) Q; at t = 10 R_d C by %.1e" % (
        worst, final)
    return "off the closed form by %.1e at most (Delta t = R_d C/50); %.1e from (R_p + R_d) Q at t = 10 R_d C" % (
        worst, final)


@test("wall shear stress (-integrals_wall_shear_stress): Poiseuille flow in the rigid channel has the closed form "
      "4 mu U/H on both walls, to 1e-12 on 30x10 and 60x20 cells")
def test_wall_shear_stress():
    rigid = ["-options_file", os.path.join(ROOT, "options", "examples", "rigid-channel.yaml"),
             "-integrals_wall_shear_stress", "bottom,top"]
    exact, worst = 4 * 0.035 * 1.0 / 1.0, 0.0
    for faces in ("30,10", "60,20"):
        out = os.path.join(WORK, "wss-" + faces.replace(",", "x"))
        solve(rigid + ["-fluid_dm_plex_box_faces", faces], out=out)
        c = columns(out)
        worst = max(worst, abs(c["tau_w(bottom)"][-1] - exact) / exact, abs(c["tau_w(top)"][-1] - exact) / exact)
    assert worst <= 1e-12, "off 4 mu U/H by %.1e" % worst
    return "4 mu U/H = %g to %.1e on both meshes" % (exact, worst)
