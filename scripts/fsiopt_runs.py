#!/usr/bin/env python3
"""Shared helpers for scripts that run bin/fsiopt over several variants.

A variant is one fsiopt command line with its own output directory. A run directory is
re-used when it is complete (summary.json, probes.csv and history.csv present, and the
variant's extra outputs, e.g. fields.h5 of a run with -write_fields) and the
command line recorded in its cmd.txt is the one we would run now. cmd.txt is written only
after a successful run, and removed with the old outputs before a new run starts, so an
interrupted run is never taken for a complete one.

A run that exits with the one-line `fsiopt: error: ...` message has failed for good; a run
that dies otherwise (killed by a signal, binary missing or busy while being rebuilt, a
crash without that message) is retried a few times after a short wait.

Resumable variants (Variant(..., resumable=True)) continue an unfinished run from fsiopt's
checkpoint instead of starting over: scripts/fsiopt_resume.py keeps their parts.

stop_runs() (on Ctrl-C or SIGTERM of a script) starts no new run and no retry; forwarded
signals let the running fsiopt processes stop at a checkpoint of their last step."""
import os, shlex, subprocess, sys, threading, time
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_tables import (  # noqa: E402,F401  (the text side, re-exported for the scripts)
    ROOT, MeshError, RUN_FIELDS, StudyProgress, clock, column_name, ensure_gmsh_mesh, extra_tag, fields_file, fields_interval, finish_report, floats,
    fmt_num, ints, md_escape, number, read_json, read_summary, read_table, rel, remove_files, run_row, run_time_grid, say,
    write_csv, write_json, write_report, write_runs_csv)
from fsiopt_resume import (  # noqa: E402  (resumable variants: their checkpoints and parts)
    CHECKPOINT, CURRENT, record_complete_run, resume_or_start_over, run_totals, start_over)

FSIOPT = os.path.join(ROOT, "bin", "fsiopt")


