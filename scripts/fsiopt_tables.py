#!/usr/bin/env python3
"""The text side of the study scripts (scripts/fsiopt_runs.py re-exports it): the
repository root, printing from several threads, number formats, a run directory's JSON
files (summary.json), the runs' CSV and markdown tables and reports, run-time grids, field
files and the gmsh meshes of other refinement levels. Only the standard library: no
fsiopt run starts here."""
import csv, hashlib, json, math, os, re, shlex, subprocess, sys, threading, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_print_lock = threading.Lock()


def say(*parts, err=False):
    with _print_lock:
        print(*parts, file=sys.stderr if err else sys.stdout, flush=True)


def rel(path):
    """path relative to the repository root when inside it (keeps cmd.txt portable)."""
    path = os.path.abspath(path)
    r = os.path.relpath(path, ROOT)
    return path if r.startswith("..") else r


RUN_FIELDS = ["variant", "label", "status", "error", "attempts", "elapsed_s", "wall_time_s", "steps", "t_final",
              "coupling_iterations", "avg_coupling_iterations", "inner_iterations", "work_factor", "fluid_solves",
              "max_interface_jump", "factorizations_fluid", "factorizations_structure", "stalled_steps", "converged",
              "fluid_dofs", "structure_dofs", "run_dir", "command"]


def run_row(v):
    s = v.summary or {}
    f = s.get("factorizations", {})
    cmd = v.cmdline
    if not cmd and v.run_dir and os.path.isfile(os.path.join(v.run_dir, "cmd.txt")):
        cmd = open(os.path.join(v.run_dir, "cmd.txt")).read().strip()
    row = {"variant": v.name, "label": v.label, "status": v.status, "error": v.error, "attempts": v.attempts,
           "elapsed_s": "%.2f" % v.elapsed_s, "run_dir": rel(v.run_dir) if v.run_dir else "", "command": cmd,
           "factorizations_fluid": f.get("fluid", ""), "factorizations_structure": f.get("structure", "")}
    for k in ("wall_time_s", "steps", "t_final", "coupling_iterations", "avg_coupling_iterations", "inner_iterations",
              "work_factor", "fluid_solves", "max_interface_jump", "stalled_steps", "converged", "fluid_dofs",
              "structure_dofs"):
        val = s.get(k, "")
        row[k] = str(val).lower() if isinstance(val, bool) else val
    return row


def write_runs_csv(path, variants):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=RUN_FIELDS)
        w.writeheader()
        for v in variants:
            w.writerow(run_row(v))


