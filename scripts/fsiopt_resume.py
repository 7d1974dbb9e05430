#!/usr/bin/env python3
"""Resumable runs of the study scripts and fsiopt's checkpoints as they see them: the step a
checkpoint ends (checkpoint_step, also read by the tests), whether an unfinished run can
continue from its checkpoint, and the parts of a run that did (attempts.json) with their
totals. scripts/fsiopt_runs.py's run_variant() drives them.

Resumable variants (Variant(..., resumable=True); only scripts/turek_hron_table.py makes
them) continue an unfinished run from fsiopt's checkpoint instead of starting over:
  - the command line that identifies the run (cmd.txt's; Variant.run_options, e.g.
    -checkpoint_every K, are passed to the process but are not part of it) is written to
    cmd.pending before a fresh start, and current_attempt.json records each process
    (its exact command, first step, start time; its elapsed time and error once it ends);
  - a run directory without a complete run but with a checkpoint.h5 whose cmd.pending is
    the command line we would run now is continued with `-restart <dir>/checkpoint.h5`
    (one line `resuming from step N` on stdout), also on a retry after the process died; a
    checkpoint without cmd.pending, of another command line, or unreadable is deleted (one
    line why) and the run starts over, as with --force;
  - before a restart, the ended process is recorded as a part in attempts.json: the steps
    it hands on (first_step .. the checkpoint's step), its coupling iterations over them
    (its summary.json when it ended at the checkpoint, e.g. after SIGINT/SIGTERM; else
    counted in its history.csv(.partial): the rows with iteration >= 1 of those steps) and
    its whole wall time (summary.json; else the time the script measured; else estimated
    from its files' times), including any steps it ran past the checkpoint, which the next
    part runs again; the complete run's last part is appended too, and run_totals() sums
    the parts (fsiopt's own summary.json of a restarted run covers only its last part);
  - a restart that fsiopt refuses (`fsiopt: error: option -restart ...`: another dt, other
    unknowns or rank count, a checkpoint at the last step) starts over once, with a note;
    so does a run whose -checkpoint_every (a run option) fsiopt refuses, without it;
  - after a complete run, checkpoint.h5, cmd.pending and current_attempt.json are deleted;
    attempts.json stays with cmd.txt."""
import csv, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fsiopt_tables import number, read_json, read_summary, remove_files, say, write_json  # noqa: E402

# the files of a resumable run's directory besides its outputs (see the module docstring)
CHECKPOINT, PENDING, ATTEMPTS, CURRENT = "checkpoint.h5", "cmd.pending", "attempts.json", "current_attempt.json"


def read_parts(run_dir):
    """The parts recorded in run_dir/attempts.json (a list; [] without one)."""
    parts = read_json(os.path.join(run_dir, ATTEMPTS))
    return parts if isinstance(parts, list) else []


def checkpoint_step(path):
    """The step fsiopt's checkpoint ends (attribute 'step' of its /run group). Raises."""
    import h5py   # only needed to resume
    with h5py.File(path, "r") as f:
        return int(f["run"].attrs["step"])


def resume_point(run_dir, cmdline):
    """(step, why not): the step of run_dir/checkpoint.h5 when the unfinished run there was
    started with cmdline (its cmd.pending); else (None, why it cannot be used, or "" when
    there is no checkpoint)."""
    path = os.path.join(run_dir, CHECKPOINT)
    if not os.path.isfile(path):
        return None, ""
    try:
        with open(os.path.join(run_dir, PENDING)) as f:
            pending = f.read().strip()
    except OSError:
        return None, "deleting %s (no cmd.pending: of an unknown command line); starting over" % CHECKPOINT
    if pending != cmdline:
        return None, "deleting %s (cmd.pending: of another command line); starting over" % CHECKPOINT
    try:
        return checkpoint_step(path), ""
    except Exception as e:   # h5py missing, a truncated file, not fsiopt's
        return None, "deleting %s (unreadable: %s); starting over" % (CHECKPOINT, str(e).splitlines()[0][:200] if str(e)
                                                                        else type(e).__name__)


