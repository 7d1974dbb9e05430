#!/usr/bin/env python3
"""What the cylinder's polygon costs in the Turek-Hron benchmarks.

The fluid mesh's cells are straight between the cylinder's nodes, so the wetted cylinder is
the polygon inscribed in its circle r = 0.05 and encloses less than its area. For every
level n of --levels this script takes the level's meshes in two geometries:

  inscribed  the benchmark's meshes (meshes/turek-hron-{fluid,flag}.geo, -setnumber n N);
  area       the same meshes with the cylinder's nodes (but the flag's two corners on it)
             moved radially to the radius R that makes the polygon enclose the circle's
             area pi r^2 over its arc: the same cells, the same flag mesh,

and runs every case of --cases (default cfd1) on both:

  bin/fsiopt -options_file options/turek-hron/CASE.yaml
             -fluid_dm_plex_filename F [-structure_dm_plex_filename S] [--extra]

The difference of a quantity between the two geometries, against its change from the
previous level, says whether the polygon or the discretization limits it: a polygon cost far
below the level-to-level change is not what an isoparametric cylinder would fix. The
quantities are summary.json's: a steady case's final drag and lift (and the tip's ux, uy
when coupled), a periodic one's mean, amplitude and frequency over its window (--t-final
shortens every run; the window is the scene's). Area deficit per level (the polygon's area
against pi r^2, from the mesh nodes) and R are tabulated too.

Outputs (--out, default out/turek-polygon): polygon.md, polygon.csv; meshes in <out>/meshes;
runs in <out>/runs/<case>-n<N>-<geometry>[-T<T>][-x<hash>], re-used while complete with the
same command line and newer than their meshes (--force: run again); --jobs J runs J at a
time. A failed run is reported in the tables and the script exits non-zero at the end.

Examples (build first: make all):
  /usr/bin/python3 scripts/turek_polygon.py --cases cfd1 --levels 1,2,3
  /usr/bin/python3 scripts/turek_polygon.py --cases cfd3,fsi3 --levels 1 --jobs 2"""
import argparse, math, os, shlex, sys

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr   # noqa: E402
from fsiopt_runs import ROOT, rel, say   # noqa: E402
from turek_hron_rows import CASES, MESH_OPTION, PARTS, QUANTITIES   # noqa: E402

from turek_hron_table import GEO, GEO_INCLUDES as INCLUDES, OPTIONS_FILE   # noqa: E402
CENTRE, RADIUS, CYLINDER = (0.2, 0.2), 0.05, 5   # the scene's cylinder and its face set
GEOMETRIES = ("inscribed", "area")


def read_msh(path):
    """(lines, {node: (line index, x, y)}, [(node, node) of face set 5], {nodes of other face sets})."""
    with open(path) as f:
        lines = f.read().split("\n")
    try:
        i = lines.index("$Nodes")
        nodes = {}
        for k in range(i + 2, i + 2 + int(lines[i + 1])):
            a = lines[k].split()
            nodes[int(a[0])] = (k, float(a[1]), float(a[2]))
        i = lines.index("$Elements")
        segments, others = [], set()
        for line in lines[i + 2:i + 2 + int(lines[i + 1])]:
            a = [int(x) for x in line.split()]
            if a[1] == 1:   # a 2-node line: its physical group, then its nodes
                (segments.append(tuple(a[-2:])) if a[3] == CYLINDER else others.update(a[-2:]))
    except (ValueError, KeyError, IndexError) as e:
        raise fr.MeshError("%s: not a msh 2.2 file with face set %d (%s)" % (rel(path), CYLINDER, e))
    if not segments:
        raise fr.MeshError("%s: no segment in face set %d" % (rel(path), CYLINDER))
    return lines, nodes, segments, others


def angle(node):
    return math.atan2(node[2] - CENTRE[1], node[1] - CENTRE[0])


def radius(node):
    return math.hypot(node[1] - CENTRE[0], node[2] - CENTRE[1])


def segment_angle(nodes, p, q):
    return abs((angle(nodes[q]) - angle(nodes[p]) + math.pi) % (2 * math.pi) - math.pi)


def polygon(path):
    """(mean radius of the cylinder's nodes, segment angles, the polygon's area over the
    circle's sector of the same angles)."""
    _, nodes, segments, _ = read_msh(path)
    angles, area = [], 0.0
    for p, q in segments:
        t = segment_angle(nodes, p, q)
        angles.append(t)
        area += 0.5 * radius(nodes[p]) * radius(nodes[q]) * math.sin(t)   # the triangle from the centre
    moved = {n for seg in segments for n in seg}
    r = sum(radius(nodes[n]) for n in moved) / len(moved)
    return r, angles, area / (0.5 * RADIUS * RADIUS * sum(angles))


