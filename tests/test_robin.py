"""Robin supports of the wall (-structure_boundary_NAME robin: the traction -(k eta + c etadot)):
the supported plate's closed forms, static and in time, alone and coupled to the fluid."""
import os

from harness import ROOT, WORK, adjoint_difference, probe_rows, refused, run, solve, test

PLATE = ["-options_file", os.path.join(ROOT, "options", "examples", "supported-plate.yaml")]
CHANNEL = ["-options_file", os.path.join(ROOT, "options", "channel2d.yaml")]
K, C, P, H = 50.0, 2.0, 2.0, 0.2  # the example's stiffness, damping, pressure, thickness; density 1
POINTS = ((0.3, 0.15), (0.7, 0.05))


@test("robin support, static: the plate on its foundation under a uniform pressure deflects by the closed form "
      "-p/k - p y/E at two points that are no nodes, to 1e-12 on both operator backends, on 1 and 2 ranks",
      quick=True)
def test_robin_static():
    worst = 0.0
    for backend, nproc in (("ceed", 1), ("petsc", 1), ("ceed", 2)):
        out = os.path.join(WORK, "robin-static-%s-%d" % (backend, nproc))
        solve(PLATE + ["-structure_time_order", "0", "-structure_boundary_bottom_damping", "0", "-dt", "0.1",
                       "-t_final", "0.2", "-fem_backend", backend],
              nproc=nproc, out=out)
        last = probe_rows(out)[-1]
        for x, y in POINTS:
            exact = -P / K - P * y / 100.0
            tag = "(%g;%g)" % (x, y)
            worst = max(worst, abs(last["eta_y" + tag] - exact) / abs(exact), abs(last["eta_x" + tag]) / abs(exact))
    assert worst <= 1e-12, "deflection off the closed form by %.1e" % worst
    return "closed form to %.1e" % worst


def oscillator(order, dt, steps, m):
    """The plate as a rigid mass m per unit area on the spring k and dashpot c, stepped by the
    wall's schemes: backward Euler (order 1) and the midpoint rule (order 2)"""
    x = v = 0.0
    out = []
    for _ in range(steps):
        x0 = x
        if order == 1:
            x = (-P + m * (x0 + dt * v) / dt ** 2 + C * x0 / dt) / (m / dt ** 2 + K + C / dt)
            v = (x - x0) / dt
        else:
            x = (-2 * P + 4 * m * (x0 + dt * v) / dt ** 2 - K * x0 + 2 * C * x0 / dt) / (4 * m / dt ** 2 + K + 2 * C / dt)
            v = 2 * (x - x0) / dt - v
        out.append(x)
    return out


@test("robin support, in time: a stiff plate follows the damped oscillator m x'' + c x' + k x = -p of its schemes "
      "(first order and midpoint), step by step over 100 steps to 2e-7 at E = 1e8, and the gap is the plate's "
      "compliance: ten times larger at E = 1e7")
def test_robin_dynamic():
    gaps = {}
    for order in (1, 2):
        for E in ("1e7", "1e8"):
            out = os.path.join(WORK, "robin-dynamic-%d-%s" % (order, E))
            solve(PLATE + ["-structure_time_order", str(order), "-structure_youngs_modulus", E], out=out)
            rows = probe_rows(out)[1:]
            exact = oscillator(order, 0.01, len(rows), 1.0 * H)
            peak = max(abs(x) for x in exact)
            gaps[order, E] = max(abs(r["eta_y(0.3;0.15)"] - x) for r, x in zip(rows, exact)) / peak
    for order in (1, 2):
        assert gaps[order, "1e8"] <= 2e-7, "order %d: off the oscillator by %.1e" % (order, gaps[order, "1e8"])
        ratio = gaps[order, "1e7"] / gaps[order, "1e8"]
        assert 8 <= ratio <= 12, "order %d: the gap does not scale with the compliance (ratio %.2f)" % (order, ratio)
    return "off the oscillator by %.1e (first order), %.1e (midpoint) at E = 1e8" % (gaps[1, "1e8"], gaps[2, "1e8"])


@test("robin support, coupled: the channel's wall supported on its top keeps the coupling's adjoint identity "
      "(1e-10) and, 20 steps into the pulse, deflects less the stiffer its support (k = 1e7, 1e9; a soft support "
      "changes the wall's frequency and may move it more at a given time)")
def test_robin_coupled():
    base = CHANNEL + ["-t_final", "0.002", "-structure_boundary_top", "robin"]
    deflections = []
    for k in ("1e7", "1e9"):
        out = os.path.join(WORK, "robin-coupled-" + k)
        rc, stdout, err, _ = run(base + ["-structure_boundary_top_stiffness", k, "-structure_boundary_top_damping", "10",
                                         "-coupling_test_adjoint"], out=out)
        assert rc == 0, err
        identity = adjoint_difference(stdout)
        assert abs(identity) <= 1e-10, "k = %s: <J h, r> - <h, J^T r> relative %.1e" % (k, identity)
        deflections.append(abs(probe_rows(out)[-1]["dy(1.5;1.)"]))
    free = os.path.join(WORK, "robin-coupled-free")
    solve(CHANNEL + ["-t_final", "0.002"], out=free)
    deflections.insert(0, abs(probe_rows(free)[-1]["dy(1.5;1.)"]))
    assert deflections[0] > deflections[1] > deflections[2] > 0, "deflections free, k 1e7, 1e9: %s" % deflections
    return "deflections %.3g (free), %.3g (k 1e7), %.3g (k 1e9)" % tuple(deflections)


@test("robin support, bad input: no stiffness, a stiffness of zero or below, a negative damping, an interface in a "
      "structure alone: one line each")
def test_robin_refused():
    return refused([
        ("no stiffness", CHANNEL + ["-structure_boundary_top", "robin"], "-structure_boundary_top_stiffness"),
        ("zero stiffness", PLATE + ["-structure_boundary_bottom_stiffness", "0"], "-structure_boundary_bottom_stiffness"),
        ("negative stiffness", PLATE + ["-structure_boundary_bottom_stiffness", "-5"],
         "-structure_boundary_bottom_stiffness"),
        ("negative damping", PLATE + ["-structure_boundary_bottom_damping", "-1"], "-structure_boundary_bottom_damping"),
        ("an interface alone", PLATE + ["-structure_boundary_left", "interface"], "-structure_boundary_left"),
    ]) or "5 inputs refused in one line each"