def _count_iterations(run_dir, first, last):
    """(coupling iterations of steps first..last, file) from history.csv(.partial): its rows
    with iteration >= 1 (fsiopt counts the last iteration of each optimizer solve); (None,
    None) without a history."""
    for name in ("history.csv.partial", "history.csv"):
        try:
            with open(os.path.join(run_dir, name), newline="") as f:
                rows = csv.reader(f)
                header = next(rows, [])
                i_step, i_it = header.index("step"), header.index("iteration")
                n = 0
                for r in rows:
                    try:
                        step, it = int(r[i_step]), int(r[i_it])
                    except (IndexError, ValueError):
                        continue
                    if first <= step <= last and it >= 1:
                        n += 1
                return n, name
        except (OSError, ValueError):
            continue
    return None, None


def _last_probe_step(run_dir):
    """The last step in probes.csv(.partial) (its rows after the header, less the row of t_start)."""
    for name in ("probes.csv.partial", "probes.csv"):
        try:
            with open(os.path.join(run_dir, name)) as f:
                n = sum(1 for line in f if line.strip())
            return n - 2 if n >= 2 else None
        except OSError:
            continue
    return None


def fold_attempt(run_dir, step, coupled):
    """Records the process that ran last in run_dir (current_attempt.json, its summary.json
    or history, its files) as a part of the run in attempts.json: steps first_step..step (the
    checkpoint the next part starts from), its coupling iterations over them, its whole wall
    time. Nothing when no process ran since the last part was recorded."""
    cur = read_json(os.path.join(run_dir, CURRENT))
    s = read_summary(run_dir)
    if not cur and not s:
        return
    parts = read_parts(run_dir)
    first = cur.get("first_step") or s.get("first_step") or (parts[-1]["last_step"] + 1 if parts else 1)
    if s and s.get("first_step", 1) != first:
        s = {}   # not this process's
    part = {"part": len(parts) + 1, "command": cur.get("command", ""), "first_step": first, "last_step": step,
            "steps": max(0, step - first + 1)}
    ran_to = s.get("steps_done") if s else _last_probe_step(run_dir)
    part["ran_to_step"] = ran_to
    if s and s.get("steps_done") == step:
        part.update(coupling_iterations=s.get("coupling_iterations"), stalled_steps=s.get("stalled_steps"),
                    counts_from="summary.json")
    elif step < first:   # it ended before its first checkpoint: none of its steps is kept
        part.update(coupling_iterations=0, stalled_steps=0, counts_from="no step kept")
    elif coupled:
        n, name = _count_iterations(run_dir, first, step)
        part.update(coupling_iterations=n, stalled_steps=None, counts_from=name or "unknown (no history.csv)")
    else:
        part.update(coupling_iterations=0, stalled_steps=s.get("stalled_steps", 0) if s else 0,
                    counts_from="uncoupled")
    if s and number(s.get("wall_time_s")) is not None:
        part.update(wall_time_s=s["wall_time_s"], wall_time_from="summary.json")
    elif number(cur.get("elapsed_s")) is not None:
        part.update(wall_time_s=cur["elapsed_s"], wall_time_from="measured by the script")
    elif number(cur.get("started")) is not None:
        times = [os.path.getmtime(os.path.join(run_dir, n)) for n in
                 (CHECKPOINT, "probes.csv.partial", "history.csv.partial", "stdout.log", "stderr.log")
                 if os.path.isfile(os.path.join(run_dir, n))]
        end = max(times) if times else cur["started"]
        part.update(wall_time_s=max(0.0, end - cur["started"]), wall_time_from="estimated from file times")
    else:
        part.update(wall_time_s=None, wall_time_from="unknown")
    if s.get("interrupted"):
        ended = "interrupted by %s" % s["interrupted"]
    elif s.get("failure"):
        ended = s["failure"]
    else:
        ended = cur.get("ended") or "unknown (no summary.json: the process was killed, or the script stopped)"
    part["ended"] = ended
    write_json(os.path.join(run_dir, ATTEMPTS), parts + [part])
    remove_files(run_dir, [CURRENT])


