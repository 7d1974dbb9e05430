"""Fields at every Lagrange node (-write_fields_nodes all) and the derived fields of
-write_fields_derived (src/report/fields_grid.c, fields_derived.c) against closed forms:
Poiseuille flow, which the (Q2,Q1) and (P2,P1) spaces hold exactly, on quadrilaterals,
triangles, hexahedra and tetrahedra, and a layered plate under a uniform pressure."""
import os, subprocess, sys

import numpy as np

from harness import ROOT, WORK, inputs_dir, refused, run, solve, test
from test_fields import VTK_SITE, read_fields

CHANNEL2D = ["-options_file", os.path.join(ROOT, "options", "examples", "rigid-channel.yaml")]
PLATE = ["-options_file", os.path.join(ROOT, "options", "examples", "layered-plate.yaml")]
MU, G = 0.035, 8 * 0.035   # the channels' viscosity and pressure gradient 8 mu U / H^2 (U = 1, H = 1)
BOX = """SetFactory("OpenCASCADE");
DefineConstant[ hexahedra = 1 ];
Box(1) = {0, 0, 0, 2, 1, 1};
e = 1e-6;
Physical Surface("inlet") = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 1 + e};
Physical Surface("outlet") = Surface In BoundingBox{2 - e, -e, -e, 2 + e, 1 + e, 1 + e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 2 + e, e, 1 + e};
Physical Surface("top") = Surface In BoundingBox{-e, 1 - e, -e, 2 + e, 1 + e, 1 + e};
Physical Surface("sides") = Surface In BoundingBox{-e, -e, -e, 2 + e, 1 + e, e};
Physical Surface("sides") += Surface In BoundingBox{-e, -e, 1 - e, 2 + e, 1 + e, 1 + e};
Physical Volume("fluid") = {1};
Transfinite Curve{:} = 3;
If (hexahedra)
  Transfinite Surface{:};
  Recombine Surface{:};
  Transfinite Volume{1};
EndIf
"""
PROFILE = "4*y*(1-y), 0, 0"
RECTANGLE = """SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 6, 1};
e = 1e-6;
Physical Curve("left") = Curve In BoundingBox{-e, -e, -e, e, 1 + e, e};
Physical Curve("right") = Curve In BoundingBox{6 - e, -e, -e, 6 + e, 1 + e, e};
Physical Curve("bottom") = Curve In BoundingBox{-e, -e, -e, 6 + e, e, e};
Physical Curve("top") = Curve In BoundingBox{-e, 1 - e, -e, 6 + e, 1 + e, e};
Physical Surface("fluid") = {1};
Mesh.MeshSizeMax = 0.25;
"""


def triangles():
    """rigid-channel.yaml's channel on an unstructured mesh of triangles"""
    geo = os.path.join(inputs_dir(), "rectangle.geo")
    with open(geo, "w") as f:
        f.write(RECTANGLE)
    return ["-scene", "general", "-general_physics", "fluid", "-units", "cgs", "-dt", "1", "-t_final", "1",
            "-fluid_dm_plex_filename", geo, "-fluid_density", "1", "-fluid_viscosity", str(MU), "-fluid_steady", "1",
            "-fluid_boundary_left", "velocity", "-fluid_boundary_left_velocity", "4*y*(1-y), 0",
            "-fluid_boundary_bottom", "wall", "-fluid_boundary_top", "wall",
            "-fluid_boundary_right", "traction", "-fluid_boundary_right_traction", "0, %g*4*(1-2*y)" % MU]


def box(hexahedra):
    """Poiseuille flow between the plates y = 0, 1 of a 2 x 1 x 1 box (the exact profile on
    its inlet and sides, the exact traction on its outlet), 2 x 1 x 1 hexahedra or tetrahedra"""
    geo = os.path.join(inputs_dir(), "box.geo")
    with open(geo, "w") as f:
        f.write(BOX)
    return ["-scene", "general", "-general_physics", "fluid", "-general_dim", "3", "-units", "cgs", "-dt", "1",
            "-t_final", "1", "-fluid_dm_plex_filename", geo, "-fluid_geo_setnumber", "hexahedra,%d" % hexahedra,
            "-fluid_density", "1", "-fluid_viscosity", str(MU), "-fluid_steady", "1",
            "-fluid_boundary_inlet", "velocity", "-fluid_boundary_inlet_velocity", PROFILE,
            "-fluid_boundary_sides", "velocity", "-fluid_boundary_sides_velocity", PROFILE,
            "-fluid_boundary_bottom", "wall", "-fluid_boundary_top", "wall",
            "-fluid_boundary_outlet", "traction", "-fluid_boundary_outlet_traction", "0, %g*4*(1-2*y), 0" % MU]


CASES = {"quadrilaterals": (lambda: CHANNEL2D, 300, 4, 6.0), "triangles": (triangles, None, 4, 6.0),
         "hexahedra": (lambda: box(1), 8, 8, 2.0), "tetrahedra": (lambda: box(0), None, 8, 2.0)}


