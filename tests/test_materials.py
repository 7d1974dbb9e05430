"""Materials per region of the wall (-structure_region_NAME_model, _youngs_modulus,
_poisson_ratio, _density): the two-layer plate's closed forms, static and in time, the model
per region, the backends' agreement, and the refusals."""
import os

from harness import ROOT, WORK, probe_rows, refused, run, solve, test

PLATE = ["-options_file", os.path.join(ROOT, "options", "examples", "layered-plate.yaml")]
P = 2.0  # the example's pressure; E_inner = 400, E_outer = 100, densities 3 and 1, layers 0.1 thick


@test("materials per region, static: the two-layer plate under a uniform pressure deflects by the closed form of "
      "two springs in series at a point of each layer that is no node, to 1e-12, on both operator backends and on "
      "2 ranks", quick=True)
def test_materials_static():
    exact = {"eta_y(0.3;0.05)": -P * 0.05 / 400, "eta_y(0.7;0.15)": -P * 0.1 / 400 - P * 0.05 / 100}
    worst = 0.0
    for backend, nproc in (("ceed", 1), ("petsc", 1), ("ceed", 2)):
        out = os.path.join(WORK, "materials-static-%s-%d" % (backend, nproc))
        solve(PLATE + ["-fem_backend", backend], nproc=nproc, out=out)
        values = probe_rows(out)[-1]
        worst = max([worst] + [abs(values[k] - v) / abs(v) for k, v in exact.items()])
    assert worst <= 1e-12, "deflections off the closed form by %.1e" % worst
    return "closed form to %.1e" % worst


@test("materials per region, in time: on a Robin support the stiff two-layer plate follows the oscillator of its "
      "total mass (rho_inner h + rho_outer h) over 100 steps to 2e-7 of its peak: each layer's density counts")
def test_materials_density():
    k, c, dt = 50.0, 2.0, 0.01
    out = os.path.join(WORK, "materials-density")
    solve(PLATE + ["-structure_boundary_bottom", "robin", "-structure_boundary_bottom_stiffness", str(k),
                   "-structure_boundary_bottom_damping", str(c), "-structure_time_order", "1", "-dt", str(dt),
                   "-t_final", "1", "-structure_youngs_modulus", "1e8", "-structure_region_inner_youngs_modulus",
                   "4e8"], out=out)
    rows = probe_rows(out)[1:]
    m, x, v, gap, peak = 3 * 0.1 + 1 * 0.1, 0.0, 0.0, 0.0, 0.0
    for r in rows:
        x0 = x
        x = (-P + m * (x0 + dt * v) / dt ** 2 + c * x0 / dt) / (m / dt ** 2 + k + c / dt)
        v = (x - x0) / dt
        gap, peak = max(gap, abs(r["eta_y(0.7;0.15)"] - x)), max(peak, abs(x))
    assert gap / peak <= 2e-7, "off the oscillator of mass %g by %.1e of its peak" % (m, gap / peak)
    return "off the oscillator of mass 0.4 by %.1e of its peak" % (gap / peak)


@test("materials per region, the model: St. Venant-Kirchhoff named region by region equals the wall made St. "
      "Venant-Kirchhoff as a whole (to 1e-12), and departs from the linear wall under a large load; libCEED equals "
      "PETSc with the two models side by side (-fem_backend_check, 1e-12)")
def test_materials_model():
    load = ["-structure_boundary_top_pressure", "40", "-structure_time_order", "1", "-dt", "0.01", "-t_final", "0.05"]
    regions = os.path.join(WORK, "materials-svk-regions")
    solve(PLATE + load + ["-structure_region_inner_model", "svk", "-structure_region_outer_model", "svk"], out=regions)
    whole = os.path.join(WORK, "materials-svk-whole")
    solve(PLATE + load + ["-structure_model", "svk", "-structure_region_outer_model", "svk"], out=whole)
    linear = os.path.join(WORK, "materials-linear")
    solve(PLATE + load, out=linear)
    a, b, l = (probe_rows(d)[-1] for d in (regions, whole, linear))
    same = max(abs(a[k] - b[k]) / max(abs(b[k]), 1e-30) for k in a if k.startswith("eta_y"))
    apart = max(abs(a[k] - l[k]) / abs(l[k]) for k in a if k.startswith("eta_y"))
    assert same <= 1e-12 and apart >= 1e-3, "regions vs whole %.1e, vs linear %.1e" % (same, apart)
    rc, stdout, err, _ = run(PLATE + load + ["-structure_region_inner_model", "svk", "-fem_backend_check"],
                             out=os.path.join(WORK, "materials-check"))
    assert rc == 0, err
    diffs = [float(w) for line in stdout.splitlines() if line.startswith("fsiopt: backend check:")
             for w in line.replace(",", " ").split() if w[0].isdigit() and "e" in w]
    assert diffs and max(diffs) <= 1e-12, "backend check: %s" % diffs
    return "regions = whole to %.1e; %.1e from linear; backends within %.1e" % (same, apart, max(diffs))


@test("materials per region, bad input: a region the mesh lacks (its names listed), an option of no known kind, an "
      "unknown model, a Poisson ratio of 0.5: one line each")
def test_materials_refused():
    return refused([
        ("no such region", PLATE + ["-structure_region_middle_density", "2"], "the structure mesh has no region middle"),
        ("unknown kind", PLATE + ["-structure_region_inner_young", "5"], "-structure_region_inner_young"),
        ("unknown model", PLATE + ["-structure_region_inner_model", "rubber"], "-structure_region_inner_model"),
        ("incompressible", PLATE + ["-structure_region_inner_poisson_ratio", "0.5"],
         "-structure_region_inner_poisson_ratio"),
    ]) or "4 inputs refused in one line each"