def area_mesh(inscribed, out):
    """The inscribed fluid mesh with the cylinder's nodes moved radially to R, its other nodes
    (the flag's corners on the circle among them, so the flag mesh still conforms) kept: the
    same cells, and a polygon that encloses the circle's area. Written unless `out` is newer
    than `inscribed`; returns R."""
    lines, nodes, segments, others = read_msh(inscribed)
    # sum over segments of the centre triangles = (r^2/2) sum(theta): quadratic in R
    a = b = c = 0.0
    for p, q in segments:
        t = segment_angle(nodes, p, q)
        fixed = (p in others) + (q in others)
        a += math.sin(t) if fixed == 0 else 0.0
        b += RADIUS * math.sin(t) if fixed == 1 else 0.0
        c += RADIUS * RADIUS * (t - (math.sin(t) if fixed == 2 else 0.0))
    R = (-b + math.sqrt(b * b + 4 * a * c)) / (2 * a)
    for n in {n for seg in segments for n in seg} - others:
        k, x, y = nodes[n]
        scale = R / radius(nodes[n])
        words = lines[k].split()
        lines[k] = " ".join([words[0], "%.17g" % (CENTRE[0] + scale * (x - CENTRE[0])),
                             "%.17g" % (CENTRE[1] + scale * (y - CENTRE[1]))] + words[3:])
    if not (os.path.isfile(out) and os.path.getmtime(out) > os.path.getmtime(inscribed)):
        tmp = out + ".tmp%d" % os.getpid()
        with open(tmp, "w") as f:
            f.write("\n".join(lines))
        os.replace(tmp, out)
    return R


def meshes(level, geometry, mesh_dir, gmsh):
    """{part: path} of a level's meshes of one geometry, and the cylinder nodes' radius R."""
    paths = {p: os.path.join(mesh_dir, "turek-hron-%s-n%d.msh" % (p, level)) for p in GEO}
    for part, geo in GEO.items():
        fr.ensure_gmsh_mesh(geo, INCLUDES, paths[part], level, 2, "%s n=%d" % (part, level), gmsh=gmsh, verbosity=1)
    if geometry == "inscribed":
        return paths, RADIUS
    area = dict(paths, fluid=os.path.join(mesh_dir, "turek-hron-fluid-n%d-area.msh" % level))
    return area, area_mesh(paths["fluid"], area["fluid"])


def columns(case):
    kind, periodic = CASES[case]
    stats = ("mean", "amplitude", "frequency") if periodic else ("final",)
    return [(key, column, header, st) for key, column, header, kinds in QUANTITIES if kind in kinds for st in stats]


