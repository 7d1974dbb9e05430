#!/usr/bin/env python3
"""make check-memory: a fast subset of fsiopt runs under valgrind memcheck.

Each run goes through `valgrind --leak-check=full`, and once more without valgrind under
PETSc's own allocation tracing (-malloc_debug -malloc_dump: every PetscMalloc not freed by
PetscFinalize; the two together would take an hour). A run fails
when valgrind reports an error (invalid read or write, use of uninitialised values, bad
free) or a definitely/indirectly lost block with one of our functions in its stack, or
when PETSc lists a block allocated in our sources that was never freed. Frames of Debian's
libraries carry no file and line (no debug information), ours do (bin/fsiopt is built with
-g), so "a frame with (file.c:line)" is how our code is recognised; errors and leaks that
only touch Open MPI, HDF5 or PETSc internals are counted and shown, not failed on.

Arguments: words; only the runs whose names contain one of them go (default: all runs;
--list shows the names). Logs go to a new directory /tmp/fsiopt-memory-XXXX.
Last line: 'N passed, M failed'; exit status non-zero on any failure. Takes a few minutes.
"""
import argparse, os, re, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import ROOT, run_fsiopt  # noqa: E402  (the binary, its environment, the launch)

CHANNEL = ["-options_file", "options/channel2d.yaml"]

