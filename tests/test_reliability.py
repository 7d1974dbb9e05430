"""Reliability: signals (deterministic, -interrupt_test_step) and the closed standard output,
diverging steps and their retries, output ownership, full disks, memory, ranks, summary.json.
Checkpoints and restarts: test_restarts.py; bad input and -help: test_bad_input.py."""
import csv, os, shutil, subprocess

from harness import (CHANNEL, FLUID_SPACE, ROOT, turek, WORK, S, checkpoint_step, fail_text, fr, inputs_dir,
                     interrupted, out_dir, read_probes, refused, run, same_file, solve, test, ITERATIVE_ILU)


@test("SIGINT, SIGTERM, SIGHUP: the run stops after the step, outputs complete, converged false, exit != 0", quick=True)
def test_sigint_sigterm_stop_after_the_step():
    details = []
    for name, step, nproc in (("SIGINT", 7, 1), ("SIGTERM", 10, 2), ("SIGHUP", 5, 1)):
        rc, err, out = interrupted(name, step, nproc)
        lines = [l for l in err.splitlines() if l.strip()]
        if nproc > 1:   # mpiexec adds its own lines about the ranks' exit status
            lines = [l for l in lines if l.startswith("fsiopt")]
        assert rc != 0, "%s: exit 0" % name
        assert len(lines) == 1 and lines[0].startswith("fsiopt: error: interrupted by %s after step %d " % (name, step)) \
            and "-restart" in lines[0], "%s: stderr %s" % (name, lines)
        s = fr.read_summary(out)
        assert s["converged"] is False and s["interrupted"] == name, "%s: summary %s" % (name, s)
        assert s["steps_done"] == step, "%s after step %d: steps_done %d" % (name, step, s["steps_done"])
        assert checkpoint_step(os.path.join(out, "checkpoint.h5")) == step, "%s: the checkpoint is not of step %d" % (name, step)
        head, rows = read_probes(os.path.join(out, "probes.csv"))  # complete, not .partial
        assert len(rows) == step + 1 and abs(rows[-1][0] - step * s["dt"]) < 1e-12, \
            "%s: %d probe rows, the last at t = %g" % (name, len(rows), rows[-1][0])
        # the checkpoint it left continues the run
        end = step + 3
        more = solve(CHANNEL + ["-t_final", repr(end * s["dt"]), "-restart", os.path.join(out, "checkpoint.h5")], nproc=nproc)
        assert more["first_step"] == step + 1 and more["steps_done"] == end, "%s: restart %s" % (name, more)
        details.append("%s on %d rank%s: stopped after step %d exactly, restarted at step %d" % (
            name, nproc, "s" if nproc > 1 else "", step, more["first_step"]))
    return ", ".join(details)


@test("SIGUSR2, SIGALRM, SIGQUIT, SIGXCPU (a batch system's or a limit's warning before its kill): the run stops after "
      "the step as under SIGTERM, with its checkpoint, complete outputs and one line; the checkpoint continues the run")
def test_batch_signals_stop_after_the_step():
    details = []
    for name, step in (("SIGUSR2", 7), ("SIGALRM", 5), ("SIGQUIT", 6), ("SIGXCPU", 8)):
        rc, err, out = interrupted(name, step)
        lines = [l for l in err.splitlines() if l.strip()]
        assert rc == 1 and len(lines) == 1 and \
            lines[0].startswith("fsiopt: error: interrupted by %s after step %d " % (name, step)), \
            "%s: exit %s, stderr %s" % (name, rc, lines)
        s = fr.read_summary(out)
        assert s["interrupted"] == name and s["steps_done"] == step and not os.path.exists(os.path.join(out, ".fsiopt.lock")) \
            and not [f for f in os.listdir(out) if f.endswith(".partial")], "%s: summary %s, left %s" % (
                name, s, os.listdir(out))
        assert checkpoint_step(os.path.join(out, "checkpoint.h5")) == step, "%s: the checkpoint is not of step %d" % (name, step)
        more = solve(CHANNEL + ["-t_final", repr((step + 2) * s["dt"]), "-restart", os.path.join(out, "checkpoint.h5")])
        assert more["first_step"] == step + 1, "%s: restart %s" % (name, more)
        details.append("%s after step %d" % (name, step))
    return ", ".join(details) + ": stopped there, checkpoint restarted"


@test("a file-size limit (RLIMIT_FSIZE 8 MB) under a run writing fields every step: SIGXFSZ ignored, the failing "
      "write reported in one line naming the file and 'File too large', exit 1, no lock left, what was written kept "
      "as .partial")
