"""The production SLURM job (scripts/slurm/run.sbatch) on this machine, with stand-ins for srun
(it runs the command on one rank) and scontrol (it records the requeue): a run stopped before
the queue's limit is requeued and goes on from its checkpoint to the probes of a run that
checkpointed at that step and went on."""
import os
import signal
import subprocess
import time

from harness import CHANNEL, ROOT, WORK, checkpoint_step, fr, solve, test

JOB = os.path.join(ROOT, "scripts", "slurm", "run.sbatch")


def stand_ins():
    fake = os.path.join(WORK, "slurm-bin")
    os.makedirs(fake, exist_ok=True)
    # srun -n N [--option ...] COMMAND...: the command itself, on one rank
    open(os.path.join(fake, "srun"), "w").write(
        '#!/bin/sh\nwhile [ $# -gt 0 ]; do case "$1" in -n) shift 2 ;; --*) shift ;; *) break ;; esac; done\n'
        'exec "$@"\n')
    open(os.path.join(fake, "scontrol"), "w").write('#!/bin/sh\necho "$@" >> "%s"\n' % os.path.join(fake, "scontrol.log"))
    for tool in ("srun", "scontrol"):
        os.chmod(os.path.join(fake, tool), 0o755)
    log = os.path.join(fake, "scontrol.log")
    if os.path.exists(log):
        os.remove(log)
    return fake, log


def job_env(fake, run, extra, restart_count=0):
    env = dict(fr.fsiopt_env())
    env.update({"PATH": fake + ":/usr/bin:/bin", "SLURM_SUBMIT_DIR": ROOT, "SLURM_JOB_ID": "77", "SLURM_NTASKS": "1",
                "SLURM_RESTART_COUNT": str(restart_count), "CASE": CHANNEL[1], "RUN": run, "EXTRA": extra,
                "SRUN": "srun", "HOME": WORK})
    return env


def requeues(log):
    return open(log).read().splitlines() if os.path.exists(log) else []


@test("SLURM production job: a run stopped after a step (fsiopt's SIGTERM) is requeued once (scontrol requeue "
      "JOBID) and its next start goes on from the checkpoint to the end: probes.csv byte for byte those of a run "
      "that checkpointed at that step and went on; started again, a finished run runs nothing")
def test_batch_requeue():
    fake, log = stand_ins()
    run = os.path.join(WORK, "batch-stop")
    extra = "-t_final 0.003 -interrupt_test_step 10 -interrupt_test_signal SIGTERM"
    first = subprocess.run(["/bin/bash", JOB], env=job_env(fake, run, extra), cwd=WORK, capture_output=True, text=True,
                           timeout=300)
    s = fr.read_summary(run)
    assert first.returncode == 0 and requeues(log) == ["requeue 77"] and s["steps_done"] == 10, \
        "first start: exit %d, requeues %s, summary %s, %s" % (first.returncode, requeues(log), s, first.stderr[-300:])
    second = subprocess.run(["/bin/bash", JOB], env=job_env(fake, run, extra, 1), cwd=WORK, capture_output=True,
                            text=True, timeout=300)
    s = fr.read_summary(run)
    assert second.returncode == 0 and s["converged"] and s["first_step"] == 11 and requeues(log) == ["requeue 77"], \
        "second start: exit %d, summary %s, requeues %s" % (second.returncode, s, requeues(log))
    reference = os.path.join(WORK, "batch-reference")
    solve(CHANNEL + ["-t_final", "0.003", "-interrupt_test_step", "10", "-interrupt_test_signal", "SIGUSR1"],
          out=reference)
    assert open(os.path.join(run, "probes.csv")).read() == open(os.path.join(reference, "probes.csv")).read(), \
        "the requeued run's probes differ from the run that checkpointed at step 10 and went on"
    third = subprocess.run(["/bin/bash", JOB], env=job_env(fake, run, extra, 2), cwd=WORK, capture_output=True,
                           text=True, timeout=300)
    assert third.returncode == 0 and "reached its end already" in third.stdout, third.stdout + third.stderr
    return "stopped at step 10, requeued once, the next start ran steps 11-30: probes byte for byte"


@test("SLURM production job: SLURM's SIGUSR1 to the job script mid-run stops fsiopt after its step, the job "
      "requeues, and the next start finishes the run with the probes of a run that checkpointed at that step")
def test_batch_signal():
    fake, log = stand_ins()
    run = os.path.join(WORK, "batch-signal")
    env = job_env(fake, run, "-t_final 0.1")
    job = subprocess.Popen(["/bin/bash", JOB], env=env, cwd=WORK, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
    stdout, deadline = os.path.join(run, "stdout.log"), time.time() + 120
    while time.time() < deadline and job.poll() is None:   # fsiopt's first line: the set-up is done
        if os.path.exists(stdout) and "steps 1 to 1000" in open(stdout).read():
            break
        time.sleep(0.05)
    time.sleep(1.0)
    assert job.poll() is None, "the run ended before the signal: %s" % job.communicate()[1][-300:]
    job.send_signal(signal.SIGUSR1)
    probes = os.path.join(run, "probes.csv")
    out, err = job.communicate(timeout=300)
    s = fr.read_summary(run)
    step = checkpoint_step(os.path.join(run, "checkpoint.h5"))
    assert job.returncode == 0 and requeues(log) == ["requeue 77"] and s.get("interrupted") == "SIGTERM" and \
        step == s["steps_done"] < 1000, "after the signal: exit %s, requeues %s, summary %s, checkpoint of step %s, %s" % (
            job.returncode, requeues(log), s, step, err[-300:])
    again = subprocess.run(["/bin/bash", JOB], env=job_env(fake, run, "-t_final 0.1", 1), cwd=WORK,
                           capture_output=True, text=True, timeout=300)
    s = fr.read_summary(run)
    assert again.returncode == 0 and s["converged"] and s["first_step"] == step + 1, \
        "next start: exit %d, summary %s, %s" % (again.returncode, s, again.stderr[-300:])
    reference = os.path.join(WORK, "batch-signal-reference")
    solve(CHANNEL + ["-t_final", "0.1", "-interrupt_test_step", str(step), "-interrupt_test_signal", "SIGUSR1"],
          out=reference)
    assert open(probes).read() == open(os.path.join(reference, "probes.csv")).read(), \
        "the requeued run's probes differ from the run that checkpointed at step %d and went on" % step
    return "signalled at step %d of 1000, requeued, finished: probes byte for byte" % step