def signed_volumes(x, cells):
    """Each written cell's measure, signed by VTK's orientation (at the first corner for a
    quadrilateral or hexahedron)"""
    p = x[cells]
    if cells.shape[1] == 3:
        a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        return (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) / 2
    if cells.shape[1] == 4 and x.shape[1] == 2:   # the shoelace formula
        return sum(p[:, k, 0] * p[:, (k + 1) % 4, 1] - p[:, (k + 1) % 4, 0] * p[:, k, 1] for k in range(4)) / 2
    if cells.shape[1] == 4:
        return np.linalg.det(np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]], axis=1)) / 6
    jacobian = np.linalg.det(np.stack([p[:, 1] - p[:, 0], p[:, 3] - p[:, 0], p[:, 4] - p[:, 0]], axis=1))
    return jacobian   # a box's hexahedra: its volume


def check_readers(out):
    env = dict(os.environ, PYTHONPATH=VTK_SITE) if VTK_SITE else None
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "check_fields.py"), "--readers", "require", out],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 0, "check_fields %s: %s" % (out, (p.stderr or p.stdout).strip())


@test("fields at every node: Poiseuille's velocity at each written node of (Q2,Q1) quadrilaterals and hexahedra and "
      "(P2,P1) triangles and tetrahedra equals the closed form to 1e-11; each cell written as its 4 (2D) or 8 (3D) "
      "refined cells, all oriented as VTK's, filling the domain; VTK's XDMF reader reads them")
def test_fields_every_node():
    details = []
    for name, (args, cells, children, volume) in CASES.items():
        out = os.path.join(WORK, "every-node-" + name)
        solve(args() + ["-write_fields"], out=out)
        fluid = read_fields(out)["fluid"][1]
        import h5py
        with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
            topology = h5["fluid/topology"][()]
        x, u = fluid["geometry"], fluid["velocity"]
        exact = 4 * x[:, 1] * (1 - x[:, 1])
        error = max(abs(u[:, 0] - exact).max(), abs(u[:, 1:]).max())
        v = signed_volumes(x, topology)
        assert error <= 1e-11, "%s: velocity off the closed form by %.1e at the written nodes" % (name, error)
        assert (cells is None or len(topology) == children * cells) and len(topology) % children == 0, \
            "%s: %d written cells for %s mesh cells" % (name, len(topology), cells)
        assert v.min() > 0 and abs(v.sum() - volume) <= 1e-12 * volume, \
            "%s: cell measures from %.2e, total %.15g (domain %g)" % (name, v.min(), v.sum(), volume)
        check_readers(out)
        details.append("%s %d nodes, %d cells, %.0e" % (name, len(x), len(topology), error))
    return "; ".join(details)


@test("derived fields on Poiseuille flow: vorticity = -4(1-2y) and Q = 0 at every node, the wall shear stress "
      "4 mu U / H along the flow and the normal stress -p(x) on both walls, to 1e-11, on quadrilaterals (1 and 2 "
      "ranks), triangles, hexahedra and tetrahedra")
def test_derived_poiseuille():
    derived = ["-write_fields", "-write_fields_derived", "vorticity,q_criterion,traction,normal_stress,wall_shear_stress",
               "-write_fields_walls", "bottom,top"]
    details = []
    for name, nproc in (("quadrilaterals", 1), ("quadrilaterals", 2), ("triangles", 1), ("hexahedra", 1),
                        ("tetrahedra", 1)):
        args = CASES[name][0]()
        out = os.path.join(WORK, "derived-%s-%d" % (name, nproc))
        solve(args + derived, nproc=nproc, out=out)
        got = read_fields(out)
        fluid, walls = got["fluid"][1], got["walls"][1]
        y, xw = fluid["geometry"][:, 1], walls["geometry"]
        omega = fluid["vorticity"] if fluid["vorticity"].ndim == 1 else fluid["vorticity"][:, 2]
        others = 0.0 if fluid["vorticity"].ndim == 1 else abs(fluid["vorticity"][:, :2]).max()
        length = CASES[name][3]
        gaps = {"vorticity": max(abs(omega + 4 * (1 - 2 * y)).max(), others),
                "Q": abs(fluid["q_criterion"]).max(),
                "wall shear stress": max(abs(walls["wall_shear_stress"][:, 0] - 4 * MU).max(),
                                         abs(walls["wall_shear_stress"][:, 1:]).max()),
                "normal stress": abs(walls["normal_stress"] + G * (length - xw[:, 0])).max(),
                "traction": abs(walls["traction"][:, 0] + 4 * MU).max()}
        on_walls = np.minimum(abs(xw[:, 1]), abs(xw[:, 1] - 1)).max()
        assert on_walls <= 1e-12 and max(gaps.values()) <= 1e-11, "%s on %d: %s, walls' nodes %.1e off the walls" % (
            name, nproc, ", ".join("%s %.1e" % kv for kv in gaps.items()), on_walls)
        details.append("%s (%d) %.0e" % (name, nproc, max(gaps.values())))
    return "largest gap: " + "; ".join(details)