def clock(seconds):
    """h:mm:ss or m:ss"""
    s = int(round(max(0.0, seconds)))
    return "%d:%02d:%02d" % (s // 3600, s // 60 % 60, s % 60) if s >= 3600 else "%d:%02d" % (s // 60, s % 60)


class StudyProgress:
    """Prints "run i of n" as each run starts, with an ETA from the runs that ran so far
    (re-used runs take no time and count for none). Thread-safe: runs may go in parallel."""

    def __init__(self, total):
        self.total, self.started, self.ran, self.reused = total, 0, 0, 0
        self.t0, self.lock = time.time(), threading.Lock()

    def begin(self, name):
        with self.lock:
            self.started += 1
            i, left = self.started, self.total - self.ran - self.reused
            eta = " (ETA %s)" % clock((time.time() - self.t0) / self.ran * left) if self.ran else ""
        say("run %d of %d: %s%s" % (i, self.total, name, eta))

    def end(self, reused=False):
        with self.lock:
            if reused:
                self.reused += 1
            else:
                self.ran += 1


def column_name(header):
    """A probes.csv header without its unit: 'dy(1.5;1.) [cm]' -> 'dy(1.5;1.)' (files
    written before the headers had units pass unchanged)."""
    return re.sub(r"\s*\[[^\]]*\]$", "", header.strip())


def split_header(header):
    """A probes.csv header as (name, unit): 'dz(0.5;0.;1.25) [cm]' -> ('dz(0.5;0.;1.25)', 'cm'),
    'drag [N/m]' -> ('drag', 'N/m'); a header without a unit gives (header, None). The
    name is the header's text as written: coordinates are never re-formatted."""
    header = header.strip()
    m = re.fullmatch(r"(.*?)\s*\[([^\]]*)\]", header)
    return (m.group(1), m.group(2)) if m else (header, None)


def column_kind(name):
    """The quantity of a probes.csv column name: 'dy(1.5;1.)' -> 'dy', 'drag' -> 'drag'."""
    return name.split("(", 1)[0]


def is_displacement(name):
    """True for a displacement probe column: dx(...), dy(...), dz(...)."""
    return re.fullmatch(r"d[xyz]\(.*\)", name) is not None


def read_rows(path, growing=False):
    """A CSV's rows (the header first), at least one. growing: the file is still being written
    (fsiopt's *.partial), so a last line without its newline is half written and left out."""
    with open(path, newline="") as f:
        text = f.read()
    if growing and text and not text.endswith("\n"):
        text = text[:text.rfind("\n") + 1]
    rows = list(csv.reader(text.splitlines()))
    if not rows:
        raise ValueError("%s is empty" % path)
    return rows


def module_help(doc, used_by):
    """--help of a module under scripts/ run as a script: what it is for, who imports it."""
    import argparse
    ap = argparse.ArgumentParser(description=doc + "\n\nA module, imported by %s. It takes no arguments and "
                                 "runs nothing by itself." % used_by,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.parse_args()
    ap.print_help()


def read_probe_columns(path, growing=False):
    """probes.csv (or its .partial, growing = True) as (t, [(name, unit, header, values)]):
    the columns after t in file order, each with its name and unit split from the header
    (unit None when the header has none) and the header exactly as written."""
    rows = read_rows(path, growing)
    headers = [h.strip() for h in rows[0]]
    if not headers or split_header(headers[0])[0] != "t":
        raise ValueError("%s: expected a first column t, got %r" % (path, headers[:1]))
    data = [[float(x) for x in r] for r in rows[1:] if r]
    if any(len(r) != len(headers) for r in data):
        raise ValueError("%s: a row does not have the %d columns of the header" % (path, len(headers)))
    cols = [[r[i] for r in data] for i in range(len(headers))]
    return cols[0], [split_header(h) + (h, cols[i + 1]) for i, h in enumerate(headers[1:])]


def select_columns(names, spec):
    """The names a filter such as 'dx,dz' selects, in the order of names. A filter entry
    selects a column by its quantity (dx), its name (dy(1.5;1.)) or its whole header
    (dy(1.5;1.) [cm]); names are (name, header) pairs. spec None or empty: every
    displacement column (dx, dy, dz). Returns (selected, the entries that select nothing)."""
    entries = [e.strip() for e in (spec or "").split(",") if e.strip()]
    if not entries:
        return [n for n in names if is_displacement(n[0])], []
    hit = lambda e, n: e in (n[0], n[1], column_kind(n[0]))  # noqa: E731
    return [n for n in names if any(hit(e, n) for e in entries)], [e for e in entries if not any(hit(e, n) for n in names)]


def summary_key(run_dir, key):
    """summary.json's value of key in a run directory; None without the file or the key."""
    try:
        with open(os.path.join(run_dir, "summary.json")) as f:
            return json.load(f).get(key)
    except (OSError, ValueError, AttributeError):
        return None


def read_json(path):
    """A JSON file's content; {} when it is missing or unreadable."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def read_summary(run_dir):
    """A run directory's summary.json; {} without one."""
    return read_json(os.path.join(run_dir, "summary.json"))


def write_json(path, obj):
    """obj as JSON to path (written to path.tmp, then renamed)."""
    with open(path + ".tmp", "w") as f:
        json.dump(obj, f, indent=1)
        f.write("\n")
    os.replace(path + ".tmp", path)


def remove_files(run_dir, names):
    """The files `names` of run_dir removed, those that exist."""
    for name in names:
        try:
            os.remove(os.path.join(run_dir, name))
        except FileNotFoundError:
            pass


def run_scene(run_dir):
    """The scene of a run: summary.json's "scene", else the run directory's name."""
    scene = summary_key(run_dir, "scene")
    return scene if isinstance(scene, str) and scene else os.path.basename(os.path.normpath(os.path.abspath(run_dir)))


# how the figures name lengths and pressures in the unit systems summary.json's "units" names
UNIT_NAMES = {"cgs": {"length": "cm", "pressure": "dyn/cm$^2$"}, "SI": {"length": "m", "pressure": "Pa"}}


def run_units(run_dir, default="cgs"):
    """{"length": ..., "pressure": ...} of a run's unit system (summary.json "units"; default
    when the summary or the key is missing or names another system)."""
    units = summary_key(run_dir, "units")
    return UNIT_NAMES.get(units if isinstance(units, str) else None, UNIT_NAMES[default])


def read_table(path, growing=False):
    """A CSV with a header row of names and numeric rows: (names, list of float columns).
    growing: the file is still being written (fsiopt's *.partial), so a last line without
    its newline is half written and left out."""
    rows = read_rows(path, growing)
    names = [column_name(n) for n in rows[0]]
    data = [[float(x) for x in r] for r in rows[1:] if r]
    cols = [[r[i] for r in data] for i in range(len(names))]
    return names, cols


def run_time_grid(options_file, extra):
    """(t_start, dt) of runs of options_file (relative to ROOT) with the extra options (a
    list): -t_start / -dt among them, else the options file's, else 0 and 1e-4."""
    grid = {"t_start": 0.0, "dt": 1e-4}
    try:
        with open(os.path.join(ROOT, options_file)) as f:
            for line in f:
                m = re.match(r"(t_start|dt):\s*([-+0-9.eE]+)\s*(#.*)?$", line)
                if m:
                    grid[m.group(1)] = float(m.group(2))
    except OSError:
        pass
    for i, opt in enumerate(extra[:-1]):
        if opt in ("-t_start", "-dt"):
            grid[opt[1:]] = float(extra[i + 1])
    return grid["t_start"], grid["dt"]


def fields_interval(t_start, dt, t_final, times, who):
    """K of -write_fields_interval that writes the steps of the given times: the gcd of their
    steps, leaving out step 0 and the last step (always written). sys.exit on a time outside
    the run; a note on stderr for a time off the step grid (its nearest step is written)."""
    last = int(math.floor((t_final - t_start) / dt + 0.5))
    steps = []
    for t in times:
        n = int(math.floor((t - t_start) / dt + 0.5))
        if not 0 <= n <= last:
            sys.exit("%s: t = %g is outside the run [%g, %g]" % (who, t, t_start, t_final))
        if abs(t_start + n * dt - t) > 1e-6 * dt:
            print("%s: note: t = %g is not a multiple of dt = %g from t_start = %g; step %d is drawn"
                  % (who, t, dt, t_start, n), file=sys.stderr)
        if 0 < n < last:
            steps.append(n)
    return math.gcd(*steps) if steps else max(last, 1)


def fields_file(run_dir):
    """run_dir/fields.h5, or FileNotFoundError saying why it is missing."""
    path = os.path.join(run_dir, "fields.h5")
    if not os.path.isfile(path):
        extra = " (only fields.h5.partial: the run is unfinished or failed)" if os.path.isfile(path + ".partial") else \
            " (a run without -write_fields?)"
        raise FileNotFoundError("%s: no such file%s" % (rel(path), extra))
    return path


# ---------------------------------------------------------------------------- option values, table text, reports
def floats(text):
    return [float(x) for x in text.split(",") if x.strip()]


def ints(text):
    return [int(x) for x in text.split(",") if x.strip()]


def fmt_num(t):
    """-dt / -t_final text: exact enough, no float noise (3*1e-5 -> 3e-05)."""
    return "%.10g" % t


def extra_tag(extra):
    """run-name suffix for --extra options (a short hash; empty without)."""
    return "-x" + hashlib.sha1(" ".join(extra).encode()).hexdigest()[:8] if extra else ""


def md_escape(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def number(x):
    """float of x, or None for a missing / non-numeric / non-finite value."""
    if isinstance(x, bool):
        return None
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def write_report(md, md_path, written):
    """Writes md (markdown lines) to md_path, prints it, then `written: ` and the paths in
    written (relative to the repository root when inside it)."""
    with open(md_path, "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    print("written: %s" % ", ".join(rel(p) for p in written))


def finish_report(md, md_path, written, failed, total, script, what, dir_quote=""):
    """The end of a table script: md (markdown lines) gets a "## Failures" section with a line
    `- LABEL: ERROR (RUN DIR)` per (label, run) of failed (run: .error, .run_dir; the run
    directory in dir_quote, e.g. "`"), then write_report(md, md_path, written); when a run
    failed, `SCRIPT: N of TOTAL WHAT failed` on stderr and exit status 1."""
    if failed:
        md = md + ["", "## Failures", ""] + [
            "- %s: %s%s" % (label, md_escape(r.error), " (%s%s%s)" % (dir_quote, rel(r.run_dir), dir_quote)
                            if r.run_dir else "")
            for label, r in failed]
    write_report(md, md_path, written)
    if failed:
        say("%s: %d of %d %s failed" % (script, len(failed), total, what), err=True)
        sys.exit(1)


class MeshError(Exception):
    pass


def ensure_gmsh_mesh(geo, includes, out, level, dim, what, gmsh="gmsh", verbosity=2):
    """out: the gmsh mesh (msh 2.2, -setnumber n level) of the .geo file `geo` (paths relative
    to the repository root), generated unless present and newer than `geo` and `includes`;
    written to a temporary name and renamed, so that an interrupted gmsh never leaves a mesh
    that looks complete. Raises MeshError."""
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    try:
        newest = max(os.path.getmtime(os.path.join(ROOT, g)) for g in [geo] + list(includes))
    except OSError as e:
        raise MeshError("%s: %s" % (e.filename and rel(e.filename), e.strerror))
    if os.path.isfile(out) and os.path.getmtime(out) > newest:
        say("  mesh %-23s re-used %s" % (what, rel(out)))
        return out
    tmp = "%s.tmp%d.msh" % (out[:-len(".msh")], os.getpid())
    cmd = [gmsh, "-%d" % dim, "-format", "msh22", "-v", str(verbosity), "-setnumber", "n", str(level), "-o", tmp, geo]
    say("  mesh %-23s running: %s" % (what, shlex.join(cmd)))
    try:
        p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        if not (p.returncode == 0 and os.path.isfile(tmp) and os.path.getsize(tmp) > 0):
            lines = [l.strip() for l in (p.stderr + p.stdout).splitlines() if l.strip()]
            raise MeshError("gmsh %s n=%d: exit status %d%s" % (geo, level, p.returncode,
                                                               ": " + lines[-1][:300] if lines else ""))
        os.replace(tmp, out)
    except OSError as e:
        raise MeshError("cannot run %s: %s" % (gmsh, e.strerror or e))
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return out


def write_csv(path, rows, fields, float_format="%.6g"):
    """rows (dicts) as CSV with the columns `fields`; floats in float_format."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (float_format % v if isinstance(v, float) else v) for k, v in r.items()})


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    module_help(__doc__, "the scripts through scripts/fsiopt_runs.py, which re-exports it")
