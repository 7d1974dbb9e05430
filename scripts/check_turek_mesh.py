#!/usr/bin/env python3
"""Consistency check of the Turek-Hron fluid and flag meshes (gmsh msh 2.2 ASCII).

Usage: check_turek_mesh.py FLUID.msh FLAG.msh

Asserts, and exits non-zero with a one-line message otherwise:
  - only quadrilaterals (type 3) and line elements (type 1) in each file;
  - every node of each file is used by some quadrilateral (PETSc's reader makes a vertex
    of every node in the file);
  - face sets (physical tags of the lines) {1,2,3,4,5,6} in the fluid, {4,6} in the flag;
  - the nodes on face set 6 are the same points in both files (to 1e-10);
  - A = (0.6, 0.2), the flag's tip midpoint, is a node of both files;
  - no degenerate quad, and all quads of a file have signed areas of one sign.
Prints cell and node counts, the smallest |area| and the smallest scaled Jacobian (the
minimum over the four corners of sin of the corner angle: 1 for a rectangle) per file.
"""
import argparse
import sys

import numpy as np

TOL = 1e-10
A = (0.6, 0.2)


class CheckError(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise CheckError(msg)


def read_msh2(path):
    """Nodes (id -> xy), quads (k x 4 node ids), lines {tag: [(n0, n1), ...]}."""
    with open(path) as f:
        lines = f.read().splitlines()
    check(lines and lines[0] == "$MeshFormat", f"{path}: not a gmsh msh file")
    ver = lines[1].split()
    check(ver[0].startswith("2.") and ver[1] == "0", f"{path}: not msh 2.x ASCII (header {lines[1]!r})")
    i = lines.index("$Nodes")
    nn = int(lines[i + 1])
    nodes = {}
    for l in lines[i + 2:i + 2 + nn]:
        w = l.split()
        nodes[int(w[0])] = (float(w[1]), float(w[2]))
    check(len(nodes) == nn, f"{path}: duplicate node ids")
    i = lines.index("$Elements")
    ne = int(lines[i + 1])
    quads, faces = [], {}
    for l in lines[i + 2:i + 2 + ne]:
        w = [int(x) for x in l.split()]
        etype, ntags = w[1], w[2]
        tags, conn = w[3:3 + ntags], w[3 + ntags:]
        check(etype in (1, 3), f"{path}: element {w[0]} has type {etype} (only 1 = line, 3 = quad allowed)")
        if etype == 3:
            quads.append(conn)
        else:
            faces.setdefault(tags[0], []).append(tuple(conn))
    return nodes, np.array(quads, dtype=int), faces


def quad_metrics(path, nodes, quads):
    ids = sorted(nodes)
    index = {k: j for j, k in enumerate(ids)}
    xy = np.array([nodes[k] for k in ids])
    check(len(quads) > 0, f"{path}: no quadrilaterals")
    p = xy[np.vectorize(index.__getitem__)(quads)]  # (k, 4, 2)
    x, y = p[..., 0], p[..., 1]
    area = 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)
    # corner Jacobians: cross(e_next, e_prev) / (|e_next| |e_prev|), signed like the area
    e_next = np.roll(p, -1, axis=1) - p
    e_prev = np.roll(p, 1, axis=1) - p
    cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
    norms = np.linalg.norm(e_next, axis=2) * np.linalg.norm(e_prev, axis=2)
    check(np.all(norms > 0), f"{path}: quad with a zero-length edge")
    sj = cross / norms
    sign = 1.0 if area[0] > 0 else -1.0
    check(np.all(area * sign > 0), f"{path}: quads of both orientations or with zero area "
          f"({np.sum(area > 0)} positive, {np.sum(area < 0)} negative, {np.sum(area == 0)} zero)")
    sj = sj * sign
    check(np.all(sj > 0), f"{path}: {np.sum(sj <= 0)} quads with a non-convex or degenerate corner "
          f"(min scaled Jacobian {sj.min():.3g})")
    return np.abs(area).min(), sj.min(), "counter-clockwise" if sign > 0 else "clockwise"


def face_points(nodes, faces, tag):
    ids = {n for seg in faces.get(tag, []) for n in seg}
    return np.array(sorted(nodes[k] for k in ids))


def has_point(nodes, pt):
    xy = np.array(list(nodes.values()))
    return bool(np.any(np.max(np.abs(xy - np.array(pt)), axis=1) < TOL))


def main(argv):
    ap = argparse.ArgumentParser(prog="check_turek_mesh.py", usage="%(prog)s FLUID.msh FLAG.msh",
                                 description=__doc__.replace("\nUsage: check_turek_mesh.py FLUID.msh FLAG.msh\n", ""),
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Example: scripts/check_turek_mesh.py meshes/turek-hron-fluid.msh "
                                 "meshes/turek-hron-flag.msh")
    ap.add_argument("fluid", metavar="FLUID.msh", help="the fluid mesh (gmsh msh 2.2 ASCII)")
    ap.add_argument("flag", metavar="FLAG.msh", help="the flag (structure) mesh (gmsh msh 2.2 ASCII)")
    args = ap.parse_args(argv[1:])
    fluid_path, flag_path = args.fluid, args.flag
    data = {}
    for name, path, want in (("fluid", fluid_path, {1, 2, 3, 4, 5, 6}), ("flag", flag_path, {4, 6})):
        nodes, quads, faces = read_msh2(path)
        used = set(quads.ravel().tolist())
        unused = set(nodes) - used
        check(not unused, f"{path}: {len(unused)} nodes used by no quadrilateral (e.g. {sorted(unused)[:5]})")
        check(used <= set(nodes), f"{path}: quads refer to undefined nodes")
        check(want <= set(faces), f"{path}: face sets {sorted(want - set(faces))} missing (have {sorted(faces)})")
        check(has_point(nodes, A), f"{path}: A = {A} is not a node")
        amin, sjmin, orient = quad_metrics(path, nodes, quads)
        data[name] = (nodes, faces)
        fs = ", ".join(f"{t}:{len(faces[t])}" for t in sorted(faces))
        print(f"{name}: {len(quads)} quads, {len(nodes)} nodes, min |area| {amin:.3e}, "
              f"min scaled Jacobian {sjmin:.3f}, {orient}; face set edges {{{fs}}}")
    p_fluid = face_points(*data["fluid"], 6)
    p_flag = face_points(*data["flag"], 6)
    check(len(p_fluid) == len(p_flag),
          f"face set 6: {len(p_fluid)} nodes in the fluid, {len(p_flag)} in the flag")
    # match each fluid point to its nearest flag point (sizes are small)
    d = np.max(np.abs(p_fluid[:, None, :] - p_flag[None, :, :]), axis=2)
    check(np.all(d.min(axis=1) < TOL) and np.all(d.min(axis=0) < TOL),
          f"face set 6: nodes differ between the meshes (max mismatch {max(d.min(axis=1).max(), d.min(axis=0).max()):.3e})")
    check(has_point(dict(enumerate(map(tuple, p_fluid))), A), f"A = {A} not on face set 6")
    print(f"interface (face set 6): {len(p_fluid)} common nodes; A = {A} a node of both: OK")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv))
    except CheckError as e:
        print(f"check_turek_mesh: {e}", file=sys.stderr)
        sys.exit(1)
    except (OSError, ValueError, IndexError) as e:
        print(f"check_turek_mesh: cannot read the meshes: {e}", file=sys.stderr)
        sys.exit(1)
