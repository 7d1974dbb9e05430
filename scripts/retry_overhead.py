#!/usr/bin/env python3
"""What keeping each step's start in memory (for the Δt-halving retries, -dt_min < -dt)
costs: the same run with the default -dt_min and with -dt_min = -dt (no copy kept),
alternated --repeats times in one invocation, reported as ratios of the median wall time
(summary.json wall_time_s) and of the peak resident memory (per process, from wait4).
The two must write the same probes.csv: keeping the start changes no result.

  /usr/bin/python3 scripts/retry_overhead.py [--options options/channel2d.yaml]
      [--t-final 0.02] [--repeats 3] [--out out/retry-overhead] [-- extra fsiopt options]"""
import argparse, json, os, statistics, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_runs import ROOT, run_fsiopt  # noqa: E402  (the binary, its environment, the launch)


def run(args, out):
    r = run_fsiopt(args, out_dir=out, stdout=False, rusage=True)
    err = (r.stderr or "").strip()
    if r.returncode != 0:
        sys.exit("retry_overhead: fsiopt failed: %s" % (err.splitlines()[-1] if err else "exit %s" % r.returncode))
    summary = json.load(open(os.path.join(out, "summary.json")))
    return summary, r.maxrss_mib, open(os.path.join(out, "probes.csv")).read()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--options", default="options/channel2d.yaml")
    ap.add_argument("--t-final", default="0.02")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "retry-overhead"))
    ap.add_argument("extra", nargs="*", help="more fsiopt options (after --)")
    a = ap.parse_args()
    base = ["-options_file", a.options, "-t_final", a.t_final] + a.extra
    dt = None
    times, memory, probes = {"kept": [], "none": []}, {"kept": [], "none": []}, {}
    for r in range(a.repeats):
        for variant in ("kept", "none"):
            extra = [] if variant == "kept" else ["-dt_min", repr(dt)]
            s, rss, csv = run(base + extra, os.path.join(a.out, variant))
            dt = dt or s["dt"]
            if variant == "kept" and r == 0:
                continue  # the first run only reads dt (and warms the file cache): not timed
            times[variant].append(s["wall_time_s"])
            memory[variant].append(rss)
            probes[variant] = csv
    if probes["kept"] != probes["none"]:
        sys.exit("retry_overhead: probes.csv differs with and without the kept start")
    tk, tn = statistics.median(times["kept"]), statistics.median(times["none"])
    mk, mn = max(memory["kept"]), max(memory["none"])
    print("%s, %d steps of dt %g, %d timed runs each" % (a.options, s["steps"], dt, len(times["none"])))
    print("| start kept (default -dt_min) | none (-dt_min = dt) | ratio |")
    print("|---|---|---|")
    print("| wall %.2f s | %.2f s | %.3f |" % (tk, tn, tk / tn))
    print("| peak RSS %.1f MiB | %.1f MiB | %.3f |" % (mk, mn, mk / mn))
    print("probes.csv identical: yes")


if __name__ == "__main__":
    main()
