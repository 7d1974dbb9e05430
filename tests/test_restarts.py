"""Checkpoints and restarts: a restart continues the run that wrote the checkpoint (after
SIGKILL, SIGUSR1's checkpoint, a partitioned method, fluid | structure ranks, the mesh
solver's warm start), accepts the same problem written differently, survives SIGKILLs
during checkpoint writes, and at another dt keeps the scheme's order. Signals that stop a
run: test_reliability.py."""
import math, os, shutil, subprocess

from harness import (CHANNEL, ROOT, WORK, checkpoint_step, fail_text, fr, inputs_dir, interrupted, krylov_iterations,
                     out_dir, read_probes, run, same_file, solve, test, ITERATIVE_ILU)


@test("a restart accepts the same problem written differently (1.10 for 1.1, -t_start 0) and what does not change it "
      "(progress, memory, -force, -check_rank_sync): the probes continue exactly")
def test_restart_accepts_same_problem():
    d = inputs_dir()
    solve(CHANNEL + ["-t_final", "0.0002", "-checkpoint_every", "2"], out=os.path.join(d, "ck-same"))
    checkpoint = os.path.join(d, "ck-same", "checkpoint.h5")
    plain = os.path.join(WORK, "restart-plain")
    solve(CHANNEL + ["-t_final", "0.0004", "-restart", checkpoint], out=plain)
    other = os.path.join(WORK, "restart-respelled")
    solve(CHANNEL + ["-t_final", "0.0004", "-restart", checkpoint, "-structure_density", "1.10", "-t_start", "0",
                     "-progress_interval", "1", "-memory_per_node_gib", "64", "-force", "-check_rank_sync"], out=other)
    assert same_file(os.path.join(plain, "probes.csv"), os.path.join(other, "probes.csv")), "the probes differ"
    return "accepted; probes.csv byte for byte the plain restart's"


@test("SIGUSR1: a checkpoint of the step and the run goes on to its end (exit 0); the checkpoint continues it exactly")
def test_sigusr1_checkpoint():
    details = []
    for step, nproc in ((7, 1), (4, 2)):
        rc, err, out = interrupted("SIGUSR1", step, nproc, extra=["-t_final", "0.002"])
        stdout = open(os.path.join(out, "stdout.log")).read() if os.path.exists(os.path.join(out, "stdout.log")) else ""
        s = fr.read_summary(out)
        assert rc == 0 and s["converged"] and s["steps_done"] == 20 and not s.get("interrupted"), \
            "SIGUSR1 on %d ranks: exit %s, summary %s, stderr %s" % (nproc, rc, s, err)
        assert checkpoint_step(os.path.join(out, "checkpoint.h5")) == step, "the checkpoint is not of step %d" % step
        again = os.path.join(WORK, "sigusr1-again-%d" % nproc)
        more = solve(CHANNEL + ["-t_final", "0.002", "-restart", os.path.join(out, "checkpoint.h5")], nproc=nproc, out=again)
        assert more["first_step"] == step + 1, "restart at step %s" % more["first_step"]
        # 1 rank byte for byte; 2 ranks to the spread of the same 2-rank run repeated (its
        # reductions may add in another order: four runs of `mpiexec -n 2 bin/fsiopt -options_file
        # options/channel2d.yaml -t_final 0.002` differed by up to 6.4e-11 on one machine)
        gap = fr.probes_difference(read_probes(os.path.join(again, "probes.csv"))[1],
                                   read_probes(os.path.join(out, "probes.csv"))[1])
        assert (same_file(os.path.join(out, "probes.csv"), os.path.join(again, "probes.csv")) if nproc == 1
                else gap <= 1e-9), "SIGUSR1 on %d ranks: the restarted probes differ from the run that went on " \
            "by %.1e" % (nproc, gap)
        details.append("%d rank%s: checkpoint of step %d, run went on to step 20, restart = it %s" % (
            nproc, "s" if nproc > 1 else "", step, "byte for byte" if nproc == 1 else "to %.0e" % gap))
    return "; ".join(details)


@test("an iterative mesh solver starts from the mesh in hand (-mesh_motion_warm_start): tube3d with the iterative "
      "solver files, four steps: at most 0.85 x the CG iterations from zero, and a restart from step 2 continues the "
      "run byte for byte")