def test_file_size_limit():
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (8_000_000, 8_000_000))

    out = os.path.join(WORK, "file-size-limit")
    cmd = fr.fsiopt_command(CHANNEL + ["-t_final", "0.01", "-write_fields", "-write_fields_interval", "1"], 1, out)
    p = subprocess.run(cmd, cwd=ROOT, preexec_fn=limit, capture_output=True, text=True, timeout=300)
    lines = [l for l in (p.stdout + p.stderr).splitlines() if l.startswith("fsiopt: error")]
    left = os.listdir(out)
    assert p.returncode == 1 and len(lines) == 1 and "fields.h5" in lines[0] and "File too large" in lines[0], \
        "exit %s (-25: killed by SIGXFSZ), %s" % (p.returncode, lines or p.stderr[-300:])
    assert ".fsiopt.lock" not in left and "fields.h5.partial" in left and "summary.json" not in left, "left %s" % left
    return lines[0]


@test("the standard output's reader goes away (a closed pipe): the run stops after the step with a checkpoint and "
      "complete outputs, one line on stderr, exit != 0, and the checkpoint continues the run", quick=True)
def test_closed_stdout_pipe():
    out = os.path.join(WORK, "closed-pipe")
    cmd = fr.fsiopt_command(CHANNEL + ["-t_final", "0.05", "-progress_seconds", "0.2"], 1, out)
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.readline()   # the run started; then nobody reads its standard output any more
    proc.stdout.close()
    try:
        err = proc.stderr.read()
        rc = proc.wait(timeout=300)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise AssertionError("the run did not stop after its standard output was closed")
    lines = [l for l in err.splitlines() if l.strip()]
    assert rc not in (0, 141, -13), "exit status %d (141 or -13: killed by SIGPIPE)" % rc
    assert len(lines) == 1 and lines[0].startswith("fsiopt: error: interrupted by SIGPIPE after step ") and \
        "-restart" in lines[0], "stderr %s" % lines
    s = fr.read_summary(out)
    step = s["steps_done"]
    assert s["interrupted"] == "SIGPIPE" and s["converged"] is False and 0 < step < 500, "summary %s" % s
    assert checkpoint_step(os.path.join(out, "checkpoint.h5")) == step, "the checkpoint is not of step %d" % step
    _, rows = read_probes(os.path.join(out, "probes.csv"))  # complete, not .partial
    assert len(rows) == step + 1, "%d probe rows after step %d" % (len(rows), step)
    more = solve(CHANNEL + ["-t_final", repr((step + 2) * s["dt"]), "-restart", os.path.join(out, "checkpoint.h5")])
    assert more["first_step"] == step + 1 and more["steps_done"] == step + 2, "restart %s" % more
    return "stopped after step %d with its checkpoint, restarted at step %d" % (step, more["first_step"])


@test("SIGTERM, SIGINT, SIGHUP during the set-up: one line, exit != 0, no lock, no output left")
def test_signal_during_setup():
    details = []
    for name, nproc in (("SIGTERM", 1), ("SIGINT", 2), ("SIGHUP", 1)):
        out = os.path.join(WORK, "setup-signal-%s-%d" % (name, nproc))
        rc, stdout, err, summary = run(CHANNEL + ["-interrupt_test_setup", "-interrupt_test_signal", name], nproc=nproc, out=out)
        ours = [l for l in (stdout + err).splitlines() if l.startswith("fsiopt")]
        assert rc not in (0, None) and rc > 0, "%s: exit status %s" % (name, rc)
        assert len(ours) == 1 and ours[0].startswith("fsiopt: error: stopped by %s during the set-up" % name), \
            "%s: lines %s" % (name, ours)
        assert "PETSC ERROR" not in stdout + err and "MPI_ABORT" not in stdout + err, "%s: %s" % (name, err[-300:])
        assert not os.path.exists(out), "%s: left %s" % (name, os.listdir(out))
        details.append("%s on %d rank%s" % (name, nproc, "s" if nproc > 1 else ""))
    return ", ".join(details) + ": one line each, exit 1, nothing left"


@test("2 ranks: every run splits the meshes the same way (6 runs: the same layout signatures and checkpoint vectors)")
def test_partition_deterministic():
    import h5py
    sigs, states = set(), []
    for i in range(6):
        out = os.path.join(WORK, "split-%d" % i)
        solve(CHANNEL + ["-t_final", "0.0004", "-checkpoint_every", "4"], nproc=2, out=out)
        with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as f:
            sigs.add((float(f["run"].attrs["fluid_layout"]), float(f["run"].attrs["structure_layout"])))
            states.append([float(x) for x in f["fluid"]["state"][()]])
    spread = max(max(abs(a - b) for a, b in zip(s, states[0])) for s in states) / max(abs(x) for x in states[0])
    assert len(sigs) == 1 and spread <= 1e-10, "layouts %s, fluid states differ by %.2e" % (sigs, spread)
    return "one layout in 6 runs, fluid states within %.1e" % spread


