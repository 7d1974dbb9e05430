"""The test suite's shared harness: registration (@test(title, quick=...)), the runs of
fsiopt (scripts/fsiopt_runs.run_fsiopt), rates, probe files, the scenes' option lists,
the result counting and the WORK directory. The tests live in tests/test_*.py, one file
per area; tests/run_tests.py imports them all and calls main()."""
import csv, math, os, shutil, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.dont_write_bytecode = True   # no __pycache__ next to the sources
import fsiopt_runs as fr  # noqa: E402  (the one module that launches fsiopt)
from fsiopt_runs import FSIOPT, probes_difference  # noqa: E402,F401
from fsiopt_resume import checkpoint_step  # noqa: E402,F401  (the step a checkpoint ends)

WORK = tempfile.mkdtemp(prefix="fsiopt-tests-")
TIMEOUT = 600     # s: a hang guard for every run, not a measure of speed
TESTS = []        # (title, function, quick), in registration order

# the scenes' option lists shared by the areas
FLUID_SPACE = ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6", "-mms_discrete_time"]
SVK = ["-scene", "mms-structure", "-structure_model", "svk"]
NS_STEP = ["-options_file", "options/mms-ns.yaml"]        # one step of 1e-6 from t0 = 0.5
SHORT = ["-scene", "mms-ns", "-t_start", "0.5", "-t_final", "0.52", "-dt", "0.01", "-refine", "1"]
CHANNEL = ["-options_file", "options/channel2d.yaml"]


def turek(case):
    """the options of a Turek-Hron case (options/turek-hron/CASE.yaml)"""
    return ["-options_file", "options/turek-hron/%s.yaml" % case]


REFERENCE = os.path.join(ROOT, "tests", "reference")


def test(title, quick=False):
    """Registers a test: title (what run_tests.py prints and selects on, with the
    function's name), quick (part of the fast tier, run_tests.py --quick). The function
    returns a line of detail (its measured values) or raises AssertionError."""
    def register(fn):
        TESTS.append((title, fn, quick))
        return fn
    return register


def out_dir(tag="run"):
    """A fresh directory name under WORK."""
    return os.path.join(WORK, "%s-%d" % (tag, len(os.listdir(WORK))))


def run(args, nproc=1, tag="run", out=None, **kw):
    """Runs fsiopt, returns (returncode, stdout, stderr, summary or None)."""
    r = fr.run_fsiopt(args, nproc, out or out_dir(tag), timeout=kw.pop("timeout", TIMEOUT), **kw)
    if r.timed_out:
        raise AssertionError("run hung (killed after %d s): %s" % (TIMEOUT, " ".join(args)))
    return r.returncode, r.stdout, r.stderr, r.summary


def solve(args, nproc=1, out=None):
    """Runs fsiopt, returns its summary; AssertionError when it fails."""
    rc, stdout, err, summary = run(args, nproc, out=out)
    if rc != 0 or summary is None:
        raise AssertionError("run failed (%s): %s" % (" ".join(args), (err or stdout).strip()[-300:]))
    return summary


def interrupted(name, step, nproc=1, extra=()):
    """channel2d sending itself the signal `name` after step `step` (-interrupt_test_step):
    (returncode, stderr, outputs dir)."""
    out = os.path.join(WORK, "signal-%s-%d" % (name, nproc))
    rc, _, err, _ = run(CHANNEL + list(extra) + ["-interrupt_test_step", str(step), "-interrupt_test_signal", name],
                        nproc=nproc, out=out)
    return rc, err, out


def fail_text(rc, stdout, err):
    return "run failed: %s" % (err or stdout).strip()[-300:]


def rates(errors, key):
    return [math.log2(errors[i][key] / errors[i + 1][key]) for i in range(len(errors) - 1)]


def check_rates(errs, floors):
    """Every rate of each key in floors (errors on successive halvings) at least its floor."""
    got = {k: rates(errs, k) for k in floors}
    for k, floor in floors.items():
        assert min(got[k]) >= floor, "%s rates %s below %.2f (errors %s)" % (
            k, ["%.2f" % r for r in got[k]], floor, ["%.2e" % e[k] for e in errs])
    return "; ".join("%s %s" % (k, " ".join("%.2f" % r for r in v)) for k, v in got.items())


def read_probes(path):
    """(column names without their units, rows of numbers)"""
    rows = list(csv.reader(open(path)))
    return [fr.column_name(n) for n in rows[0]], [[float(v) for v in r] for r in rows[1:]]


def probe_rows(out):
    """probes.csv of a run's directory as rows of {column name without its unit: value}"""
    head, rows = read_probes(os.path.join(out, "probes.csv"))
    return [dict(zip(head, r)) for r in rows]


def difference_to_largest(rows, reference):
    """The largest difference of two probe series (t first) relative to the reference's
    largest value over all its columns (probes_difference scales each column by its own)."""
    scale = max(abs(v) for r in reference for v in r[1:])
    assert len(rows) == len(reference) and scale > 0, "%d against %d probe rows, scale %g" % (
        len(rows), len(reference), scale)
    return max(abs(a - b) for ra, rb in zip(rows, reference) for a, b in zip(ra[1:], rb[1:])) / scale