def summary_part(summary, index, command=""):
    """The part of a complete run's last process, from its summary.json."""
    first = summary.get("first_step", 1)
    last = summary.get("steps_done", summary.get("steps"))
    return {"part": index, "command": command, "first_step": first, "last_step": last,
            "steps": max(0, last - first + 1) if isinstance(last, int) else None, "ran_to_step": last,
            "coupling_iterations": summary.get("coupling_iterations"), "stalled_steps": summary.get("stalled_steps"),
            "counts_from": "summary.json", "wall_time_s": summary.get("wall_time_s"), "wall_time_from": "summary.json",
            "ended": "complete"}


def run_totals(run_dir, summary):
    """The whole run over its parts (attempts.json; a run without one is one part, its
    summary.json): parts, steps; coupling_iterations, avg_coupling_iterations (the sums
    over the parts when every part's count is known and the parts join up, else the last
    part's) and its_cover ("whole run" or "steps A-B"); stalled_steps (the sum, or None
    when a part's is unknown, e.g. of a killed process) and stalled_cover (the steps whose
    stalled steps are known: "whole run" or "steps A-B", the last part's); wall_time_s (the
    sum of the parts' known times) and wall_time_note ("", "estimated": a part's time
    estimated from file times, "lower bound": a part's time unknown)."""
    parts = read_parts(run_dir)
    if not parts or parts[-1].get("ended") != "complete":
        parts = parts + [summary_part(summary, len(parts) + 1)]
    last = parts[-1]
    last_steps = "steps %s-%s" % (last.get("first_step"), last.get("last_step"))
    steps = summary.get("steps_done", summary.get("steps"))
    joined = parts[0].get("first_step") == 1 and last.get("last_step") == steps and all(
        b.get("first_step") == a.get("last_step", -9) + 1 for a, b in zip(parts, parts[1:]))
    t = {"parts": len(parts), "steps": steps}
    its = [number(p.get("coupling_iterations")) for p in parts]
    if joined and None not in its:
        t.update(coupling_iterations=int(sum(its)), avg_coupling_iterations=sum(its) / max(steps or 0, 1),
                 its_cover="whole run")
    else:
        t.update(coupling_iterations=summary.get("coupling_iterations"),
                 avg_coupling_iterations=summary.get("avg_coupling_iterations"), its_cover=last_steps)
    stalled = [number(p.get("stalled_steps")) for p in parts]
    if joined and None not in stalled:
        t.update(stalled_steps=int(sum(stalled)), stalled_cover="whole run")
    else:
        t.update(stalled_steps=None, stalled_cover=last_steps)
    walls = [number(p.get("wall_time_s")) for p in parts]
    t["wall_time_s"] = sum(w for w in walls if w is not None)
    t["wall_time_note"] = "lower bound" if None in walls else \
        "estimated" if any(p.get("wall_time_from") == "estimated from file times" for p in parts) else ""
    return t


def start_over(run_dir, cmdline):
    """A fresh start of a resumable run: no checkpoint, no parts; cmd.pending = cmdline."""
    remove_files(run_dir, [CHECKPOINT, CHECKPOINT + ".tmp", ATTEMPTS, CURRENT])
    with open(os.path.join(run_dir, PENDING), "w") as f:
        f.write(cmdline + "\n")


def resume_or_start_over(v, cmdline, force):
    """The step to restart from (the ended process recorded as a part), or None (a fresh start)."""
    step, why = (None, "") if force else resume_point(v.run_dir, cmdline)
    if step is None:
        if why:
            say("  %-28s %s" % (v.name, why))
        start_over(v.run_dir, cmdline)
        return None
    fold_attempt(v.run_dir, step, "history.csv" in v.outputs)
    return step


def record_complete_run(run_dir, summary, command):
    """After the last process of a resumable run completed it: its part appended to
    attempts.json, the checkpoint, cmd.pending and current_attempt.json deleted. Returns
    run_totals()."""
    parts = read_parts(run_dir)
    write_json(os.path.join(run_dir, ATTEMPTS), parts + [summary_part(summary, len(parts) + 1, command)])
    remove_files(run_dir, [CHECKPOINT, CHECKPOINT + ".tmp", PENDING, CURRENT])
    return run_totals(run_dir, summary)


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "scripts/fsiopt_runs.py and the tests (checkpoint_step)")