def value(run, column, stat):
    q = (run.summary or {}).get("quantities") or {} if run.ok else {}
    return fr.number((q.get(column) or {}).get(stat))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="cfd1", help="comma-separated Turek-Hron cases with a fluid (default cfd1)")
    ap.add_argument("--levels", default="1,2", help="mesh levels n, comma-separated (default 1,2)")
    ap.add_argument("--t-final", type=float, default=None, help="-t_final of every run (default: the case's)")
    ap.add_argument("--extra", default="", help="options passed to every run")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "turek-polygon"), help="output directory")
    ap.add_argument("--gmsh", default="gmsh", help="gmsh binary (default gmsh)")
    ap.add_argument("--bin", default=fr.FSIOPT, help="fsiopt binary (default bin/fsiopt)")
    ap.add_argument("--force", action="store_true", help="run again even when a complete matching run exists")
    args = ap.parse_args()
    cases = [c.strip() for c in args.cases.split(",") if c.strip()]
    bad = [c for c in cases if c not in CASES or CASES[c][0] == "csm"]
    if bad or not cases:
        ap.error("--cases: expected some of %s, got %r" % (",".join(c for c in CASES if CASES[c][0] != "csm"),
                                                          args.cases))
    try:
        levels = fr.ints(args.levels)
    except ValueError:
        levels = []
    if not levels or min(levels) < 1:
        ap.error("--levels: expected comma-separated integers >= 1, got %r" % args.levels)
    if args.t_final is not None and args.t_final <= 0:
        ap.error("--t-final: positive expected")
    if args.jobs < 1:
        ap.error("--jobs: at least 1 expected")
    extra = shlex.split(args.extra)
    args.out = os.path.abspath(args.out)
    mesh_dir, runs_dir = os.path.join(args.out, "meshes"), os.path.join(args.out, "runs")

    geometry_rows, runs, failed_meshes = [], [], []
    for level in levels:
        for geometry in GEOMETRIES:
            try:
                paths, R = meshes(level, geometry, mesh_dir, args.gmsh)
                r, angles, ratio = polygon(paths["fluid"])
            except fr.MeshError as e:
                say("  mesh n=%d %s FAILED: %s" % (level, geometry, e), err=True)
                failed_meshes.append("n = %d %s: %s" % (level, geometry, e))
                continue
            geometry_rows.append({"level": level, "geometry": geometry, "node_radius": r, "segments": len(angles),
                                  "mean_angle": sum(angles) / len(angles), "area_ratio": ratio})
            for case in cases:
                options = ["-options_file", OPTIONS_FILE % case]
                for part in PARTS[CASES[case][0]]:
                    options += [MESH_OPTION[part], rel(paths[part])]
                tag = ""
                if args.t_final is not None:
                    options += ["-t_final", fr.fmt_num(args.t_final)]
                    tag = "-T" + fr.fmt_num(args.t_final)
                options += extra
                name = "%s-n%d-%s%s%s" % (case, level, geometry, tag, fr.extra_tag(extra))
                outputs = ("summary.json", "probes.csv") + (("history.csv",) if CASES[case][0] == "fsi" else ())
                runs.append(fr.Variant(name, "%s n = %d %s" % (case, level, geometry), options, outputs=outputs, case=case,
                                       level=level, geometry=geometry, meshes=paths))
    for v in runs:   # a run older than its meshes runs again
        d = os.path.join(runs_dir, v.name, "summary.json")
        if os.path.isfile(d) and any(os.path.getmtime(m) > os.path.getmtime(d) for m in v.params["meshes"].values()):
            os.remove(d)
    fr.run_all(runs, args.bin, runs_dir, jobs=args.jobs, force=args.force)

    rows = []
    for v in runs:
        row = {"case": v.params["case"], "level": v.params["level"], "geometry": v.params["geometry"],
               "status": v.status, "error": v.error, "run_dir": rel(v.run_dir or ""),
               "wall_time_s": (v.summary or {}).get("wall_time_s", "") if v.ok else ""}
        for key, column, _, st in columns(v.params["case"]):
            row["%s_%s" % (key, st)] = value(v, column, st)
        rows.append(row)
    os.makedirs(args.out, exist_ok=True)
    base = os.path.join(args.out, "polygon")
    fields = ["case", "level", "geometry", "status", "error", "wall_time_s"] + sorted(
        {"%s_%s" % (k, st) for c in cases for k, _, _, st in columns(c)}) + ["run_dir"]
    fr.write_csv(base + ".csv", rows, fields)

    g = lambda x, f="%.6g": "" if x is None else f % x   # noqa: E731
    md = ["# What the cylinder's polygon costs (Turek-Hron)", "",
          "`%s -options_file %s` with the level's meshes (inscribed: the benchmark's; area: the cylinder's nodes at "
          "the radius R whose polygon encloses pi r^2)%s%s; runs in `%s`." % (
              rel(args.bin), OPTIONS_FILE % "CASE", ", -t_final %s" % fr.fmt_num(args.t_final) if args.t_final else "",
              ", extra options `%s`" % " ".join(extra) if extra else "", rel(runs_dir)), "",
          "| level | geometry | cylinder segments | mean segment angle (rad) | node radius (m) | area / pi r^2 over the arc |",
          "|---|---|---|---|---|---|"]
    for r in geometry_rows:
        md.append("| %d | %s | %d | %.4f | %.6f | %.6f |" % (r["level"], r["geometry"], r["segments"], r["mean_angle"],
                                                           r["node_radius"], r["area_ratio"]))
    by = {(r["case"], r["level"], r["geometry"]): r for r in rows}
    for case in cases:
        cols = columns(case)
        md += ["", "## %s" % case, "",
               "Per level: the value on the inscribed polygon, the change (%) to the area polygon, and the change (%) "
               "of the inscribed value from the previous level.", "",
               "| quantity | " + " | ".join("n = %d | area − inscribed %% | from n − 1 %%" % lv for lv in levels) + " |",
               "|---|" + "---|---|---|" * len(levels)]
        for key, _, header, st in cols:
            cells, prev = [], None
            for lv in levels:
                a = (by.get((case, lv, "inscribed")) or {}).get("%s_%s" % (key, st))
                b = (by.get((case, lv, "area")) or {}).get("%s_%s" % (key, st))
                poly = 100 * (b - a) / abs(a) if a and b is not None else None
                step = 100 * (a - prev) / abs(prev) if a is not None and prev else None
                cells += [g(a), g(poly, "%+.3f"), g(step, "%+.3f")]
                prev = a
            md.append("| %s %s | %s |" % (header, st, " | ".join(cells)))
    failed = [(v.label, v) for v in runs if not v.ok]
    if failed_meshes:
        md += ["", "## Meshes that failed", ""] + ["- " + m for m in failed_meshes]
    fr.finish_report(md, base + ".md", [base + ".csv", base + ".md"], failed, len(runs), "turek_polygon", "run(s)")
    if failed_meshes:
        sys.exit(1)


if __name__ == "__main__":
    main()
