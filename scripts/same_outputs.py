#!/usr/bin/env python3
"""Behaviour-preserving changes (refactors, reformatting): runs a fixed set of cases with
one fsiopt binary and compares probes.csv, history.csv and summary.json byte for byte
with another run of the same cases (a directory written earlier, or a second binary).
summary.json is compared without the keys that measure the machine, not the computation
(wall time, start time, host, version, memory), and with the run's directory written as DIR; keys the reference lacks are listed, not compared.

  scripts/same_outputs.py record DIR [--fsiopt BIN]      # the reference outputs
  scripts/same_outputs.py compare DIR [--fsiopt BIN] [--now DIR2]  # a run now against DIR
  scripts/same_outputs.py time DIR --against BIN [--fsiopt BIN] [--rounds N]
                                                         # wall times of two binaries, back to back
  scripts/same_outputs.py --list                         # the cases and their options

time: each round runs every case with the two binaries one after the other (the order
alternating from round to round), and reports per case the least wall time (summary.json's
wall_time_s) of each binary and their ratio this/other: the fastest of N rounds is the
least disturbed by whatever else runs on the machine.

Exit 0 when every case agrees, 1 otherwise (each difference named)."""
import argparse, json, os, shutil, sys, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import FSIOPT, run_fsiopt  # noqa: E402  (the binary, its environment, the launch)

CHANNEL = ["-options_file", "options/channel2d.yaml"]
CASES = {
    "channel2d-opt": CHANNEL + ["-t_final", "0.01"],
    "channel2d-aitken": CHANNEL + ["-coupling", "aitken", "-t_final", "0.003"],
    "channel2d-iqnils": CHANNEL + ["-coupling", "iqnils", "-t_final", "0.005"],
    "mms-ns": ["-options_file", "options/mms-ns.yaml"],
    "tube3d": ["-options_file", "options/tube3d.yaml", "-t_final", "3e-4"],
    "turek-hron-fsi1": ["-options_file", "options/turek-hron/fsi1.yaml", "-t_final", "2"],
    "turek-hron-csm3": ["-options_file", "options/turek-hron/csm3.yaml", "-t_final", "0.5"],
}
FILES = ("probes.csv", "history.csv", "summary.json")
MACHINE_KEYS = ("wall_time_s", "start_time", "host", "version", "memory_gib")


def run_cases(fsiopt, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    for name, args in CASES.items():
        d = os.path.join(out_dir, name)
        shutil.rmtree(d, ignore_errors=True)
        t0 = time.time()
        p = run_fsiopt(args, out_dir=d, fsiopt=fsiopt)
        print("%-18s exit %s  %6.1fs" % (name, p.returncode, time.time() - t0), flush=True)
        if p.returncode:
            print("  " + (p.stderr or p.stdout).strip().splitlines()[-1], flush=True)


def summary_without_machine(path):
    """summary.json without what measures the machine; the run's own directory, which the
    options name (-output_dir, -checkpoint_file), written as DIR"""
    text = open(path).read()
    run_dir = json.loads(text).get("options_given", {}).get("-output_dir")
    s = json.loads(text.replace(json.dumps(run_dir)[1:-1], "DIR") if run_dir else text)
    for k in MACHINE_KEYS:
        s.pop(k, None)
    return s


def compare(reference, now, added):
    problems = []
    for name in CASES:
        for f in FILES:
            a, b = os.path.join(reference, name, f), os.path.join(now, name, f)
            if not os.path.exists(a) and not os.path.exists(b):
                continue
            if not os.path.exists(a) or not os.path.exists(b):
                problems.append("%s/%s: present in only one run" % (name, f))
            elif f == "summary.json":
                sa, sb = summary_without_machine(a), summary_without_machine(b)
                diff = sorted(k for k in set(sa) & set(sb) if sa[k] != sb[k]) + sorted(set(sa) - set(sb))
                if diff:
                    problems.append("%s/summary.json: %s differ" % (name, ", ".join(diff)))
                if set(sb) - set(sa):   # keys the change adds: reported, not a difference
                    added.update(set(sb) - set(sa))
            elif open(a, "rb").read() != open(b, "rb").read():
                problems.append("%s/%s: bytes differ" % (name, f))
    return problems


def wall_time(fsiopt, out_dir, name):
    d = os.path.join(out_dir, name)
    shutil.rmtree(d, ignore_errors=True)
    p = run_fsiopt(CASES[name], out_dir=d, fsiopt=fsiopt)
    if p.returncode:
        raise SystemExit("same_outputs.py time: %s with %s failed: %s" % (name, fsiopt, (p.stderr or p.stdout).strip()[-300:]))
    return json.load(open(os.path.join(d, "summary.json")))["wall_time_s"]


def time_pair(this, other, out_dir, rounds):
    """the least wall time of each binary per case over `rounds` back-to-back rounds"""
    best = {name: [float("inf"), float("inf")] for name in CASES}
    for r in range(rounds):
        for name in CASES:
            for k in ((0, 1) if r % 2 == 0 else (1, 0)):
                t = wall_time((this, other)[k], os.path.join(out_dir, ("this", "other")[k]), name)
                best[name][k] = min(best[name][k], t)
    print("%-18s %9s %9s %7s" % ("case", "this s", "other s", "ratio"))
    for name, (a, b) in best.items():
        print("%-18s %9.2f %9.2f %7.3f" % (name, a, b, a / b))
    total = sum(v[0] for v in best.values()) / sum(v[1] for v in best.values())
    print("all cases: this/other %.3f (least of %d rounds each)" % (total, rounds))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("action", nargs="?", choices=("record", "compare", "time"))
    ap.add_argument("dir", nargs="?")
    ap.add_argument("--fsiopt", default=FSIOPT)
    ap.add_argument("--now", help="compare: where this run's outputs go (default DIR.now)")
    ap.add_argument("--against", help="time: the other binary")
    ap.add_argument("--rounds", type=int, default=3, help="time: rounds (default 3)")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    if a.list or not a.action:
        for name, args in CASES.items():
            print("%-18s %s" % (name, " ".join(args)))
        return 0
    if not a.dir:
        ap.error("expected the directory of the reference outputs")
    if a.action == "time":
        if not a.against:
            ap.error("time: expected --against BIN, the binary to time this one against")
        time_pair(a.fsiopt, a.against, a.dir, a.rounds)
        return 0
    if a.action == "record":
        run_cases(a.fsiopt, a.dir)
        return 0
    now = a.now or a.dir.rstrip("/") + ".now"
    run_cases(a.fsiopt, now)
    added = set()
    problems = compare(a.dir, now, added)
    if added:
        print("summary.json keys new since the reference (not compared): %s" % ", ".join(sorted(added)))
    for p in problems:
        print("DIFFERENT " + p)
    print("%d cases: %s" % (len(CASES), "probes, history and summary identical" if not problems else "%d differences" % len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