# options/solvers/: the iterative solvers' files, by name
SOLVER_FILES = {name: ["-options_file", "options/solvers/%s.yaml" % name]
                for name in ("fluid-schur-gamg", "fluid-velocity-ilu", "fluid-velocity-asm", "structure-cg-gamg",
                             "structure-cg-ilu", "structure-cholesky", "mesh-cg-gamg")}
# the set for small time steps (scripts/cost_growth.py's iterative-ilu): ILU(0) on the fluid's
# velocity block and on the wall, GAMG on the pressure and the mesh motion
ITERATIVE_ILU = SOLVER_FILES["fluid-schur-gamg"] + SOLVER_FILES["fluid-velocity-ilu"] + \
    SOLVER_FILES["structure-cg-ilu"] + SOLVER_FILES["mesh-cg-gamg"]


def last_rows(out, name="history.csv"):
    """{step: the step's last row} of a run's history.csv."""
    last = {}
    for r in csv.DictReader(open(os.path.join(out, name))):
        last[int(r["step"])] = r
    return last


def printed(stdout, prefix):
    return [l for l in stdout.splitlines() if l.startswith(prefix)]


def krylov_iterations(stdout, prefix):
    """The iterations of each linear solve under `prefix` (-<prefix>_ksp_converged_reason)."""
    return [int(l.split()[-1]) for l in stdout.splitlines() if l.strip().startswith("Linear %s_ solve" % prefix)]


def stage_count(log, stage, event):
    """how many times `event` ran in the -log_view stage `stage` of the report in file `log`
    (0 when it did not)"""
    from fsiopt_logview import parse_stage_event_table
    return parse_stage_event_table(open(log).read()).get(stage, {}).get(event, (0,))[0]


def adjoint_difference(stdout):
    """The relative difference <J h, r> - <h, J^T r> that the one "adjoint test:" line of
    -coupling_test_adjoint reports."""
    lines = printed(stdout, "adjoint test:")
    assert len(lines) == 1, "expected one adjoint test line, found %d in %s" % (len(lines), stdout[-300:])
    return float(lines[0].split()[-1])


def same_file(a, b):
    return open(a, "rb").read() == open(b, "rb").read()


# A checkpoint's checksums (include/checksum.h, kind fsiopt-mix64-1): its table, the root's
# attribute "checksums", and the checksum of a value, for tests that change a value together
# with its checksum (what a damage that a checksum cannot see looks like) or recompute them.
_MASK = (1 << 64) - 1


def _entry(index, bits):
    z = bits ^ (((index + 1) * 0x9e3779b97f4a7c15) & _MASK)
    z = ((z ^ (z >> 30)) * 0xbf58476d1ce4e5b9) & _MASK
    z = ((z ^ (z >> 27)) * 0x94d049bb133111eb) & _MASK
    return z ^ (z >> 31)


def checkpoint_checksum(value):
    """The checksum fsiopt stores of an attribute's value (an integer, a float or a string)
    or a dataset's (an array of floats), as the 16 hex digits it writes."""
    import numpy as np
    if isinstance(value, (str, bytes)):
        h = 0xcbf29ce484222325   # FNV-1a 64 of the string's bytes
        for c in value.encode() if isinstance(value, str) else value:
            h = ((h ^ c) * 0x100000001b3) & _MASK
        return "%016x" % _entry(0, h)
    a = np.asarray(value)
    if a.ndim:
        bits = a.astype("<f8").view("<u8")
        return "%016x" % (sum(_entry(i, int(b)) for i, b in enumerate(bits)) & _MASK)
    if np.issubdtype(a.dtype, np.integer):
        return "%016x" % _entry(0, int(a) & _MASK)
    return "%016x" % _entry(0, int(a.astype("<f8").view("<u8")))


def checkpoint_checksums(f):
    """An open h5py file's table of checksums (with its parts "checksums 1", ... of fluid |
    structure ranks): (kind, {item: 16 hex digits}), the items as fsiopt names them
    ("dataset /fluid/state", "attribute 'step' in /run")."""
    lines, k = f.attrs["checksums"].decode().splitlines(), 1
    while "checksums %d" % k in f.attrs:
        lines += f.attrs["checksums %d" % k].decode().splitlines()
        k += 1
    return lines[0], {l[17:]: l[:16] for l in lines[1:]}


def write_checkpoint_checksums(f, kind, table):
    """Replaces an open h5py file's table of checksums (its parts joined to it), a
    fixed-length string as fsiopt's."""
    text = "\n".join([kind] + ["%s %s" % (v, k) for k, v in table.items()]) + "\n"
    for name in [n for n in f.attrs if n.startswith("checksums")]:
        del f.attrs[name]
    f.attrs.create("checksums", text.encode(), dtype="S%d" % (len(text) + 1))