def test_mesh_warm_start_restart():
    args = ["-options_file", "options/tube3d.yaml", "-coupling_inner", "gmres", "-mesh_ksp_converged_reason"] + \
        ITERATIVE_ILU
    its, outs = {}, {}
    # the run a checkpoint continues is the one that wrote it (it starts its next step as a restart does)
    for name, extra in (("warm", ["-t_final", "0.0004", "-checkpoint_every", "2"]),
                        ("cold", ["-t_final", "0.0004", "-mesh_motion_warm_start", "0"]),
                        ("first half", ["-t_final", "0.0002", "-checkpoint_every", "2"])):
        outs[name] = out_dir("mesh-%s" % name.split()[0])
        rc, stdout, err, s = run(args + extra, out=outs[name])
        assert rc == 0 and s, "%s: %s" % (name, fail_text(rc, stdout, err))
        solves = krylov_iterations(stdout, "mesh")
        its[name] = sum(solves) / max(len(solves), 1)
    assert its["warm"] <= 0.85 * its["cold"], "CG iterations per mesh solve %.2f warm, %.2f from zero" % (
        its["warm"], its["cold"])
    again = out_dir("mesh-restart")
    more = solve(args + ["-t_final", "0.0004", "-restart", os.path.join(outs["first half"], "checkpoint.h5")], out=again)
    assert more["first_step"] == 3, "restart at step %s" % more["first_step"]
    assert same_file(os.path.join(outs["warm"], "probes.csv"), os.path.join(again, "probes.csv")), \
        "the restarted probes differ from the run's by %.1e" % fr.probes_difference(
            read_probes(os.path.join(again, "probes.csv"))[1], read_probes(os.path.join(outs["warm"], "probes.csv"))[1])
    return "CG iterations per mesh solve %.2f (from zero %.2f); restart at step 3 = the run byte for byte" % (
        its["warm"], its["cold"])


@test("10 SIGKILLs while checkpoints are written, then a run with the same checkpoint name and directory: it "
      "completes (no lock, semaphore or shared-memory file left behind), and its checkpoint restarts")
def test_killed_checkpoint_writes():
    import random, time
    out = os.path.join(WORK, "killed-writes")
    ck = os.path.join(out, "ck.h5")
    args = CHANNEL + ["-t_final", "0.01", "-checkpoint_every", "1", "-checkpoint_file", ck, "-quiet"]
    shm_before = set(os.listdir("/dev/shm")) if os.path.isdir("/dev/shm") else set()
    rng, kills = random.Random(7), 0
    for _ in range(10):
        p = subprocess.Popen(fr.fsiopt_command(args, out_dir=out), cwd=ROOT, env=fr.fsiopt_env(),
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(400):   # until it writes its first checkpoint
            if os.path.exists(ck) or os.path.exists(ck + ".tmp"):
                break
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.3))
        p.kill()
        p.wait()
        kills += p.returncode == -9
    left = sorted(set(os.listdir("/dev/shm")) - shm_before) if os.path.isdir("/dev/shm") else []
    s = solve(args, out=out)
    assert s["converged"] and s["steps_done"] == 100, "the run after the kills: %s" % s
    more = solve(CHANNEL + ["-t_final", "0.0102", "-restart", ck], out=os.path.join(WORK, "killed-writes-restart"))
    assert more["first_step"] == 101, "its checkpoint restarts at step %s" % more["first_step"]
    assert not [f for f in left if "sm" in f.lower() or "ompi" in f.lower()], "left in /dev/shm: %s" % left
    return "%d of 10 runs killed mid-run; the next run with the same names completed and its checkpoint restarts; " \
        "nothing of theirs in /dev/shm" % kills


@test("restart from a checkpoint continues exactly, also after SIGKILL")
def test_restart_after_sigkill():
    every = ["-t_final", "0.01", "-checkpoint_every", "5"]
    full = os.path.join(WORK, "ck-full")
    solve(CHANNEL + every, out=full)
    # killed outright after step 33: the checkpoint of step 30, written before, stays
    rc, err, killed = interrupted("SIGKILL", 33, extra=every)
    assert rc == -9, "exit status %s after SIGKILL (stderr %s)" % (rc, err.strip()[-200:])
    assert not os.path.exists(os.path.join(killed, "summary.json")), "a killed run wrote summary.json"
    ck = os.path.join(killed, "checkpoint.h5")
    step = checkpoint_step(ck)
    assert step == 30, "the killed run's checkpoint is of step %d, not 30" % step
    restarted = os.path.join(WORK, "ck-restarted")
    s = solve(CHANNEL + every + ["-restart", ck], out=restarted)
    assert s["first_step"] == 31 and s["steps_done"] == 100, "restart at step %s, done %s" % (s["first_step"], s["steps_done"])
    assert same_file(os.path.join(full, "probes.csv"), os.path.join(restarted, "probes.csv")), \
        "the restarted run's probes.csv differs from the uninterrupted run's"
    return "killed after step 33, its checkpoint of step 30; restarted at step 31: probes.csv byte for byte the uninterrupted run's"