def fsiopt_env(base=None, oversubscribe=True, jobs=1, **extra):
    """The environment fsiopt runs in: Open MPI allowed as root (ignored for other users)
    and, unless oversubscribe is False, more ranks than cores allowed (the Makefile sets the
    same); with jobs > 1 runs side by side, one thread per run (OMP_NUM_THREADS etc. unless
    set); plus `extra`."""
    env = dict(os.environ if base is None else base, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    if oversubscribe:
        env["OMPI_MCA_rmaps_base_oversubscribe"] = "1"
    if jobs > 1:   # one core per run
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            env.setdefault(k, "1")
    env.update(extra)
    return env


def fsiopt_command(args, nproc=1, out_dir=None, fsiopt=None, launcher=("mpiexec",), wrapper=()):
    """The command line of one fsiopt run: [launcher -n nproc] [wrapper] fsiopt args
    [-output_dir out_dir] (the launcher only when nproc > 1; wrapper: e.g. valgrind and
    its options)."""
    cmd = list(wrapper) + [fsiopt or FSIOPT] + list(args) + (["-output_dir", out_dir] if out_dir else [])
    return list(launcher) + ["-n", str(nproc)] + cmd if nproc > 1 else cmd


class FsioptRun:
    """What run_fsiopt() returns: returncode (None: could not start, or timed out), stdout,
    stderr (text, or None when not captured), summary (out_dir/summary.json, None without
    one), out_dir, cmd, elapsed_s, timed_out, maxrss_mib (with rusage=True: the peak
    resident memory of the process, from wait4; else None)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def __iter__(self):   # rc, stdout, stderr, summary = run_fsiopt(...)
        return iter((self.returncode, self.stdout, self.stderr, self.summary))


def launch(cmd, env=None, cwd=ROOT, timeout=None, stdout=True, stderr=True, rusage=False):
    """Runs a command line that starts fsiopt (fsiopt_command's, a Variant's) once, from cwd,
    in fsiopt_env() unless env is given; the process is known to stop_runs() meanwhile.
    stdout, stderr: True to capture (text, undecodable bytes replaced), False to discard
    (None returned). timeout: seconds, then the process is killed. rusage: the peak
    resident memory from wait4. Returns (returncode or None, stdout, stderr, elapsed s,
    timed out, peak MiB or None); a command that cannot start gives returncode None and
    the reason in stderr."""
    t0, timed_out, maxrss = time.time(), False, None
    out, err = ("" if stdout else None), ("" if stderr else None)
    pipe = lambda capture: subprocess.PIPE if capture else subprocess.DEVNULL
    try:
        p = subprocess.Popen(cmd, cwd=cwd, env=fsiopt_env() if env is None else env, stdout=pipe(stdout),
                             stderr=pipe(stderr), text=True, errors="replace")
    except OSError as e:   # binary missing or busy (being re-linked)
        return None, out, "cannot run %s: %s" % (cmd[0], e.strerror or e), time.time() - t0, False, None
    with _children_lock:
        _children.add(p)
    try:
        if rusage:   # wait4 for the peak memory; the pipes are read meanwhile
            texts, readers = {}, []
            for name, stream in (("out", p.stdout), ("err", p.stderr)):
                if stream is not None:
                    readers.append(threading.Thread(target=lambda n=name, f=stream: texts.__setitem__(n, f.read())))
                    readers[-1].start()
            killed = threading.Event()
            timer = threading.Timer(timeout, lambda: (killed.set(), p.kill())) if timeout else None
            if timer:
                timer.start()
            _, status, usage = os.wait4(p.pid, 0)
            if timer:
                timer.cancel()
            timed_out = killed.is_set()
            for r in readers:
                r.join()
            p.returncode = returncode = None if timed_out else os.waitstatus_to_exitcode(status)
            out, err, maxrss = texts.get("out", out), texts.get("err", err), usage.ru_maxrss / 1024.0
            for stream in (p.stdout, p.stderr):
                if stream is not None:
                    stream.close()
        else:
            try:
                out, err = p.communicate(timeout=timeout or None)
                returncode = p.returncode
            except subprocess.TimeoutExpired:
                p.kill()
                out, err = p.communicate()
                timed_out, returncode = True, None
    finally:
        with _children_lock:
            _children.discard(p)
    return returncode, out, err, time.time() - t0, timed_out, maxrss


def run_fsiopt(args, nproc=1, out_dir=None, fsiopt=None, launcher=("mpiexec",), wrapper=(), env=None, cwd=ROOT,
               timeout=None, stdout=True, stderr=True, rusage=False, check=False):
    """Runs fsiopt once: fsiopt_command(args, nproc, out_dir, fsiopt, launcher, wrapper) by
    launch() (env, cwd, timeout, stdout, stderr, rusage: its). Returns a FsioptRun, with
    out_dir/summary.json read. check: raise subprocess.CalledProcessError unless it exits 0."""
    cmd = fsiopt_command(args, nproc, out_dir, fsiopt, launcher, wrapper)
    returncode, out, err, elapsed, timed_out, maxrss = launch(cmd, env, cwd, timeout, stdout, stderr, rusage)
    summary = None
    if out_dir and os.path.isfile(os.path.join(cwd, out_dir, "summary.json")):
        summary = read_json(os.path.join(cwd, out_dir, "summary.json")) or None
    if check and returncode != 0:
        raise subprocess.CalledProcessError(returncode if returncode is not None else -1, cmd, out, err)
    return FsioptRun(returncode=returncode, stdout=out, stderr=err, summary=summary, out_dir=out_dir, cmd=cmd,
                     elapsed_s=elapsed, timed_out=timed_out, maxrss_mib=maxrss)


OUTPUTS = ("summary.json", "probes.csv", "history.csv")
STOP = threading.Event()   # set by stop_runs(): no new run, no retry
_children, _children_lock = set(), threading.Lock()


class Variant:
    """One fsiopt run: name (also the run directory name), label (legend), options;
    outputs: the files a complete run has (default OUTPUTS); run_options: options passed to
    the process that are not part of the command line recorded in cmd.txt (re-use does not
    depend on them); resumable: continue an unfinished run from its checkpoint (module
    docstring)."""

    def __init__(self, name, label, options, outputs=OUTPUTS, run_options=(), resumable=False, **params):
        self.name, self.label, self.options, self.params = name, label, list(options), params
        self.outputs = tuple(outputs)
        self.run_options, self.resumable = list(run_options), resumable
        self.totals = {}   # resumable runs: run_totals() of the complete run
        self.run_dir = None
        self.status = "pending"   # ok | reused | failed
        self.error = ""
        self.elapsed_s = float("nan")
        self.attempts = 0
        self.summary = {}
        self.cmdline = ""

    def command(self, fsiopt, runs_dir):
        self.run_dir = os.path.join(runs_dir, self.name)
        return [rel(fsiopt)] + self.options + ["-output_dir", rel(self.run_dir)]

    @property
    def ok(self):
        return self.status in ("ok", "reused")


def probes_difference(rows, reference):
    """the largest difference of two probe series (rows of numbers, t first), relative to
    each column's largest value in the reference"""
    worst = 0.0
    for c in range(1, len(reference[0])):
        scale = max(abs(r[c]) for r in reference) or 1.0
        worst = max(worst, max(abs(a[c] - b[c]) for a, b in zip(rows, reference)) / scale)
    return worst


def is_complete(run_dir, cmdline, outputs=OUTPUTS):
    try:
        with open(os.path.join(run_dir, "cmd.txt")) as f:
            recorded = f.read().strip()
    except OSError:
        return False
    return recorded == cmdline and all(os.path.isfile(os.path.join(run_dir, o)) for o in outputs) \
        and bool(read_summary(run_dir))


def error_line(stderr, returncode):
    """(message, final): the `fsiopt: error:` line's message (final: do not retry) or a
    description of how the run died."""
    lines = [l.strip() for l in stderr.splitlines() if l.strip()]
    for l in reversed(lines):
        if l.startswith("fsiopt: error:"):
            return l[len("fsiopt: error:"):].strip(), True
    msg = "killed by signal %d" % -returncode if returncode < 0 else "exit status %d" % returncode
    if lines:
        msg += " (stderr: %s)" % lines[-1][:300]
    return msg, False


def stop_runs(signum=None):
    """No new run and no retry from now on; signum: also sent to the running fsiopt
    processes (e.g. SIGTERM: each writes a checkpoint of its last step and stops). Without
    it the processes are left alone (after a Ctrl-C they have their SIGINT already: a
    second signal would kill them before their checkpoint)."""
    STOP.set()
    if signum:
        with _children_lock:
            for p in list(_children):
                try:
                    p.send_signal(signum)
                except OSError:
                    pass


def execute(cmd, run_dir, env=None, timeout=None):
    """Runs cmd once (launch(); env None: fsiopt_env()), keeps its output in
    run_dir/stdout.log and stderr.log. Returns (returncode or None, stdout, stderr, elapsed
    s, timed out)."""
    returncode, stdout, stderr, elapsed, timed_out, _ = launch(cmd, env, ROOT, timeout)
    for name, text in (("stdout.log", stdout), ("stderr.log", stderr)):
        with open(os.path.join(run_dir, name), "w") as f:
            f.write(text)
    return returncode, stdout, stderr, elapsed, timed_out


def _clear_outputs(v):
    """cmd.txt and the outputs (resumable: also their .partial files, so that a part is
    never counted from an older process's)."""
    remove_files(v.run_dir, ["cmd.txt"] + [n for o in v.outputs for n in ((o, o + ".partial") if v.resumable else (o,))])


def run_variant(v, fsiopt, runs_dir, force=False, retries=2, wait_s=5.0, env=None):
    """Run (or re-use, or resume) one variant; sets v.status, v.error, v.summary, v.elapsed_s
    (the last process's; re-used: the run's wall time) and, resumable, v.totals."""
    cmd = v.command(fsiopt, runs_dir)
    cmdline = v.cmdline = shlex.join(cmd)
    if STOP.is_set():
        v.status, v.error = "failed", "not run: interrupted"
        return v
    if not force and is_complete(v.run_dir, cmdline, v.outputs):
        v.status, v.summary = "reused", read_summary(v.run_dir)
        v.elapsed_s = v.summary.get("wall_time_s", float("nan"))
        if v.resumable:
            v.totals = run_totals(v.run_dir, v.summary)
            v.elapsed_s = v.totals["wall_time_s"]
        say("  %-28s re-used %s" % (v.name, rel(v.run_dir)))
        return v
    os.makedirs(v.run_dir, exist_ok=True)
    step = resume_or_start_over(v, cmdline, force) if v.resumable else None
    _clear_outputs(v)
    options, fell_back, died = list(v.run_options), set(), 0
    checkpoint = os.path.join(v.run_dir, CHECKPOINT)
    while True:
        v.attempts += 1
        run_cmd = cmd + options + (["-restart", rel(checkpoint)] if step is not None else [])
        if step is not None:
            say("  %-28s resuming from step %d (%s): %s" % (v.name, step, rel(checkpoint), shlex.join(run_cmd)))
        else:
            say("  %-28s running: %s" % (v.name, shlex.join(run_cmd)))
        current = {"command": shlex.join(run_cmd), "first_step": (step or 0) + 1, "started": time.time()}
        if v.resumable:
            write_json(os.path.join(v.run_dir, CURRENT), current)
        returncode, stdout, stderr, v.elapsed_s, _ = execute(run_cmd, v.run_dir, env)
        if returncode == 0 and all(os.path.isfile(os.path.join(v.run_dir, o)) for o in v.outputs):
            with open(os.path.join(v.run_dir, "cmd.txt"), "w") as f:
                f.write(cmdline + "\n")
            v.status, v.error, v.summary = "ok", "", read_summary(v.run_dir)
            if v.resumable:
                v.totals = record_complete_run(v.run_dir, v.summary, current["command"])
            stall = v.summary.get("stalled_steps", 0)
            say("  %-28s done in %.1f s%s" % (v.name, v.elapsed_s,
                                             ", %d stalled steps (not converged)" % stall if stall else ""))
            return v
        if returncode is None:
            msg, final = stderr, False
        elif returncode == 0:
            msg, final = "exit status 0 but outputs missing in %s" % rel(v.run_dir), False
        else:
            msg, final = error_line(stderr, returncode)
            msg = "fsiopt: error: " + msg if final else msg
        v.status, v.error = "failed", msg
        if v.resumable:
            write_json(os.path.join(v.run_dir, CURRENT), dict(current, elapsed_s=v.elapsed_s, ended=msg))
        if final and v.resumable and not STOP.is_set():
            # once each: a refused restart starts over; refused checkpoints: without them
            why = msg[len("fsiopt: error: "):]
            if step is not None and why.startswith("option -restart") and "restart" not in fell_back:
                fell_back.add("restart")
                say("  %-28s restart refused (%s); starting over once" % (v.name, why[:300]))
            elif "option -checkpoint_every" in why and "-checkpoint_every" in options and "every" not in fell_back:
                fell_back.add("every")
                options = [o for i, o in enumerate(options) if o != "-checkpoint_every" and
                           (i == 0 or options[i - 1] != "-checkpoint_every")]
                say("  %-28s checkpoints refused (%s); starting over once without -checkpoint_every"
                    % (v.name, why[:300]))
            else:
                break
            step = None
            start_over(v.run_dir, cmdline)
            _clear_outputs(v)
            continue
        if final or died >= retries or STOP.is_set():
            break
        died += 1
        say("  %-28s died (%s); retrying in %g s" % (v.name, msg, wait_s), err=True)
        time.sleep(wait_s)
        if STOP.is_set():
            break
        if v.resumable:
            step = resume_or_start_over(v, cmdline, False)
        _clear_outputs(v)
    say("  %-28s FAILED: %s" % (v.name, v.error), err=True)
    return v


def run_all(variants, fsiopt, runs_dir, jobs=1, force=False, retries=2, oversubscribe=True):
    """Run the variants (jobs at a time; in fsiopt_env(), oversubscribe: its); duplicates
    by name are run once."""
    unique = list({v.name: v for v in variants}.values())
    env = fsiopt_env(oversubscribe=oversubscribe, jobs=jobs)
    say("%d run(s) in %s, %d at a time" % (len(unique), rel(runs_dir), jobs))
    progress = StudyProgress(len(unique))

    def one(v):
        progress.begin(v.name)
        run_variant(v, fsiopt, runs_dir, force, retries, env=env)
        progress.end(v.status == "reused")

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        list(pool.map(one, unique))
    return unique


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "the study, benchmark and check scripts under scripts/")
