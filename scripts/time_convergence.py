#!/usr/bin/python3
"""Convergence in time of a periodic state: runs continued from one checkpoint at dt, dt/2,
dt/4, ... over the same stretch of time, and what changes with dt.

  /usr/bin/python3 scripts/time_convergence.py --checkpoint out/fsi3-swing/checkpoint.h5 \\
      --options-file options/turek-hron/fsi3.yaml --extra "-probes_surface_force" \\
      --dt 0.001 --halvings 2 --t-final 6 --window 0.5 --out out/fsi3-dt

Each run is
  bin/fsiopt -options_file F EXTRA -restart CHECKPOINT [-restart_change_dt] -dt DT
             -t_final T -quantities_window W -output_dir OUT/dt-DT
(-restart_change_dt when DT is not the checkpoint's step: the run goes on at DT as a
retried step does). A run whose summary.json exists and whose cmd.txt is this command line
is re-used; runs go one at a time. The quantities are summary.json's: per probe column
(and force_surface.csv's with -probes_surface_force) the mean, amplitude and frequency over
the last W seconds. OUT/time_convergence.md and .csv hold, per quantity, its value at each
dt, the relative change from the previous dt (%) and the observed order
log2(|q(dt) - q(dt/2)| / |q(dt/2) - q(dt/4)|) of each three successive dt."""
import argparse, math, os, shlex, sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402


def checkpoint_dt(path):
    import h5py
    with h5py.File(path, "r") as f:
        return float(f["run"].attrs["dt"])


def run_one(args, dt, change_dt):
    out = os.path.join(args.out, "dt-%s" % fr.fmt_num(dt))
    options = ["-options_file", args.options_file] + shlex.split(args.extra) + ["-restart", args.checkpoint] + \
        (["-restart_change_dt"] if change_dt else []) + \
        ["-dt", fr.fmt_num(dt), "-t_final", fr.fmt_num(args.t_final), "-quantities_window", fr.fmt_num(args.window)]
    cmdline = shlex.join(fr.fsiopt_command(options, out_dir=out))
    if fr.is_complete(out, cmdline) and not args.force:
        fr.say("  dt %s: re-used %s" % (fr.fmt_num(dt), out))
        return fr.read_summary(out)
    os.makedirs(out, exist_ok=True)
    fr.remove_files(out, ["cmd.txt", "summary.json"])
    fr.say("  dt %s: %s" % (fr.fmt_num(dt), cmdline))
    r = fr.run_fsiopt(options, out_dir=out, env=fr.fsiopt_env(), stdout=False)
    if r.returncode != 0 or not r.summary:
        sys.exit("time_convergence: the run at dt %s failed: %s" % (fr.fmt_num(dt), (r.stderr or "").strip()[-400:]))
    with open(os.path.join(out, "cmd.txt"), "w") as f:
        f.write(cmdline + "\n")
    fr.say("  dt %s: done in %.0f s" % (fr.fmt_num(dt), r.elapsed_s))
    return r.summary


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--checkpoint", required=True, help="the checkpoint every run continues from")
    ap.add_argument("--options-file", required=True)
    ap.add_argument("--extra", default="", help="more fsiopt options (one string)")
    ap.add_argument("--dt", type=float, required=True, help="the largest dt")
    ap.add_argument("--halvings", type=int, default=2, help="how many times dt is halved (default 2: dt, dt/2, dt/4)")
    ap.add_argument("--t-final", type=float, required=True)
    ap.add_argument("--window", type=float, required=True, help="the quantities' window: the runs' last W seconds")
    ap.add_argument("--out", required=True)
    ap.add_argument("--force", action="store_true", help="run again even when a complete run is there")
    args = ap.parse_args()
    if not (args.dt > 0 and args.halvings >= 1 and args.window > 0):
        ap.error("--dt and --window: positive; --halvings: at least 1")
    base_dt = checkpoint_dt(args.checkpoint)
    dts = [args.dt / 2 ** k for k in range(args.halvings + 1)]
    summaries = [run_one(args, dt, abs(dt - base_dt) > 1e-12 * base_dt) for dt in dts]
    rows = []
    for name in summaries[0]["quantities"]:
        if name == "window_s":
            continue
        for kind in ("mean", "amplitude", "frequency"):
            values = [s["quantities"].get(name, {}).get(kind) for s in summaries]
            if any(v is None for v in values):
                continue
            changes = [100 * (values[i] - values[i - 1]) / abs(values[i - 1]) if values[i - 1] else None
                       for i in range(1, len(values))]
            orders = []
            for i in range(2, len(values)):
                a, b = abs(values[i - 2] - values[i - 1]), abs(values[i - 1] - values[i])
                orders.append(math.log2(a / b) if a > 0 and b > 0 else None)
            rows.append([name, kind] + values + changes + orders)
    head = ["quantity", "kind"] + ["dt %s" % fr.fmt_num(dt) for dt in dts] + \
        ["change %% %s->%s" % (fr.fmt_num(dts[i - 1]), fr.fmt_num(dts[i])) for i in range(1, len(dts))] + \
        ["order %s..%s" % (fr.fmt_num(dts[i - 2]), fr.fmt_num(dts[i])) for i in range(2, len(dts))]
    fr.write_csv(os.path.join(args.out, "time_convergence.csv"), [dict(zip(head, r)) for r in rows], head)

    def cell(v, i):
        if v is None:
            return "—"
        if i < len(dts):
            return "%.5g" % v
        return "%+.3f" % v if i < 2 * len(dts) - 1 else "%.2f" % v
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| %s | %s | " % (fr.md_escape(r[0]), r[1]) + " | ".join(cell(v, i) for i, v in enumerate(r[2:])) + " |"
              for r in rows]
    text = "Over the last %s s to t = %s, from %s:\n\n" % (fr.fmt_num(args.window), fr.fmt_num(args.t_final),
                                                          args.checkpoint) + "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "time_convergence.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