def set_checkpoint_attribute(f, group, name, value):
    """Rewrites attribute `name` of `group` in an open h5py file with its type kept, and its
    checksum in the table to match."""
    f[group].attrs.modify(name, value)
    kind, table = checkpoint_checksums(f)
    table["attribute '%s' in /%s" % (name, group)] = checkpoint_checksum(f[group].attrs[name])
    write_checkpoint_checksums(f, kind, table)


def selected(argv):
    """(tests to run, quick): --quick keeps the fast tier; the other arguments (but --list)
    keep the tests whose title or function name contains one of them (all without)."""
    quick = "--quick" in argv
    words = [a for a in argv if a not in ("--quick", "--list")]
    chosen = [(t, fn, q) for t, fn, q in TESTS if (q or not quick) and
              (not words or any(w in t or w in fn.__name__ for w in words))]
    return chosen, quick


def main(argv):
    """Runs the selected tests, one line each; last line 'N passed, M failed'; the exit
    status (1 on any failure). With --list: one line per selected test (its file, its
    function, quick or not, its title), nothing run."""
    t0, passed, failed = time.time(), 0, 0
    if "--help" in argv or "-h" in argv:
        print(sys.modules["__main__"].__doc__)
        shutil.rmtree(WORK, ignore_errors=True)
        return 0
    unknown = [a for a in argv if a.startswith("-") and a not in ("--quick", "--list")]
    if unknown:
        print("run_tests.py: unknown option %s (expected --quick, --list, --help or words of test names)" % unknown[0],
              file=sys.stderr)
        shutil.rmtree(WORK, ignore_errors=True)
        return 2
    chosen, quick = selected(argv)
    if not chosen:
        print("run_tests.py: no test's title or name contains %s" % " or ".join(repr(w) for w in argv if w[0] != "-"),
              file=sys.stderr)
        shutil.rmtree(WORK, ignore_errors=True)
        return 2
    if "--list" in argv:
        for title, fn, q in chosen:
            print("%-20s %-52s %-5s %s" % (fn.__module__, fn.__name__, "quick" if q else "", title))
        print("%d tests%s" % (len(chosen), " (quick tier)" if quick else ""))
        shutil.rmtree(WORK, ignore_errors=True)
        return 0
    for title, fn, _ in chosen:
        t1 = time.time()
        try:
            detail = fn()
            passed += 1
            print("PASS %-42s %6.1fs  %s" % (title, time.time() - t1, detail or ""), flush=True)
        except Exception as e:  # a crash or a hang is a failure, not an abort of the suite
            failed += 1
            print("FAIL %-42s %6.1fs  %s: %s" % (title, time.time() - t1, fn.__name__, e), flush=True)
    shutil.rmtree(WORK, ignore_errors=True)
    print("total time %.0fs%s" % (time.time() - t0, " (quick tier)" if quick else ""))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


# ---- bad input: one line 'fsiopt: error: ...' naming the culprit, non-zero exit, no summary ----
F, S = ["-scene", "mms-fluid"], ["-scene", "mms-structure"]


def refused(cases, out=None):
    """Each case (name, args, token) refused with one line 'fsiopt: error: ...' holding token, a
    non-zero exit, no traceback and no summary.json (out: the -output_dir of every run)."""
    problems = []
    for name, args, token in cases:
        rc, stdout, err, summary = run(args, tag="bad", out=out)
        lines = [l for l in (stdout + err).splitlines() if l.strip()]
        why = []
        if rc == 0: why.append("exit 0")
        if summary is not None: why.append("summary.json written")
        if "PETSC ERROR" in stdout + err: why.append("PETSc traceback")
        if len(lines) != 1: why.append("%d lines" % len(lines))
        elif token not in lines[0] or not lines[0].startswith("fsiopt: error:"): why.append("message '%s' lacks '%s'" % (lines[0], token))
        if why: problems.append("%s: %s" % (name, ", ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d cases" % len(cases)


def help_text(args):
    # errors="replace" (run_fsiopt): PETSc 3.18 prints an uninitialized buffer as the
    # default of -<prefix>dm_plex_boundary_label in DMPlex's own -help lines.
    out = out_dir("help")
    r = fr.run_fsiopt(["-help"] + args, out_dir=out, timeout=120)
    assert r.returncode == 0, "-help %s: exit %s" % (" ".join(args), r.returncode)
    assert not os.path.exists(out), "-help %s left %s: %s" % (" ".join(args), out, os.listdir(out))
    return r.stdout


def own_section(text):
    """fsiopt's options as -help groups them at its end: {group line: [option lines]}."""
    groups, current = {}, None
    for line in text.split("fsiopt's options, by prefix")[-1].splitlines()[1:]:
        if line.startswith("  -"):
            groups.setdefault(current, []).append(line)
        elif line.startswith(" ") and not line.startswith("  "):
            current = line.strip()
    return groups


def inputs_dir():
    d = os.path.join(WORK, "inputs")
    os.makedirs(d, exist_ok=True)
    return d