@test("a partitioned method (iqnimvj) restarted from its checkpoint continues exactly")
def test_partitioned_restart():
    args = CHANNEL + ["-coupling", "iqnimvj", "-checkpoint_every", "20"]
    full = os.path.join(WORK, "ckp-full")
    solve(args + ["-t_final", "0.008"], out=full)
    first = os.path.join(WORK, "ckp-first")
    solve(args + ["-t_final", "0.004"], out=first)
    ck = os.path.join(first, "checkpoint.h5")
    assert checkpoint_step(ck) == 40, "checkpoint of step %d, not 40" % checkpoint_step(ck)
    restarted = os.path.join(WORK, "ckp-restarted")
    s = solve(args + ["-t_final", "0.008", "-restart", ck], out=restarted)
    assert s["first_step"] == 41 and s["steps_done"] == 80, "restart at step %s, done %s" % (s["first_step"], s["steps_done"])
    assert same_file(os.path.join(full, "probes.csv"), os.path.join(restarted, "probes.csv")), \
        "the restarted iqnimvj run's probes.csv differs from the uninterrupted run's"
    return "restarted at step 41 of 80: probes.csv byte for byte the uninterrupted run's"


@test("fluid | structure ranks write checkpoints and restart from them: 2 and 3 ranks (the fluid on 1 and 2, the "
      "structure on 1 and 2) continue the run that wrote them as closely as two such runs agree (1e-12 on one fluid rank, 1e-9 on two, or 10 x), a SIGTERM's checkpoint too; a damaged part "
      "or another -structure_ranks is refused in one line")
def test_split_restart():
    details = []
    for nproc, structure in ((2, 1), (3, 1), (3, 2)):
        args = CHANNEL + ["-structure_ranks", str(structure), "-checkpoint_every", "10"]
        full, first, restarted = (os.path.join(WORK, "split-%s-%d-%d" % (n, nproc, structure)) for n in ("full", "first", "restarted"))
        solve(args + ["-t_final", "0.002"], nproc=nproc, out=full)
        solve(args + ["-t_final", "0.002"], nproc=nproc, out=full + "-again")
        solve(args + ["-t_final", "0.001"], nproc=nproc, out=first)
        ck = os.path.join(first, "checkpoint.h5")
        assert checkpoint_step(ck) == 10, "checkpoint of step %d, not 10" % checkpoint_step(ck)
        s = solve(args + ["-t_final", "0.002", "-restart", ck], nproc=nproc, out=restarted)
        assert s["first_step"] == 11 and s["steps_done"] == 20, "restart at step %s, done %s" % (s["first_step"], s["steps_done"])
        # to round-off. On two fluid ranks the factorization (MUMPS) does not add in one order from
        # run to run on a loaded machine: with two busy loops beside it, two uninterrupted runs
        # measured 1e-10 apart and a restart 3e-11, where fluid solves stopped at 1e-6 instead of
        # 1e-7 move the probes by 1.7e-7. One fluid rank adds in one order: 1e-12.
        reference = read_probes(os.path.join(full, "probes.csv"))[1]
        gap = fr.probes_difference(read_probes(os.path.join(restarted, "probes.csv"))[1], reference)
        itself = fr.probes_difference(read_probes(os.path.join(full + "-again", "probes.csv"))[1], reference)
        bound = max(1e-12 if nproc - structure == 1 else 1e-9, 10 * itself)
        assert gap <= bound, "%d ranks, -structure_ranks %d: the restarted probes differ from the uninterrupted " \
            "run's by %.1e (bound %.0e), two uninterrupted runs by %.1e" % (nproc, structure, gap, bound, itself)
        details.append("%d:%d %.0e (runs %.0e)" % (nproc, structure, gap, itself))
    rc, err, out = interrupted("SIGTERM", 10, 2, extra=["-structure_ranks", "1", "-t_final", "0.002"])
    ck = os.path.join(out, "checkpoint.h5")
    assert rc != 0 and os.path.exists(ck) and checkpoint_step(ck) == 10, \
        "SIGTERM on fluid | structure ranks: exit %s, checkpoint %s" % (rc, os.path.exists(ck))
    again = os.path.join(WORK, "split-sigterm-restarted")
    solve(CHANNEL + ["-structure_ranks", "1", "-t_final", "0.002", "-restart", ck], nproc=2, out=again)
    plain = os.path.join(WORK, "split-sigterm-plain")
    solve(CHANNEL + ["-structure_ranks", "1", "-t_final", "0.002", "-checkpoint_every", "10"], nproc=2, out=plain)
    gap = fr.probes_difference(read_probes(os.path.join(again, "probes.csv"))[1],
                               read_probes(os.path.join(plain, "probes.csv"))[1])
    assert gap <= 1e-12, "the SIGTERM checkpoint's restart differs from the run by %.1e" % gap
    import h5py
    problems = []
    source = os.path.join(WORK, "split-first-2-1", "checkpoint.h5")
    cases = [("the structure's part", "structure/load_old", ["-structure_ranks", "1"], "no dataset /structure/load_old"),
             ("the fluid's part", "fluid/state", ["-structure_ranks", "1"], "no dataset /fluid/state"),
             ("the coupling's fluid part", "coupling/mesh_displacement", ["-structure_ranks", "1"],
              "no dataset /coupling/mesh_displacement"),
             ("no split", None, [], "written with -structure_ranks 1, this run has 0")]
    for name, dataset, extra, token in cases:
        ck = os.path.join(inputs_dir(), "split-%s.h5" % name.replace(" ", "-").replace("'", ""))
        shutil.copy(source, ck)
        if dataset:
            with h5py.File(ck, "a") as f:
                del f[dataset]
        rc, stdout, err, summary = run(CHANNEL + extra + ["-t_final", "0.002", "-restart", ck], nproc=2, tag="split-bad")
        lines = [l for l in (stdout + err).splitlines() if l.startswith("fsiopt")]
        if rc == 0 or summary is not None or len(lines) != 1 or token not in lines[0] or "PETSC ERROR" in stdout + err:
            problems.append("%s: exit %s, %s" % (name, rc, lines))
    assert not problems, "; ".join(problems)
    return "probes of the restarted run against the uninterrupted one (ranks:structure ranks): %s; SIGTERM's " \
        "checkpoint %.0e; %d damaged or mismatched checkpoints refused in one line" % (", ".join(details), gap, len(cases))


