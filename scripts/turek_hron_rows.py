#!/usr/bin/env python3
"""The rows of scripts/turek_hron_table.py: the cases and quantities, and each run's row
of the table (values, level-to-level changes, windows, unknowns, wall time, Gauss-Newton
iterations, status) from its summary.json and attempts."""
import datetime, math, os, sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import md_escape, number, rel  # noqa: E402

CASES = {"csm1": ("csm", False), "csm2": ("csm", False), "csm3": ("csm", True),
         "cfd1": ("cfd", False), "cfd2": ("cfd", False), "cfd3": ("cfd", True),
         "fsi1": ("fsi", False), "fsi2": ("fsi", True), "fsi3": ("fsi", True)}
PARTS = {"csm": ("flag",), "cfd": ("fluid",), "fsi": ("fluid", "flag")}
MESH_OPTION = {"fluid": "-fluid_dm_plex_filename", "flag": "-structure_dm_plex_filename"}
# (key, summary.json quantities column, markdown header, applies to kinds)
QUANTITIES = [("ux", "dx(0.6;0.2)", "ux(A) [m]", ("csm", "fsi")),
              ("uy", "dy(0.6;0.2)", "uy(A) [m]", ("csm", "fsi")),
              ("drag", "drag", "drag [N/m]", ("cfd", "fsi")),
              ("lift", "lift", "lift [N/m]", ("cfd", "fsi"))]
STATS = ("final", "mean", "amplitude", "frequency")
DASH = "—"


def duration(s):
    s = number(s)
    if s is None:
        return ""
    if s < 120:
        return "%.3g s" % s
    if s < 7200:
        return "%.1f min" % (s / 60)
    return "%.2f h" % (s / 3600)


def result_row(v):
    s = v.summary if v.ok else {}
    case, level = v.params["case"], v.params["level"]
    kind, periodic = CASES[case]
    q = s.get("quantities") or {}
    row = {"case": case, "level": level, "kind": kind, "periodic": str(periodic).lower(), "status": v.status,
           "error": v.error, "fluid_dofs": s.get("fluid_dofs", ""), "structure_dofs": s.get("structure_dofs", ""),
           "dt": s.get("dt", ""), "steps": s.get("steps", ""), "t_start": s.get("t_start", ""),
           "t_final": s.get("t_final", ""), "window_s": q.get("window_s", "")}
    nf, ns = number(s.get("fluid_dofs")), number(s.get("structure_dofs"))
    row["unknowns"] = int((nf or 0) + (ns or 0)) if s else ""
    for key, column, _, _ in QUANTITIES:
        for st in STATS:
            val = (q.get(column) or {}).get(st, "")
            row["%s_%s" % (key, st)] = "" if val is None else val
    for k in ("avg_coupling_iterations", "coupling_iterations", "work_factor", "stalled_steps", "max_interface_jump",
              "wall_time_s"):
        val = s.get(k, "")
        row[k] = "" if val is None else val
    row["converged"] = str(s["converged"]).lower() if "converged" in s else ""
    # a resumed run: the sums over its parts where they can be made (fsiopt_resume.run_totals)
    t = v.totals if v.ok else {}
    first, last = s.get("first_step", 1), s.get("steps_done", s.get("steps"))
    row["parts"] = t.get("parts", 1) if s else ""
    row["its_cover"] = t.get("its_cover", "whole run") if s else ""
    row["stalled_cover"] = t.get("stalled_cover", "whole run") if s else ""
    row["last_part_steps"] = "%s-%s" % (first, last) if s else ""
    row["wall_time_note"] = t.get("wall_time_note", "")
    if t:
        for k in ("coupling_iterations", "avg_coupling_iterations", "wall_time_s"):
            row[k] = t[k] if t[k] is not None else ""
        if t["stalled_steps"] is not None:   # else: the last part's (stalled_cover)
            row["stalled_steps"] = t["stalled_steps"]
            if t["stalled_steps"]:
                row["converged"] = "false"
    row["elapsed_s"] = v.elapsed_s if math.isfinite(v.elapsed_s) else ""
    cmd_txt = os.path.join(v.run_dir, "cmd.txt") if v.run_dir else ""
    row["run_date"] = datetime.datetime.fromtimestamp(os.path.getmtime(cmd_txt)).strftime("%Y-%m-%d %H:%M") \
        if v.ok and os.path.isfile(cmd_txt) else ""
    row["meshes"] = " ".join(rel(m) for m in v.params.get("meshes", []))
    row["run_dir"] = rel(v.run_dir) if v.run_dir else ""
    row["command"] = v.cmdline
    return row


