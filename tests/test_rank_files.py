"""Files only the first rank sees (a node's local disk), on two ranks started in different
working directories (mpiexec -wdir A : -wdir B): an options file only rank 0 sees serves the
run (PETSc reads it there and hands its options on); a checkpoint to restart from, or a
checkpoint directory, rank 1 cannot see gives one fsiopt line naming rank 1 before the first
step, not only Open MPI's exit notice."""
import os, shutil, subprocess

from harness import ROOT, WORK, fr, test


def two_directories(args, tag, checkpoint=None):
    """fsiopt on rank 0 in A (a copy of the options, and of `checkpoint` as first/checkpoint.h5)
    and rank 1 in B (empty), with the same relative args: (exit status, fsiopt's lines, A)"""
    a, b = (os.path.join(WORK, "rank-files-%s-%s" % (tag, side)) for side in "ab")
    for d in (a, b):
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
    shutil.copytree(os.path.join(ROOT, "options"), os.path.join(a, "options"))
    if checkpoint:
        os.makedirs(os.path.join(a, "first"))
        shutil.copy(checkpoint, os.path.join(a, "first", "checkpoint.h5"))
    cmd = ["mpiexec", "-n", "1", "-wdir", a, fr.FSIOPT] + args + [":", "-n", "1", "-wdir", b, fr.FSIOPT] + args
    p = subprocess.run(cmd, env=fr.fsiopt_env(), capture_output=True, text=True, timeout=300)
    text = p.stdout + p.stderr
    assert "PETSC ERROR" not in text, text[-400:]
    return p.returncode, [l for l in text.splitlines() if l.startswith("fsiopt: ")], a


@test("files only rank 0 sees, on 2 ranks in different working directories: an options file serves the run; a "
      "-restart checkpoint or a checkpoint directory rank 1 cannot see: one fsiopt line naming rank 1, before the "
      "first step")
def test_files_only_rank_zero_sees():
    base = ["-options_file", "options/channel2d.yaml", "-t_final", "0.0002"]
    rc, lines, a = two_directories(base + ["-output_dir", "out"], "options")
    assert rc == 0 and os.path.exists(os.path.join(a, "out", "summary.json")), "exit %s: %s" % (rc, lines[-3:])
    details = ["options file only on rank 0: ran"]
    # a checkpoint of the same problem on 2 ranks, which rank 0 alone will see
    first = os.path.join(WORK, "rank-files-checkpoint")
    subprocess.run(fr.fsiopt_command(base + ["-checkpoint_every", "1"], 2, first), cwd=ROOT, env=fr.fsiopt_env(),
                   capture_output=True, check=True, timeout=300)
    for tag, extra, token in (("restart", ["-t_final", "0.0004", "-restart", "first/checkpoint.h5"],
                               "rank 1: option -restart first/checkpoint.h5"),
                              ("checkpoint", ["-checkpoint_every", "1"], "rank 1 cannot write in out")):
        rc, lines, a = two_directories(base + extra + ["-output_dir", "out"], tag,
                                       os.path.join(first, "checkpoint.h5"))
        errors = [l for l in lines if l.startswith("fsiopt: error:")]
        assert rc != 0 and len(errors) == 1 and token in errors[0], "%s: exit %s, lines %s" % (tag, rc, lines)
        assert not any(l.startswith("fsiopt: step") for l in lines), "%s: steps ran before the refusal" % tag
        details.append("%s: %s" % (tag, errors[0][len("fsiopt: error: "):][:90]))
    return "; ".join(details)