@test("restart at another dt (-restart_change_dt): the probes converge at the fluid scheme's order (1, 2)")
def test_restart_change_dt():
    ck = os.path.join(WORK, "change-dt-ck")
    solve(CHANNEL + ["-t_final", "0.005", "-checkpoint_every", "50"], out=ck)
    orders = {}
    for order in (1, 2):
        ends = []
        for dt in ("5e-5", "2.5e-5", "1.25e-5"):
            out = os.path.join(WORK, "change-dt-%d-%s" % (order, dt))
            s = solve(CHANNEL + ["-t_final", "0.0055", "-dt", dt, "-restart", os.path.join(ck, "checkpoint.h5"),
                                 "-restart_change_dt", "-coupling_tol", "1e-9", "-fluid_time_order", str(order),
                                 "-structure_time_order", str(order), "-restart_change",
                                 "fluid_time_order,structure_time_order"], out=out)
            first = int(round(0.005 / float(dt))) + 1
            assert s["first_step"] == first and s["steps_done"] == int(round(0.0055 / float(dt))), "dt %s: steps %s to %s" % (
                dt, s["first_step"], s["steps_done"])
            head, rows = read_probes(os.path.join(out, "probes.csv"))
            after = [r[0] for r in rows if r[0] > 0.005 + 1e-12]
            assert len(after) == int(round(0.0005 / float(dt))) and abs(after[0] - 0.005 - float(dt)) < 1e-12 \
                and abs(after[-1] - 0.0055) < 1e-12, "dt %s: probe times after the restart %s" % (dt, after)
            ends.append(rows[-1][1:])
        d = [max(abs(a - b) for a, b in zip(ends[k], ends[k + 1])) for k in range(2)]
        orders[order] = math.log2(d[0] / d[1])
    assert 0.8 <= orders[1] <= 1.2 and orders[2] >= 1.7, "observed orders %s" % orders
    return "from a channel2d checkpoint of dt 1e-4 at t = 0.005, dt 5e-5 .. 1.25e-5 to 0.0055: observed order %.2f " \
        "(backward Euler), %.2f (BDF2)" % (orders[1], orders[2])
