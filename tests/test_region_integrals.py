"""Integrals over the fluid's regions (-integrals_region_volume, _mean_pressure,
_kinetic_energy): Poiseuille's closed forms, a named region against the whole mesh, the moving
channel's volume against its flow rates, and the refusals."""
import math
import os

from harness import ROOT, WORK, probe_rows, refused, solve, test

RIGID = ["-options_file", os.path.join(ROOT, "options", "examples", "rigid-channel.yaml")]
CHANNEL = ["-options_file", os.path.join(ROOT, "options", "channel2d.yaml")]
TUBE = ["-options_file", os.path.join(ROOT, "options", "tube3d.yaml")]


@test("region integrals: Poiseuille flow in the rigid channel (the fluid alone, steady) has the area 6, the mean "
      "pressure 24 mu U and the kinetic energy rho 6 U^2 8/30 of its closed form to 1e-12, on 1 and 2 ranks",
      quick=True)
def test_region_poiseuille():
    exact = {"V(all)": 6.0, "p_region(all)": 24 * 0.035, "E_kin(all)": 6 * 8 / 30}
    worst = 0.0
    for nproc in (1, 2):
        out = os.path.join(WORK, "region-poiseuille-%d" % nproc)
        solve(RIGID, nproc=nproc, out=out)
        last = probe_rows(out)[-1]
        worst = max([worst] + [abs(last[k] - v) / v for k, v in exact.items()])
    assert worst <= 1e-12, "off the closed form by %.1e" % worst
    return "closed forms to %.1e" % worst


@test("region integrals: tube3d's fluid region named blood (its gmsh physical volume) gives the whole mesh's volume, "
      "mean pressure and kinetic energy to 1e-12; its volume is the prism's (N/2) sin(2 pi/N) r^2 L over the "
      "O-grid's N = 16 sides to 1e-12")
def test_region_named():
    out = os.path.join(WORK, "region-tube")
    solve(TUBE + ["-t_final", "3e-4", "-integrals_region_volume", "blood,all", "-integrals_region_mean_pressure",
                  "blood,all", "-integrals_region_kinetic_energy", "blood,all"], out=out)
    rows = probe_rows(out)
    same = max(abs(r["%s(blood)" % k] - r["%s(all)" % k]) / max(abs(r["%s(all)" % k]), 1e-300)
               for r in rows[1:] for k in ("V", "p_region", "E_kin"))
    prism = 16 / 2 * math.sin(2 * math.pi / 16) * 0.25 * 5
    geometric = abs(rows[0]["V(all)"] - prism) / prism
    assert same <= 1e-12 and geometric <= 1e-12, "blood vs all %.1e; volume %.15g vs %.15g" % (
        same, rows[0]["V(all)"], prism)
    return "blood = all to %.1e; volume %.6g = the prism's to %.1e (pi r^2 L = %.5g)" % (
        same, rows[0]["V(all)"], geometric, math.pi * 0.25 * 5)


@test("region integrals: the channel's fluid area grows, step by step, by the net inflow dt (Q_in - Q_out) to 2e-3 "
      "of each step's change over 100 steps (the mesh's straight-sided cells against the Q2 interface velocity)")
def test_region_volume_balance():
    out = os.path.join(WORK, "region-balance")
    solve(CHANNEL + ["-t_final", "0.01", "-integrals_region_volume", "all", "-integrals_flow_rate", "left,right"],
          out=out)
    rows = probe_rows(out)
    steps = [(b["V(all)"] - a["V(all)"], -(b["t"] - a["t"]) * (b["Q(left)"] + b["Q(right)"]))
             for a, b in zip(rows, rows[1:])]
    largest = max(abs(dv) for dv, _ in steps)
    gap = max(abs(dv - flux) for dv, flux in steps) / largest
    assert largest > 0 and gap <= 2e-3, "area change against the net inflow: %.1e of the largest step's" % gap
    return "area %.6g -> %.6g; off the net inflow by %.1e of the largest step's change" % (
        rows[0]["V(all)"], rows[-1]["V(all)"], gap)


@test("region integrals, bad input: a region the fluid mesh lacks (its regions listed, all named): one line")
def test_region_refused():
    return refused([
        ("no such region", TUBE + ["-integrals_region_volume", "plasma"], "the fluid mesh has no region plasma"),
        ("box mesh", RIGID + ["-integrals_region_kinetic_energy", "1"], "-integrals_region_kinetic_energy"),
    ]) or "2 cases"