@test("derived fields in the wall: the layered plate's Cauchy stress diag(0, -p, 0) and von Mises stress p in both "
      "layers (E and 4E), linear and St. Venant-Kirchhoff, on both operator backends and 2 ranks, to 1e-12 of p")
def test_derived_plate_stress():
    p, details = 2.0, []
    for model, backend, nproc in (("linear", "ceed", 1), ("linear", "petsc", 1), ("svk", "ceed", 1), ("linear", "ceed", 2)):
        out = os.path.join(WORK, "derived-plate-%s-%s-%d" % (model, backend, nproc))
        solve(PLATE + ["-fem_backend", backend, "-structure_model", model, "-structure_region_outer_model", model,
                       "-write_fields", "-write_fields_derived", "stress,von_mises"], nproc=nproc, out=out)
        wall = read_fields(out)["structure"]
        last = wall[max(wall)]
        want = np.zeros(9)
        want[4] = -p
        gap = max(abs(last["stress"] - want).max(), abs(last["von_mises"] - p).max()) / p
        assert gap <= 1e-12, "%s, %s, %d ranks: stress off diag(0, -p, 0) by %.1e of p" % (model, backend, nproc, gap)
        details.append("%s/%s/%d %.0e" % (model, backend, nproc, gap))
    return "; ".join(details)


@test("derived fields only when asked: none, and no walls' grid, without -write_fields_derived; every dataset names "
      "its unit; bad derived-field options refused in one line", quick=True)
def test_derived_only_when_asked():
    import h5py
    out = os.path.join(WORK, "derived-none")
    solve(CHANNEL2D + ["-write_fields"], out=out)
    with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
        grids = sorted(k for k in h5)
        names = set(h5["fluid/step_00001"])
        units = {k: h5["fluid"].attrs[k].decode() for k in h5["fluid"].attrs}
    assert grids == ["fluid"] and names == {"geometry", "velocity", "pressure"}, "grids %s, datasets %s" % (grids, names)
    assert units == {"geometry unit": "cm", "velocity unit": "cm/s", "pressure unit": "dyn/cm^2"}, "units %s" % units
    asked = CHANNEL2D + ["-write_fields", "-write_fields_derived"]
    cases = [("unknown field", asked + ["vorticity,swirl"], "-write_fields_derived"),
             ("wall stress without a wall", asked + ["stress"], "-write_fields_derived"),
             ("wall fields without an interface or walls", asked + ["wall_shear_stress"], "-write_fields_walls"),
             ("unknown wall", asked + ["normal_stress", "-write_fields_walls", "roof"], "-write_fields_walls"),
             ("unknown node set", CHANNEL2D + ["-write_fields", "-write_fields_nodes", "edges"], "-write_fields_nodes")]
    return "channel: grids %s, units %s; %s refused" % (grids, sorted(units.values()), refused(cases))


@test("interface_traction (the control g) on mms-stokes, whose exact g = (0, -2 mu_s cos(x + t) sin(1 + t)): over the "
      "middle half of the interface it converges at rate >= 2 with refinement (and the fluid-stress traction beside it "
      "converges too); 0 at the interface's ends, where the fluid's velocity is prescribed; next to them it keeps an "
      "O(1) error (measured)")
def test_derived_interface_traction():
    middle, beside, stress = [], [], []
    for refine in (1, 2, 3):
        out = os.path.join(WORK, "derived-control-%d" % refine)
        solve(["-options_file", os.path.join(ROOT, "options", "mms-stokes.yaml"), "-t_final", "0.55", "-refine",
               str(refine), "-mms_discrete_time", "1", "-write_fields", "-write_fields_derived",
               "interface_traction,traction"], out=out)
        walls = read_fields(out)["walls"][1]
        x, t = walls["geometry"], walls["time"]
        order = np.argsort(x[:, 0])
        xs = x[order, 0]
        exact = -2 * 3.0 * np.cos(xs + t) * np.sin(1 + t)   # mu_s = 3
        g, s = walls["interface_traction"][order], walls["traction"][order]
        half = (xs > 0.25 - 1e-9) & (xs < 0.75 + 1e-9)
        assert abs(x[:, 1] - 1).max() <= 1e-12 and g[0].any() == g[-1].any() == False, \
            "refine %d: the interface's nodes off y = 1 or g at its ends %s, %s" % (refine, g[0], g[-1])
        middle.append(max(abs(g[half, 1] - exact[half]).max(), abs(g[half, 0]).max()))
        stress.append(abs(s[half, 1] - exact[half]).max())
        beside.append(max(abs(g[1, 1] - exact[1]), abs(g[-2, 1] - exact[-2])))
    rates = [np.log2(middle[k] / middle[k + 1]) for k in range(2)]
    assert min(rates) >= 2 and stress[2] < stress[0] / 4, \
        "control over the middle half %s (rates %s), fluid stress %s" % (middle, rates, stress)
    return "control over the middle half %s (rates %.1f, %.1f); fluid-stress traction %s; next to the ends %s" % (
        ", ".join("%.1e" % e for e in middle), rates[0], rates[1], ", ".join("%.1e" % e for e in stress),
        ", ".join("%.2f" % e for e in beside))