@test("-output_dir is owned: a second run into it is refused with one line naming the owner, the first completes "
      "unharmed; a dead run's lock is taken over with a notice, another host's is refused")
def test_output_dir_lock():
    import socket, time
    shared, alone = os.path.join(WORK, "lock-shared"), os.path.join(WORK, "lock-alone")
    long_run = CHANNEL + ["-t_final", "0.01"]
    first = subprocess.Popen(fr.fsiopt_command(long_run, out_dir=shared), cwd=ROOT, env=fr.fsiopt_env(),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lock = os.path.join(shared, ".fsiopt.lock")
    for _ in range(200):   # until the first run holds the directory
        if os.path.exists(lock):
            break
        time.sleep(0.05)
    rc, stdout, err, _ = run(CHANNEL + ["-t_final", "0.001"], out=shared)
    _, first_err = first.communicate(timeout=300)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and lines[0].startswith("fsiopt: error: option -output_dir %s: in use by run %d" % (
        shared, first.pid)), "second run: exit %s, %s" % (rc, lines)
    assert first.returncode == 0, "the first run failed: %s" % first_err
    solve(long_run, out=alone)
    assert same_file(os.path.join(shared, "probes.csv"), os.path.join(alone, "probes.csv")) and \
        not os.path.exists(lock), "the first run's outputs were disturbed, or its lock stayed"
    # a lock left by a killed run on this host: taken over with a notice
    dead = subprocess.Popen(["true"])
    dead.wait()
    with open(lock, "w") as f:
        f.write("%d %s 2026-01-01T00:00:00\n" % (dead.pid, socket.gethostname()))
    rc, _, err, s = run(CHANNEL + ["-t_final", "0.0005"], out=shared)
    notice = [l for l in err.splitlines() if "taking over the lock of run %d" % dead.pid in l]
    assert rc == 0 and s and s["steps_done"] == 5 and len(notice) == 1 and not os.path.exists(lock), \
        "stale lock: exit %s, stderr %s" % (rc, err)
    # another host's lock cannot be judged from here: refused
    with open(lock, "w") as f:
        f.write("1 some-other-host 2026-01-01T00:00:00\n")
    rc, stdout, err, _ = run(CHANNEL + ["-t_final", "0.0005"], out=shared)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and "in use by run 1 on some-other-host" in lines[0] and os.path.exists(lock), \
        "other host's lock: exit %s, %s" % (rc, lines)
    os.remove(lock)
    return "second run refused naming run %d; first run's probes = a run alone; a dead run's lock taken over with " \
        "one notice; another host's lock refused" % first.pid


def small_disk(kib):
    """a tmpfs of kib KiB (root only): its mount point, or None"""
    if os.geteuid() != 0:
        return None
    d = os.path.join(WORK, "disk-%dk" % kib)
    os.makedirs(d, exist_ok=True)
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%dk" % kib, "tmpfs", d], capture_output=True)
    return d if r.returncode == 0 else None


@test("a full disk: one line naming the file, nothing truncated under a final name, no temporary, the last "
      "checkpoint intact; an unwritable -checkpoint_file refused before step 1 (tmpfs: root only)")
def test_full_disk():
    details = []
    fields = ["-write_fields", "-write_fields_interval", "10"]
    for kib, args, token, nproc in ((12, [], "cannot write %s/probes.csv (No space left on device)", 1),
                                    (12, [], "cannot write %s/probes.csv (No space left on device)", 2),
                                    (120, ["-checkpoint_every", "50"], "cannot write the checkpoint of step 50", 1),
                                    (200, ["-checkpoint_every", "50"], "the one of step 50 stays", 1),
                                    (200, fields, "cannot write %s/fields.h5 (No space left on device) at step", 1),
                                    (200, fields, "cannot write %s/fields.h5 (No space left on device) at step", 2)):
        disk = small_disk(kib)
        if disk is None:
            return "skipped: mounting a tmpfs needs root"
        try:
            out = os.path.join(disk, "out")
            rc, stdout, err, summary = run(CHANNEL + ["-t_final", "0.05", "-quiet"] + args, nproc=nproc, out=out)
            # 2 ranks: Open MPI's launcher adds its lines about the exit status
            lines = [l for l in (stdout + err).splitlines() if l.strip() and not l.startswith("fsiopt: channel2d:")
                     and (nproc == 1 or l.startswith("fsiopt"))]
            assert "HDF5-DIAG" not in stdout + err and "PETSC ERROR" not in stdout + err and "rank 0:" not in \
                stdout + err, "%d KiB, %d rank(s): library messages: %s" % (kib, nproc, (stdout + err)[-400:])
            left = sorted(os.listdir(out))
            assert rc != 0 and len(lines) == 1 and lines[0].startswith("fsiopt: error:") and \
                (token % out if "%s" in token else token) in lines[0], "%d KiB, %d rank(s): exit %s, %s" % (
                    kib, nproc, rc, lines)
            assert not [f for f in left if f in ("probes.csv", "history.csv", "summary.json") or f.endswith(".tmp")], \
                "%d KiB: left %s" % (kib, left)
            assert "probes.csv.partial" in left and "history.csv.partial" in left, "%d KiB: left %s" % (kib, left)
            if "stays" in token:
                assert checkpoint_step(os.path.join(out, "checkpoint.h5")) == 50, "the checkpoint of step 50 is gone"
            if "fields.h5" in token:
                assert "fields.h5.partial" in left and "fields.h5" not in left, "%d KiB: left %s" % (kib, left)
            details.append("%d KiB, %d rank(s): %s" % (kib, nproc, lines[0].split(": ", 2)[-1][:60]))
        finally:
            subprocess.run(["umount", disk], capture_output=True)
    for kib in (12, 16):   # the CSVs fit, the summary does not: every rank stops with rank 0's line
        disk = small_disk(kib)
        try:
            out = os.path.join(disk, "out")
            rc, stdout, err, summary = run(CHANNEL + ["-t_final", "0.0003", "-quiet"], nproc=2, out=out)
            ours = [l for l in (stdout + err).splitlines() if l.startswith("fsiopt")]
            left = sorted(os.listdir(out))
            assert rc != 0 and ours == ["fsiopt: error: cannot write %s/summary.json (No space left on device)" % out] \
                and "summary.json" not in left and not [f for f in left if f.endswith(".tmp")], \
                "summary on %d KiB, 2 ranks: exit %s, %s, left %s" % (kib, rc, ours, left)
        finally:
            subprocess.run(["umount", disk], capture_output=True)
    details.append("summary.json on 12 and 16 KiB, 2 ranks: one line")
    rc, stdout, err, _ = run(CHANNEL + ["-t_final", "0.001", "-checkpoint_every", "5", "-checkpoint_file",
                                        "/etc/passwd/ck.h5"], out=os.path.join(WORK, "ck-unwritable"))
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and "option -checkpoint_file /etc/passwd/ck.h5: cannot write there" in lines[0] \
        and not os.path.exists(os.path.join(WORK, "ck-unwritable")), "unwritable checkpoint file: %s" % lines
    return "; ".join(details) + "; unwritable -checkpoint_file refused before step 1"


@test("memory: a -refine a node cannot hold is refused before refining, with the estimate; -force runs it; the "
      "estimate bounds the peak resident memory within [1, 2.5] (1 rank, 2 ranks shared and split, iterative solvers)")
def test_memory_estimate():
    short = CHANNEL + ["-t_final", "0.0002"]
    cases = [("channel2d -refine 7", CHANNEL + ["-refine", "7"], "fluid mesh (box) with -refine 7: estimated memory"),
             ("a node of 0.05 GiB", short + ["-memory_per_node_gib", "0.05"],
              "more than the 0.05 GiB it has (-memory_per_node_gib); use fewer refinements or more nodes, or add "
              "-force")]
    refused(cases)
    rc, stdout, err, s = run(short + ["-memory_per_node_gib", "0.05", "-force"], tag="memory-force")
    assert rc == 0 and "fsiopt: notice: -force: fluid mesh (box) with -refine 0: estimated memory" in stdout + err \
        and s["memory_gib"]["estimate"] > 0.05, "-force: exit %s, %s" % (rc, (stdout + err)[-300:])
    ratios = []
    for label, args, nproc in (("channel2d -refine 1", short + ["-refine", "1"], 1),
                               ("channel2d on 2 ranks", short, 2),
                               ("channel2d split", short + ["-structure_ranks", "1"], 2),
                               ("tube3d", ["-options_file", "options/tube3d.yaml", "-t_final", "0.0001"], 1),
                               ("tube3d iterative", ["-options_file", "options/tube3d.yaml", "-t_final", "0.0001",
                                                     "-coupling_inner", "gmres"] + ITERATIVE_ILU, 1)):
        rc, stdout, err, s = run(args, nproc=nproc, tag="memory")
        assert rc == 0 and s, "%s: exit %s, %s" % (label, rc, err[-300:])
        ratio = s["memory_gib"]["estimate"] / s["memory_gib"]["peak"]
        assert 1 <= ratio <= 2.5, "%s: estimate %.3g GiB, peak %.3g GiB" % (label, s["memory_gib"]["estimate"],
                                                                          s["memory_gib"]["peak"])
        ratios.append("%s %.2f" % (label, ratio))
    return "2 refused; -force ran; estimate/peak: " + ", ".join(ratios)


@test("3 ranks: every scene's set-up and steps create the same PETSc objects on every rank (-check_rank_sync), "
      "shared and split, and agree with 1 rank (errors, probes)")
def test_three_ranks():
    cases = (("mms-fluid", ["-options_file", "options/mms-fluid.yaml"], 0),
             ("mms-stokes", ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.6"], 0),
             ("mms-stokes split", ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.6", "-structure_ranks", "1"], 0),
             ("channel2d", CHANNEL + ["-t_final", "0.0005"], 0),
             ("channel2d split", CHANNEL + ["-t_final", "0.0005", "-structure_ranks", "1"], 0),
             ("tube3d", ["-options_file", "options/tube3d.yaml", "-t_final", "0.0002"], 0),
             ("turek-hron fsi3", turek("fsi3") + ["-dt", "0.001", "-t_final", "0.003"], 0))
    details, serial = [], {}
    for name, args, _ in cases:
        base = name.split()[0]
        if base not in serial:
            one = out_dir("one-rank")
            rc, stdout, err, s1 = run(args, out=one)
            assert rc == 0, "%s on 1 rank: %s" % (name, fail_text(rc, stdout, err))
            serial[base] = (s1, probes_or_none(one))
        out = out_dir("three-ranks")
        rc, stdout, err, s3 = run(args + ["-check_rank_sync"], nproc=3, out=out)
        assert rc == 0, "%s on 3 ranks: %s" % (name, fail_text(rc, stdout, err))
        s1, (names, rows1) = serial[base][0], (serial[base][1] or ([], []))
        worst = 0.0
        for key, value in s1["errors"].items():
            worst = max(worst, abs(s3["errors"][key] - value) / abs(value))
        rows3 = (probes_or_none(out) or (None, []))[1]
        assert len(rows3) == len(rows1), "%s: %d probe rows on 3 ranks, %d on 1" % (name, len(rows3), len(rows1))
        for c in range(1, len(names)):
            scale = max(abs(r[c]) for r in rows1) or 1.0
            worst = max(worst, max(abs(a[c] - b[c]) for a, b in zip(rows1, rows3)) / scale)
        assert worst < 1e-7, "%s: 3 ranks differ from 1 by %.2e (relative)" % (name, worst)
        details.append("%s %.0e" % (name, worst))
    return "largest relative difference to 1 rank: " + ", ".join(details)


def probes_or_none(out):
    path = os.path.join(out, "probes.csv")
    return read_probes(path) if os.path.exists(path) else None


@test("an error on any rank: one fsiopt line (with the rank when only some ranks stop), exit != 0, no MPI_ABORT "
      "banner, no lock or directory left, on 2 and 3 ranks, shared and split")
def test_errors_on_any_rank():
    bad_wall = os.path.join(inputs_dir(), "rank-missing-node.msh")
    lines = open(os.path.join(ROOT, "meshes", "wall.msh")).read().split("\n")
    end = lines.index("$EndElements")
    lines[end - 1] = " ".join(lines[end - 1].split()[:-1] + ["999"])
    open(bad_wall, "w").write("\n".join(lines))
    short = CHANNEL + ["-t_final", "0.0002"]
    cases = (
        ("2 ranks shared, every rank", 2, ["-scene", "mms-stokes", "-fluid_density", "0"], "option -fluid_density", False),
        ("2 ranks split, the structure's rank", 2, ["-scene", "mms-stokes", "-structure_ranks", "1", "-structure_density", "0"],
         "rank 1: option -structure_density", True),
        ("3 ranks split, the structure's rank", 3, ["-scene", "mms-stokes", "-structure_ranks", "1",
                                                    "-structure_dm_plex_filename", bad_wall],
         "rank 2: option -structure_dm_plex_filename", True),
        ("3 ranks, every rank", 3, S + ["-structure_dm_plex_filename", bad_wall], "refers to node 999", False),
        ("3 ranks split, the structure's two ranks", 3, short + ["-structure_ranks", "2", "-structure_poisson_ratio", "0.6"],
         "rank 1: option -structure_poisson_ratio", True),
        ("-structure_ranks 2 on 2 ranks", 2, ["-scene", "mms-stokes", "-structure_ranks", "2"], "option -structure_ranks", False),
        ("-structure_ranks 3 on 3 ranks", 3, ["-scene", "mms-stokes", "-structure_ranks", "3"], "option -structure_ranks", False),
    )
    problems = []
    for name, nproc, args, token, ranked in cases:
        out = os.path.join(WORK, "rank-error-%d" % len(problems + [name]) + name.split()[0])
        rc, stdout, err, summary = run(args, nproc=nproc, out=out)
        ours = [l for l in (stdout + err).splitlines() if l.startswith("fsiopt")]
        why = []
        if rc == 0: why.append("exit 0")
        if "MPI_ABORT" in stdout + err: why.append("MPI_ABORT banner")
        if "PETSC ERROR" in stdout + err: why.append("PETSc traceback")
        if len(ours) != 1 or not ours[0].startswith("fsiopt: error:") or token not in ours[0]: why.append("lines %s" % ours)
        if ranked != ("rank " in ours[0] if ours else False): why.append("rank named: %s" % ranked)
        if os.path.exists(out): why.append("left %s" % os.listdir(out))
        if why: problems.append("%s: %s" % (name, ", ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d cases: one line each, the rank named where only the structure's ranks stopped" % len(cases)


@test("-structure_ranks by default gives the structure the whole ranks its share of the unknowns fills: mms-stokes "
      "(30 % structure) shares 2 ranks and splits 4 ranks 3 | 1, stated in the first line, and the split run's errors "
      "are the 1-rank run's (1e-7)")
def test_sized_structure_ranks():
    args = ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.55"]
    one = solve(args)
    details = []
    for nproc in (2, 4):
        rc, stdout, err, s = run(args, nproc=nproc, tag="sized")
        assert rc == 0 and s, "%d ranks: %s" % (nproc, fail_text(rc, stdout, err))
        share = s["structure_dofs"] / (s["fluid_dofs"] + s["structure_dofs"])
        K = int(nproc * share)
        expected = {"fluid": nproc - K, "structure": K, "total": nproc} if K else \
            {"fluid": nproc, "structure": nproc, "total": nproc}
        assert s["ranks"] == expected, "%d ranks, structure share %.3f: layout %s, expected %s" % (
            nproc, share, s["ranks"], expected)
        said = "(%d fluid | %d structure)" % (nproc - K, K)
        assert (said in stdout) == (K > 0), "%d ranks: the first line %s" % (nproc, stdout.splitlines()[:1])
        worst = max(abs(s["errors"][k] - v) / abs(v) for k, v in one["errors"].items())
        assert worst <= 1e-7, "%d ranks: errors differ from 1 rank's by %.1e" % (nproc, worst)
        details.append("%d ranks: %s, errors within %.0e of 1 rank" % (nproc, said if K else "shared", worst))
    return "structure share %.3f; %s" % (share, "; ".join(details))


def diverging_cases():
    return [
        ("mesh motion inverting cells", ["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-gcl_amplitude", "0.6"], "inverted or degenerate at step 3"),
        ("mesh motion inverting hexahedra", ["-scene", "gcl", "-dt", "0.01", "-t_final", "0.1", "-gcl_amplitude", "0.6",
                                             "-fluid_dm_plex_dim", "3", "-fluid_dm_plex_box_faces", "4,4,2"], "inverted or degenerate at step 3"),
        # a soft, heavy wall: it bends before the fluid's velocities defeat its solver
        ("over-sized load inverts the channel's cells", CHANNEL + ["-t_final", "0.005", "-parameter_amplitude", "1e6",
                                                                   "-structure_youngs_modulus", "3e3", "-structure_density", "10"],
         "inverted or degenerate at step"),
        ("unrelaxed Dirichlet-Neumann diverges (added mass)", CHANNEL + ["-t_final", "0.001", "-coupling", "dn"], "coupling dn diverged at step 1"),
        ("diverging relaxed descent", ["-options_file", "options/mms-stokes.yaml", "-t_final", "0.6", "-tao_type", "sdrelaxed",
                                       "-coupling_tikhonov", "1e-4", "-tao_sdrelaxed_alpha", "0.5"], "at step 1, iteration"),
        ("structure Newton without retries", ["-options_file", "options/mms-structure.yaml", "-structure_model", "svk", "-dt", "0.05",
                                              "-structure_snes_max_it", "5", "-dt_min", "0.05"], "structure solve failed at step 1"),
    ]


@test("diverging step past -dt_min: says where, converged false, outputs to the step before")
def test_diverging_steps():
    problems = []
    cases = diverging_cases()
    for i, (name, args, token) in enumerate(cases):
        out = os.path.join(WORK, "diverging-%d" % i)
        shutil.rmtree(out, ignore_errors=True)
        rc, stdout, err, s = run(args, out=out)
        lines = [l for l in err.splitlines() if l.strip()]
        why = []
        if rc == 0: why.append("exit 0")
        if "PETSC ERROR" in stdout + err: why.append("PETSc traceback")
        if len(lines) != 1 or not lines[0].startswith("fsiopt: error: ") or token not in lines[0] or "from t = " not in lines[0]:
            why.append("stderr %s lacks one error line with '%s' and 'from t = '" % (lines, token))
        if s is None: why.append("no summary.json")
        else:
            if s["converged"] is not False or token not in (s["failure"] or ""): why.append("summary converged %s, failure %s" % (s["converged"], s["failure"]))
            if not 0 <= s["steps_done"] < s["steps"]: why.append("steps_done %s of %s" % (s["steps_done"], s["steps"]))
            if s["errors"]: why.append("errors of a failed state reported")
            probes = os.path.join(out, "probes.csv")
            if os.path.exists(probes) and len(read_probes(probes)[1]) != s["steps_done"] + 1:
                why.append("probes.csv rows != steps_done + 1")
            retries = "no retries" not in lines[0] if lines else False
            if retries and ("-dt_min" not in lines[0] or s["failed_attempts"] < 2): why.append("not retried down to -dt_min")
        if why: problems.append("%s: %s" % (name, ", ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d cases" % len(cases)


@test("a stopping signal when a step fails ends the run before the retries, at the step before, with its checkpoint, "
      "which continues the run as one written after that step does")
def test_signal_stops_retries():
    # channel2d with two Gauss-Newton iterations allowed: step 8 is the first that fails and would be retried
    base = CHANNEL + ["-t_final", "0.005", "-coupling_tol", "1e-6", "-dt", "5e-4", "-coupling_max_it", "2"]
    details = []
    for nproc in (1, 2):
        stopped, after = os.path.join(WORK, "stop-retry-%d" % nproc), os.path.join(WORK, "stop-after-%d" % nproc)
        for d in (stopped, after):
            shutil.rmtree(d, ignore_errors=True)
        rc, stdout, err, s = run(base + ["-interrupt_test_failure"], nproc=nproc, out=stopped)
        lines = [l for l in err.splitlines() if l.startswith("fsiopt")]
        assert rc != 0 and len(lines) == 1 and lines[0].startswith("fsiopt: error: interrupted by SIGTERM after step 7 ") \
            and "-restart" in lines[0], "%d ranks: rc %d, stderr %s" % (nproc, rc, lines)
        assert "not retried: SIGTERM" in stdout and "retrying with dt" not in stdout, "%d ranks: the step was retried" % nproc
        assert s["steps_done"] == 7 and s["failed_attempts"] == 1 and s["interrupted"] == "SIGTERM" and s["failure"] is None \
            and s["converged"] is False, "%d ranks: summary %s" % (nproc, s)
        assert checkpoint_step(os.path.join(stopped, "checkpoint.h5")) == 7, "%d ranks: the checkpoint is not of step 7" % nproc
        assert len(read_probes(os.path.join(stopped, "probes.csv"))[1]) == 8, "%d ranks: probes.csv does not end at step 7" % nproc
        rows = list(csv.DictReader(open(os.path.join(stopped, "history.csv"))))
        assert [r["event"] for r in rows if r["event"] in ("retry", "failed")] == ["failed"], "%d ranks: history's events" % nproc
        # the checkpoint is the one a signal after step 7 leaves: both continue the run alike, byte for byte
        rc2, _, err2, _ = run(base + ["-interrupt_test_step", "7"], nproc=nproc, out=after)
        assert rc2 != 0 and checkpoint_step(os.path.join(after, "checkpoint.h5")) == 7, "signal after step 7: %s" % err2
        ends = []
        for d in (stopped, after):
            more = solve(base + ["-restart", os.path.join(d, "checkpoint.h5")], nproc=nproc, out=d + "-restarted")
            assert more["first_step"] == 8 and more["steps_done"] == 10, "restart of %s: %s" % (d, more)
            ends.append(os.path.join(d + "-restarted", "probes.csv"))
        if nproc == 1:
            assert same_file(*ends), "1 rank: the two checkpoints continue differently"
        else:  # to round-off: two ranks' MUMPS may add in another order from run to run
            gap = fr.probes_difference(read_probes(ends[0])[1], read_probes(ends[1])[1])
            assert gap <= 1e-12, "%d ranks: the two checkpoints continue differently (%.1e)" % (nproc, gap)
        details.append("%d rank%s: stopped at step 8's first failure, 1 failed attempt" % (nproc, "s" if nproc > 1 else ""))
    return "%s; each checkpoint of step 7 continues the run as one written after step 7 (1 rank byte for byte, 2 " \
        "ranks to 1e-12)" % ", ".join(details)


@test("diverging steps retried with dt/2: = the run at dt/2 (SVK), near the smallest dt's run (channel2d)")
def test_retried_steps():
    svk = ["-options_file", "options/mms-structure.yaml", "-structure_model", "svk"]
    # Newton needs 6-7 iterations per step at dt 0.05, 5 at 0.025: every step fails once
    retried = solve(svk + ["-dt", "0.05", "-structure_snes_max_it", "5"])
    half = solve(svk + ["-dt", "0.025", "-structure_snes_max_it", "5"])
    full = solve(svk + ["-dt", "0.05"])
    assert retried["retried_steps"] == retried["steps"] == retried["failed_attempts"] and retried["smallest_dt"] == 0.025, \
        "retried %d of %d steps, %d failed attempts, smallest dt %g" % (retried["retried_steps"], retried["steps"], retried["failed_attempts"], retried["smallest_dt"])
    assert half["failed_attempts"] == 0 and retried["converged"], "the dt/2 run failed too"
    for k in retried["errors"]:
        a, b, c = retried["errors"][k], half["errors"][k], full["errors"][k]
        assert abs(a - b) <= 1e-8 * b, "%s: retried %.10e, dt/2 %.10e" % (k, a, b)
        assert c > 2 * b, "%s: dt and dt/2 runs too close to tell apart (%.3e, %.3e)" % (k, c, b)
    # coupled (opt): one Gauss-Newton iteration allowed; the steps that need two at dt are halved
    base = CHANNEL + ["-t_final", "0.0015", "-coupling_tol", "1e-6"]
    out = os.path.join(WORK, "retry-coupled")
    s = solve(base + ["-dt", "5e-4", "-coupling_max_it", "1"], out=out)
    assert s["converged"] and s["retried_steps"] >= 1 and s["max_interface_jump"] <= 1e-6, "coupled: %s" % s
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    retries = [r for r in rows if r["event"] == "retry"]
    assert len(retries) == s["failed_attempts"] and all(float(r["dt"]) > s["smallest_dt"] for r in retries), "history retry rows"
    last = {int(r["step"]): float(r["jump"]) for r in rows if r["event"] == ""}
    assert sorted(last) == [1, 2, 3] and max(last.values()) <= 1e-6, "last jumps %s" % last
    head, got = read_probes(os.path.join(out, "probes.csv"))
    assert [r[0] for r in got] == [0, 5e-4, 1e-3, 1.5e-3], "probe times %s" % [r[0] for r in got]
    split = os.path.join(WORK, "retry-split")
    solve(base + ["-dt", "5e-4", "-coupling_max_it", "1", "-structure_ranks", "1"], nproc=2, out=split)
    assert same_file(os.path.join(split, "probes.csv"), os.path.join(out, "probes.csv")), \
        "fluid | structure ranks retry differently from 1 rank"
    ends = []
    for tag, dt in (("fine", repr(s["smallest_dt"])), ("coarse", "5e-4")):
        solve(base + ["-dt", dt], out=os.path.join(WORK, "retry-" + tag))
        ends.append(read_probes(os.path.join(WORK, "retry-" + tag, "probes.csv"))[1][-1])
    fine, coarse = ends
    # most of the retried run's steps were taken at the smallest dt: its end is near that run's
    scale = [max(abs(fine[c]), abs(coarse[c])) for c in range(len(head))]
    to_fine = sum(abs(got[-1][c] - fine[c]) / scale[c] for c in range(1, len(head)))
    to_coarse = sum(abs(got[-1][c] - coarse[c]) / scale[c] for c in range(1, len(head)))
    assert to_fine < 0.25 * to_coarse, "retried run's probes: %.3f from the smallest-dt run, %.3f from the dt run" % (to_fine, to_coarse)
    return "SVK: all %d steps halved = dt/2 run to 1e-8; channel2d: %d steps retried (dt down to %g; 2 ranks identical), probes %.3f from that dt's run, %.3f from dt's" % (
        retried["steps"], s["retried_steps"], s["smallest_dt"], to_fine, to_coarse)


@test("summary.json has every key of docs/outputs.md", quick=True)
def test_summary_keys():
    s = solve(FLUID_SPACE)
    keys = ["scene", "coupling", "optimizer", "dim", "steps", "dt", "t_final", "wall_time_s", "fluid_solves",
            "fluid_linear_solves", "structure_solves", "coupling_iterations", "avg_coupling_iterations",
            "work_factor", "max_interface_jump", "factorizations", "converged", "errors", "quantities", "ranks"]
    missing = [k for k in keys if k not in s]
    assert not missing, "missing keys %s" % missing
    assert s["scene"] == "mms-fluid" and s["dim"] == 2 and s["steps"] == 1 and s["converged"] is True
    assert s["fluid_solves"] == 1 and s["structure_solves"] == 0 and s["coupling"] == "none"
    assert s["worst_corner_ratio"] is None and s["worst_corner_time"] is None, "a fixed mesh has no worst corner"
    return "%d keys" % len(keys)