def shows_period(row):
    """A periodic case with a window: mean ± amplitude [frequency]; else the final value."""
    return row["periodic"] == "true" and (number(row["window_s"]) or 0) > 0


def shown_values(row, key):
    """The shown numbers of a quantity: (final,) or (mean, amplitude, frequency); None when
    the quantity does not apply or the run failed."""
    if row["kind"] not in dict((k, kinds) for k, _, _, kinds in QUANTITIES)[key] or row["status"] == "failed":
        return None
    if shows_period(row):
        return tuple(number(row["%s_%s" % (key, st)]) for st in ("mean", "amplitude", "frequency"))
    return (number(row["%s_final" % key]),)


def g(x, f="%.5g"):
    return DASH if x is None else f % x


def value_cell(row, key):
    vals = shown_values(row, key)
    if vals is None:
        return DASH if row["status"] != "failed" else ""
    if len(vals) == 1:
        return g(vals[0])
    return "%s ± %s [%s Hz]" % (g(vals[0]), g(vals[1]), g(vals[2], "%.4g"))


def change(new, old):
    if new is None or old is None or old == 0:
        return None
    return 100.0 * (new - old) / abs(old)


def pct(x):
    return DASH if x is None else "%+.3g%%" % x


def change_cell(row, prev, key):
    a, b = shown_values(row, key), shown_values(prev, key)
    if a is None or b is None:
        return DASH
    if len(a) != len(b):   # e.g. one of the two runs without a window
        return DASH
    c = [change(x, y) for x, y in zip(a, b)]
    if len(c) == 1:
        return pct(c[0])
    return "%s ± %s [%s]" % tuple(pct(x) for x in c)


def window_cell(row):
    w, t0, tf = number(row["window_s"]), number(row["t_start"]) or 0.0, number(row["t_final"])
    if w is None:
        return ""
    text = g(w, "%.4g")
    return text + "*" if shows_period(row) and tf is not None and w >= tf - t0 - 1e-12 else text


def unknowns_cell(row):
    nf, ns = number(row["fluid_dofs"]), number(row["structure_dofs"])
    if nf is None and ns is None:
        return ""
    if row["kind"] == "fsi":
        return "%d (%d + %d)" % ((nf or 0) + (ns or 0), nf or 0, ns or 0)
    return "%d" % ((nf or 0) + (ns or 0))


def wall_cell(row):
    """The wall time (a resumed run's: summed over its parts, "(N parts)")."""
    text = duration(row["wall_time_s"])
    if not text:
        return text
    text = {"estimated": "≈", "lower bound": "≥ "}.get(row.get("wall_time_note"), "") + text
    parts = number(row.get("parts"))
    return text + " (%d parts)" % parts if parts and parts > 1 else text


def gn_cell(row):
    """Gauss-Newton iterations per step (a resumed run's over its parts; when they cannot
    be summed, the last part's, with its steps)."""
    text = g(number(row["avg_coupling_iterations"]), "%.3g")
    cover = row.get("its_cover")
    return text + " (steps %s)" % cover[len("steps "):] if cover and cover != "whole run" else text


def status_cell(v, row):
    if v.status == "failed":
        err = v.error if len(v.error) <= 100 else v.error[:97] + "..."
        return "FAILED: " + md_escape(err)
    text = {"ok": "ok", "reused": "ok (re-used)"}.get(v.status, v.status)
    stalled = number(row["stalled_steps"]) or 0
    cover = row.get("stalled_cover")
    cover = " of %s" % cover if cover and cover != "whole run" else ""
    if row["converged"] == "false" or stalled:
        text += ", not converged (%d stalled steps%s)" % (stalled, cover)
    elif cover:   # a killed part left no count
        text += "; stalled steps known only for %s" % cover[len(" of "):]
    return text


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "scripts/turek_hron_table.py, which prints the table")
