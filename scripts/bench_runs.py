#!/usr/bin/env python3
"""The runs of scripts/bench.py (and scripts/stress.py): one fsiopt run per Run, with
-log_view, its stage times read back. A run directory holds stdout.log, stderr.log,
cmd.txt (written after a successful run) and status.json (every run's status, error,
elapsed time, timeout and command line). A complete run of the same command line is
re-used, and so is a failure with an `fsiopt: error:` message or a timeout (after at least
the current timeout) unless rerun_failed; a run that dies otherwise is retried."""
import json, os, shlex, sys, time
from concurrent.futures import ThreadPoolExecutor

sys.dont_write_bytecode = True   # no scripts/__pycache__ next to the sources
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_logview import parse_stages   # noqa: E402
from fsiopt_runs import StudyProgress, error_line, execute, fsiopt_env, read_json, rel, say   # noqa: E402

OUTPUTS = ("summary.json", "probes.csv", "history.csv", "stdout.log")   # a complete run's files


class Run:
    """One fsiopt run: name (= run directory name), label, options (without -output_dir and
    -log_view, which are added). After run(): status ok | failed | timeout, reused, error,
    elapsed_s, summary, stages {stage: seconds}."""

    def __init__(self, name, label, options, **params):
        self.name, self.label, self.options, self.params = name, label, list(options), params
        self.run_dir = None
        self.status = "pending"
        self.reused = False
        self.error = ""
        self.elapsed_s = float("nan")
        self.attempts = 0
        self.summary = {}
        self.stages = {}
        self.cmdline = ""

    def command(self, fsiopt, runs_dir):
        self.run_dir = os.path.join(runs_dir, self.name)
        return [rel(fsiopt)] + self.options + ["-log_view", "-output_dir", rel(self.run_dir)]

    @property
    def ok(self):
        return self.status == "ok"

    @property
    def wall(self):
        """fsiopt's own wall time when it finished, else the time until it stopped."""
        return self.summary.get("wall_time_s", self.elapsed_s) if self.ok else self.elapsed_s

    def status_text(self):
        return self.status + (" (re-used)" if self.reused else "")


def read_stages(run_dir):
    try:
        with open(os.path.join(run_dir, "stdout.log")) as f:
            return parse_stages(f.read())
    except OSError:
        return {}


def _reuse(r, cmdline, timeout, rerun_failed):
    """True when the run directory holds a result of this very command line we may re-use."""
    d = r.run_dir
    try:
        with open(os.path.join(d, "cmd.txt")) as f:
            recorded = f.read().strip()
    except OSError:
        recorded = None
    if recorded == cmdline and all(os.path.isfile(os.path.join(d, o)) for o in OUTPUTS):
        s = read_json(os.path.join(d, "summary.json"))
        if s:
            r.status, r.summary, r.error = "ok", s, ""
            r.elapsed_s = read_json(os.path.join(d, "status.json")).get("elapsed_s", s.get("wall_time_s", float("nan")))
            return True
    st = read_json(os.path.join(d, "status.json"))
    if rerun_failed or st.get("cmdline") != cmdline:
        return False
    if st.get("status") == "failed" and st.get("final") or \
            st.get("status") == "timeout" and (not timeout or st.get("timeout_s", 0) >= timeout):
        r.status, r.error, r.elapsed_s = st["status"], st.get("error", ""), st.get("elapsed_s", float("nan"))
        return True
    return False


def run_one(r, fsiopt, runs_dir, timeout=None, force=False, rerun_failed=False, retries=1, wait_s=5.0, env=None):
    """Run (or re-use) one run; sets its status, error, summary, stages, elapsed_s."""
    cmd = r.command(fsiopt, runs_dir)
    cmdline = r.cmdline = shlex.join(cmd)
    if not force and _reuse(r, cmdline, timeout, rerun_failed):
        r.reused, r.stages = True, read_stages(r.run_dir)
        say("  %-40s re-used (%s)%s" % (r.name, r.status, ": " + r.error if r.error else ""))
        return r
    os.makedirs(r.run_dir, exist_ok=True)
    for name in ("cmd.txt", "status.json", "stderr.log") + OUTPUTS:
        try:
            os.remove(os.path.join(r.run_dir, name))
        except FileNotFoundError:
            pass
    say("  %-40s running: %s" % (r.name, cmdline))
    final = False
    for attempt in range(1, retries + 2):
        r.attempts = attempt
        returncode, stdout, stderr, r.elapsed_s, timed_out = execute(cmd, r.run_dir, env, timeout)
        r.stages = parse_stages(stdout)
        if returncode == 0 and all(os.path.isfile(os.path.join(r.run_dir, o)) for o in OUTPUTS):
            r.status, r.error = "ok", ""
            r.summary = read_json(os.path.join(r.run_dir, "summary.json"))
            with open(os.path.join(r.run_dir, "cmd.txt"), "w") as f:
                f.write(cmdline + "\n")
            break
        if timed_out:
            r.status, r.error, final = "timeout", "timeout after %g s" % timeout, True
        else:
            if returncode is None:
                msg = stderr
            elif returncode == 0:
                msg = "exit status 0 but outputs missing in %s" % rel(r.run_dir)
            else:
                msg, final = error_line(stderr, returncode)
            r.status, r.error = "failed", msg
        if final or attempt > retries:
            break
        say("  %-40s died (%s); retrying in %g s" % (r.name, r.error, wait_s), err=True)
        time.sleep(wait_s)
    with open(os.path.join(r.run_dir, "status.json"), "w") as f:
        try:   # for the record only: re-use goes by the command line, not by the binary
            built = time.strftime("%Y-%m-%dT%H:%M:%S", time.localtime(os.path.getmtime(fsiopt)))
        except OSError:
            built = ""
        json.dump({"status": r.status, "final": final, "error": r.error, "elapsed_s": r.elapsed_s,
                   "timeout_s": timeout or 0, "attempts": r.attempts, "cmdline": cmdline, "binary_mtime": built},
                  f, indent=1)
    if r.ok:
        say("  %-40s done in %.1f s" % (r.name, r.elapsed_s))
    else:
        say("  %-40s %s after %.1f s: %s" % (r.name, r.status.upper(), r.elapsed_s, r.error), err=True)
    return r


def run_all(runs, fsiopt, runs_dir, jobs=1, timeout=None, force=False, rerun_failed=False, retries=1):
    """Run the runs, jobs at a time (duplicates by name once); returns the unique runs."""
    unique = list({r.name: r for r in runs}.values())
    env = fsiopt_env(jobs=jobs)   # one thread per run when jobs > 1
    say("%d run(s) in %s, %d at a time%s" % (len(unique), rel(runs_dir), jobs,
                                             ", timeout %g s each" % timeout if timeout else ""))
    progress = StudyProgress(len(unique))

    def one(r):
        progress.begin(r.name)
        run_one(r, fsiopt, runs_dir, timeout, force, rerun_failed, retries, env=env)
        progress.end(r.reused)

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        list(pool.map(one, unique))
    return unique


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "scripts/bench.py, stress.py and tube3d_table.py")