RUNS = [
    ("fluid alone (Navier-Stokes, Q2/Q1)", ["-scene", "mms-fluid", "-dt", "0.1", "-t_start", "0.5", "-t_final", "0.6"]),
    ("structure alone (St. Venant-Kirchhoff)", ["-scene", "mms-structure", "-structure_model", "svk", "-dt", "0.01", "-t_final", "0.02"]),
    ("coupled Stokes, Gauss-Newton", ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.6"]),
    ("channel2d: moving mesh, explicit Jacobian, checkpoints", CHANNEL + ["-t_final", "0.0003", "-checkpoint_every", "2"]),
    ("channel2d: restart", CHANNEL + ["-t_final", "0.0004", "-restart", "@checkpoint"]),
    ("channel2d: IQN-ILS", CHANNEL + ["-t_final", "0.0003", "-coupling", "iqnils"]),
    ("channel2d: BDF2 fluid, incremental mesh motion", CHANNEL + ["-t_final", "0.0003", "-fluid_time_order", "2",
                                                                  "-mesh_motion_incremental"]),
    ("channel2d: biharmonic mesh motion", CHANNEL + ["-t_final", "0.0003", "-mesh_motion", "biharmonic"]),
    ("turek-hron cfd1: steady fluid, body forces", ["-options_file", "options/turek-hron/cfd1.yaml", "-dt", "1.25"]),
    ("turek-hron csm1: static flag, probes on the structure", ["-options_file", "options/turek-hron/csm1.yaml"]),
    ("structure alone: every step retried with dt/2", ["-options_file", "options/mms-structure.yaml", "-structure_model", "svk", "-dt", "0.05",
                                                        "-t_final", "0.6", "-structure_snes_max_it", "5"]),
    ("diverging: channel2d retried, then past -dt_min", CHANNEL + ["-t_final", "0.001", "-coupling", "dn"]),
    ("bad input: an unknown scene", ["-scene", "nosuchscene"]),
]

FRAME = re.compile(r"^==\d+==\s+(?:at|by) 0x[0-9A-F]+: (.*)$")
SOURCES = {f for d, _, files in os.walk(os.path.join(ROOT, "src")) for f in files if f.endswith(".c")}
MAIN = open(os.path.join(ROOT, "src", "main.c")).read().splitlines()
# main's calls into MPI and PETSc start-up and shut-down: what leaks below them is theirs
LIBRARY_CALLS = {i + 1 for i, l in enumerate(MAIN) if re.search(r"Petsc(Initialize|Finalize)\(", l)}


def ours(frame):
    """a frame of our sources (glibc also carries file:line; Debian's PETSc, MPI and HDF5 do not)"""
    m = re.search(r"\(([A-Za-z0-9_]+\.c):(\d+)\)", frame)
    if not m or m.group(1) not in SOURCES:
        return False
    return not (m.group(1) == "main.c" and int(m.group(2)) in LIBRARY_CALLS)


def blocks(log):
    """valgrind's reports: lists of lines separated by blank '==pid==' lines."""
    out, cur = [], []
    for line in log.splitlines():
        if re.match(r"^==\d+==\s*$", line):
            if cur:
                out.append(cur)
            cur = []
        elif line.startswith("=="):
            cur.append(line)
    if cur:
        out.append(cur)
    return out


def classify(block):
    head = re.sub(r"^==\d+==\s*", "", block[0])
    frames = [FRAME.match(l).group(1) for l in block[1:] if FRAME.match(l)]
    mine = any(ours(f) for f in frames)
    if "definitely lost" in head or "indirectly lost" in head:
        kind = "leak"
    elif any(k in head for k in ("Invalid", "uninitialised", "Uninitialised", "Mismatched", "free()", "overlap", "Syscall param")):
        kind = "error"
    else:
        kind = None
    return kind, mine, head, frames


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("words", nargs="*", metavar="WORD", help="run only the runs whose names contain one of the words "
                    "(default: all)")
    ap.add_argument("--list", action="store_true", help="print the runs' names and exit")
    args = ap.parse_args()
    words = args.words
    if args.list:
        print("\n".join(name for name, _ in RUNS))
        return 0
    WORK = tempfile.mkdtemp(prefix="fsiopt-memory-")
    passed = failed = 0
    checkpoint = os.path.join(WORK, "run-3", "checkpoint.h5")
    t_all = time.time()
    for i, (name, args) in enumerate(RUNS):
        if words and not any(w in name for w in words):
            continue  # arguments: only the runs whose names contain one of them
        out = os.path.join(WORK, "run-%d" % i)
        args = [checkpoint if a == "@checkpoint" else a for a in args]
        valgrind = ["valgrind", "--leak-check=full", "--show-leak-kinds=definite,indirect", "--num-callers=30",
                    "--log-file=" + os.path.join(WORK, "valgrind-%d.log" % i)]
        t0 = time.time()
        p = run_fsiopt(args + ["-output_dir", out, "-no_signal_handler"], wrapper=valgrind, timeout=3000)
        traced = run_fsiopt(args + ["-output_dir", out + "-traced", "-malloc_debug", "-malloc_dump"], timeout=3000)
        for q in (p, traced):
            if q.timed_out:
                raise TimeoutError("%s: no end after 3000 s" % " ".join(q.cmd))
        log = open(os.path.join(WORK, "valgrind-%d.log" % i), errors="replace").read()
        problems, foreign = [], 0
        for b in blocks(log):
            kind, mine, head, frames = classify(b)
            if not kind:
                continue
            if mine:
                problems.append("%s: %s" % (head, " <- ".join(f for f in frames if ours(f))[:300]))
            else:
                foreign += 1
        # PETSc's list of PetscMalloc blocks never freed: "[ 0]32 bytes Func() at file.c:line"
        for line in (traced.stdout + traced.stderr).splitlines():
            m = re.match(r"^\[\s*\d+\]\s*\d+ bytes (\S+) at (\S+)", line)
            if m and m.group(2).startswith("src/"):
                problems.append("PetscMalloc never freed: %s" % line.strip())
        expect_fail = name.startswith(("bad input", "diverging"))
        for q, how in ((p, "under valgrind"), (traced, "traced")):
            if (q.returncode != 0) != expect_fail:
                problems.append("exit status %d %s: %s" % (q.returncode, how, (q.stderr.strip().splitlines() or [""])[-1][:200]))
        status = "PASS" if not problems else "FAIL"
        passed += not problems
        failed += bool(problems)
        print("%s %-55s %6.1fs  %d reports outside our code" % (status, name, time.time() - t0, foreign), flush=True)
        for pr in problems[:10]:
            print("     " + pr)
    print("total time %.0fs (logs in %s)" % (time.time() - t_all, WORK))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
