"""Checkpoint integrity: a checkpoint whose values changed on disk after they were written (one
bit flipped in a dataset or an attribute) is refused at the restart in one line naming the
dataset or attribute; step attributes that disagree are refused naming them; a checkpoint
without checksums is read with a warning. And one writer per checkpoint file: a second run
on a -checkpoint_file in use is refused before its first step, a dead run's lock taken over.
Restarts that continue a run exactly: test_restarts.py."""
import hashlib, os, shutil, signal, socket, subprocess, time

from harness import (CHANNEL, ROOT, WORK, checkpoint_checksum, checkpoint_checksums, checkpoint_step, fr, inputs_dir,
                     out_dir, run, same_file, set_checkpoint_attribute, solve, test, write_checkpoint_checksums)

_source = {}


def source_checkpoint(nproc=1, extra=()):
    """A channel2d checkpoint of step 10 (cached per layout); copies are damaged."""
    key = (nproc,) + tuple(extra)
    if key not in _source:
        out = os.path.join(inputs_dir(), "integrity-source-%d%s" % (nproc, "-".join(extra)))
        solve(CHANNEL + list(extra) + ["-t_final", "0.001", "-checkpoint_every", "10"], nproc=nproc, out=out)
        _source[key] = os.path.join(out, "checkpoint.h5")
    return _source[key]


def damaged_copy(tag, nproc=1, extra=()):
    path = os.path.join(inputs_dir(), "integrity-%s.h5" % tag)
    shutil.copy(source_checkpoint(nproc, extra), path)
    return path


def flip_dataset_bit(path, dataset, index, bit=0):
    """Flips one bit of value `index` of a dataset in the file's bytes, as a disk would, where
    h5py says the value is stored; returns (before, after)."""
    import h5py
    with h5py.File(path, "r") as f:
        d = f[dataset]
        assert d.dtype == "<f8" and d.compression is None and 0 <= index < d.shape[0], "%s: %s" % (dataset, d)
        before = float(d[index])
        if d.chunks is None:
            offset = d.id.get_offset() + 8 * index
        else:
            info = d.id.get_chunk_info_by_coord((index // d.chunks[0] * d.chunks[0],))
            offset = info.byte_offset + 8 * (index % d.chunks[0])
    with open(path, "r+b") as f:
        f.seek(offset + bit // 8)
        byte = f.read(1)[0]
        f.seek(offset + bit // 8)
        f.write(bytes([byte ^ (1 << (bit % 8))]))
    with h5py.File(path, "r") as f:
        after = float(f[dataset][index])
    assert after != before and after == after, "%s[%d]: %r, then %r" % (dataset, index, before, after)
    return before, after


def flip_attribute_bit(path, group, name, bit=0):
    """Flips one bit of an integer or float attribute, its type kept (through HDF5: where a
    small attribute sits in the file is HDF5's own business); returns (before, after)."""
    import h5py, numpy as np
    with h5py.File(path, "r+") as f:
        a = np.array(f[group].attrs[name])
        wide = a.astype(a.dtype.newbyteorder("<")).view("<u%d" % a.dtype.itemsize)
        flipped = (wide ^ np.array(1 << bit, dtype=wide.dtype)).view(a.dtype.newbyteorder("<"))
        f[group].attrs.modify(name, flipped.astype(a.dtype))
        after = f[group].attrs[name]
    assert after != a, "%s/%s unchanged" % (group, name)
    return a.item(), np.array(after).item()


def digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def refused_restart(checkpoint, token, nproc=1, extra=(), t_final="0.002"):
    """A restart from `checkpoint`: refused with one line containing token, exit != 0, no
    PETSc or MPI_ABORT banner, nothing left of the run (its directory, made for it, is gone with its
    locks) and the checkpoint untouched. Returns the line."""
    out = out_dir("integrity-refused")
    before = digest(checkpoint)
    rc, stdout, err, summary = run(CHANNEL + list(extra) + ["-t_final", t_final, "-restart", checkpoint], nproc=nproc,
                                   out=out)
    # on several ranks the launcher adds its own note of the exit status: fsiopt's lines count
    lines = [l for l in (stdout + err).splitlines() if l.strip() and (nproc == 1 or l.startswith("fsiopt"))]
    problems = []
    if rc == 0: problems.append("exit 0")
    if "PETSC ERROR" in stdout + err or "MPI_ABORT" in stdout + err: problems.append("PETSc or MPI banner")
    if len(lines) != 1 or not lines[0].startswith("fsiopt: error: ") or token not in lines[0]:
        problems.append("lines %s, expected one 'fsiopt: error:' line with '%s'" % (lines[:4], token))
    if os.path.exists(out): problems.append("left %s: %s" % (out, os.listdir(out)))
    if summary is not None: problems.append("summary.json written")
    if digest(checkpoint) != before: problems.append("the checkpoint changed")
    if os.path.exists(checkpoint + ".lock"): problems.append("a lock beside the checkpoint")
    assert not problems, "; ".join(problems)
    return lines[0]


def short(line):
    """The line without the test's directory, for the report."""
    return line.replace(inputs_dir() + "/", "")


@test("checkpoint integrity: one bit flipped in the fluid state refused in one line naming /fluid/state")
def test_checksum_fluid_state():
    ck = damaged_copy("fluid-state")
    before, after = flip_dataset_bit(ck, "fluid/state", 100, bit=0)   # the last bit of the mantissa
    line = refused_restart(ck, "dataset /fluid/state does not match its checksum")
    return "%r became %r: %s" % (before, after, short(line))


@test("checkpoint integrity: one bit flipped in the probe series refused in one line naming /probes/series")
def test_checksum_probes():
    ck = damaged_copy("probes")
    before, after = flip_dataset_bit(ck, "probes/series", 9, bit=20)
    line = refused_restart(ck, "dataset /probes/series does not match its checksum")
    return "%r became %r: %s" % (before, after, short(line))


@test("checkpoint integrity: one bit flipped in the structure's velocity refused in one line naming "
      "/structure/velocity, also on fluid | structure ranks (2 ranks, -structure_ranks 1)")
def test_checksum_structure_velocity():
    ck = damaged_copy("structure-velocity")
    flip_dataset_bit(ck, "structure/velocity", 50, bit=1)
    line = refused_restart(ck, "dataset /structure/velocity does not match its checksum")
    split = ["-structure_ranks", "1"]
    ck2 = damaged_copy("structure-velocity-split", nproc=2, extra=split)
    flip_dataset_bit(ck2, "structure/velocity", 50, bit=1)
    line2 = refused_restart(ck2, "dataset /structure/velocity does not match its checksum", nproc=2, extra=split)
    assert "error: rank" not in line2, "the split run's line is one rank's: %s" % line2
    return "%s; 2 ranks split: one line too" % short(line)


@test("checkpoint integrity: one bit flipped in the step (/run step 10 -> 11) refused in one line naming it")
def test_checksum_step():
    ck = damaged_copy("step")
    before, after = flip_attribute_bit(ck, "run", "step", bit=0)
    assert (before, after) == (10, 11), "step %s became %s" % (before, after)
    line = refused_restart(ck, "attribute 'step' in /run does not match its checksum")
    return short(line)


@test("checkpoint integrity: one bit flipped in a time (/fluid time, /run dt) refused in one line naming it")
def test_checksum_time():
    lines = []
    for group, name in (("fluid", "time"), ("run", "dt")):
        ck = damaged_copy("real-%s-%s" % (group, name))
        before, after = flip_attribute_bit(ck, group, name, bit=3)
        assert abs(after - before) < 1e-12 * abs(before), "%s/%s %r became %r" % (group, name, before, after)
        lines.append(refused_restart(ck, "attribute '%s' in /%s does not match its checksum" % (name, group)))
    return "%s; %s" % tuple(short(l) for l in lines)


@test("checkpoint integrity: step attributes that disagree, each with a matching checksum, refused in one line "
      "naming them (/run step against /fluid step; /run step, dt, t_start against /structure time)")
def test_inconsistent_step_attributes():
    import h5py
    lines = []
    ck = damaged_copy("inconsistent-step")
    with h5py.File(ck, "r+") as f:
        set_checkpoint_attribute(f, "run", "step", 9)
    lines.append(refused_restart(ck, "its attributes disagree: step 9 in /run, 10 in /fluid"))
    ck = damaged_copy("inconsistent-time")
    with h5py.File(ck, "r+") as f:
        set_checkpoint_attribute(f, "structure", "time", 0.0011)
    lines.append(refused_restart(ck, "time in /structure is 0.0011"))
    return "; ".join(short(l) for l in lines)


@test("checkpoint integrity: a checkpoint without checksums (an older fsiopt's) restarts with one warning line, "
      "exactly as with them; a table of checksums renamed, or lacking an item, is refused in one line")
def test_checkpoint_without_checksums():
    import h5py
    ck = damaged_copy("no-checksums")
    with h5py.File(ck, "r+") as f:
        removed = len(checkpoint_checksums(f)[1])
        for name in list(f.attrs):
            del f.attrs[name]
    plain, old = out_dir("integrity-plain"), out_dir("integrity-old")
    solve(CHANNEL + ["-t_final", "0.002", "-restart", source_checkpoint()], out=plain)
    rc, stdout, err, s = run(CHANNEL + ["-t_final", "0.002", "-restart", ck], out=old)
    warnings = [l for l in (stdout + err).splitlines() if "warning" in l]
    assert rc == 0 and s and s["first_step"] == 11 and len(warnings) == 1 and "has no checksums" in warnings[0], \
        "exit %s, warnings %s, %s" % (rc, warnings, err[-300:])
    assert same_file(os.path.join(plain, "probes.csv"), os.path.join(old, "probes.csv")), \
        "the restart without checksums differs from the one with them"
    lines = []
    ck = damaged_copy("renamed-table")
    with h5py.File(ck, "r+") as f:   # one bit of the attribute's name: "checksums" -> "checksuls"
        f.attrs.create("checksuls", f.attrs["checksums"])
        del f.attrs["checksums"]
    lines.append(refused_restart(ck, "the file's root has attributes but not its table of checksums"))
    ck = damaged_copy("table-without-an-item")
    with h5py.File(ck, "r+") as f:
        kind, table = checkpoint_checksums(f)
        del table["dataset /structure/load_old"]
        write_checkpoint_checksums(f, kind, table)
    lines.append(refused_restart(ck, "dataset /structure/load_old has no checksum in the file's table"))
    return "%d checksums removed: restarted as with them, warned: %s; %s" % (
        removed, short(warnings[0]), "; ".join(short(l) for l in lines))


def while_held(args, out, held, then):
    """Starts fsiopt (args, -output_dir out), stops it (SIGSTOP) once it holds the file
    `held`, so that it holds it however slow the machine, calls then(), lets it go on and
    waits for it. Returns (its Popen, then()'s result, its stderr)."""
    first = subprocess.Popen(fr.fsiopt_command(args, out_dir=out), cwd=ROOT, env=fr.fsiopt_env(),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(400):
            if os.path.exists(held):
                break
            time.sleep(0.02)
        first.send_signal(signal.SIGSTOP)
        result = then()
    finally:
        first.send_signal(signal.SIGCONT)
    _, err = first.communicate(timeout=300)
    return first, result, err


@test("checkpoint lock: a second run on a -checkpoint_file in use is refused before its first step in one line "
      "naming -checkpoint_file and the run (another -output_dir; the file in the first's -output_dir; the first's "
      "file in the second's -output_dir); the first's checkpoint is intact and restarts")
def test_checkpoint_file_lock():
    d = os.path.join(WORK, "ck-lock")
    os.makedirs(os.path.join(d, "owned-by-second"), exist_ok=True)
    short = CHANNEL + ["-t_final", "0.003", "-checkpoint_every", "10"]
    shared = os.path.join(d, "shared.h5")
    owned_first = os.path.join(d, "first-2", "checkpoint.h5")
    owned_second = os.path.join(d, "owned-by-second", "checkpoint.h5")
    cases = (  # the first run's options and output directory, the file it holds; the second's; its line
        (["-checkpoint_file", shared], "first-1", shared + ".lock", ["-checkpoint_file", shared], "second-1",
         "in use by run"),
        ([], "first-2", os.path.join(d, "first-2", ".fsiopt.lock"), ["-checkpoint_file", owned_first], "second-2",
         "in the output directory of run"),
        (["-checkpoint_file", owned_second], "first-3", owned_second + ".lock", [], "owned-by-second",
         "in use by run"))
    lines = []
    for first_args, first_out, held, second_args, second_out, relation in cases:
        first_out, second_out = os.path.join(d, first_out), os.path.join(d, second_out)
        existed = os.path.exists(second_out)
        def second():   # and what is in its directory before the first goes on
            result = run(short + second_args, out=second_out)
            return result, sorted(os.listdir(second_out)) if os.path.exists(second_out) else None
        first, ((rc, stdout, err, summary), left), first_err = while_held(short + first_args, first_out, held, second)
        ck = dict(zip(first_args[::2], first_args[1::2])).get("-checkpoint_file",
                                                              os.path.join(first_out, "checkpoint.h5"))
        said = [l for l in (stdout + err).splitlines() if l.strip()]
        assert rc != 0 and len(said) == 1 and said[0].startswith(
            "fsiopt: error: option -checkpoint_file %s: %s %d on " % (ck, relation, first.pid)) and \
            "PETSC ERROR" not in stdout + err, "second run (%s): exit %s, %s" % (relation, rc, said)
        assert summary is None and left == ([os.path.basename(held)] if held.startswith(second_out) else
                                            [] if existed else None), "the refused run left %s" % left
        assert first.returncode == 0, "the first run failed: %s" % first_err[-300:]
        assert not os.path.exists(ck + ".lock") and not os.path.exists(os.path.join(first_out, ".fsiopt.lock")), \
            "a lock stayed"
        assert checkpoint_step(ck) == 30, "the first run's checkpoint is of step %d, not 30" % checkpoint_step(ck)
        lines.append(said[0].replace(d + "/", ""))
    s = solve(CHANNEL + ["-t_final", "0.004", "-restart", shared], out=out_dir("ck-lock-restart"))
    assert s["first_step"] == 31 and s["steps_done"] == 40, "restart at step %s" % s["first_step"]
    return "; ".join(lines)


@test("checkpoint lock: a dead run's lock of the -checkpoint_file is taken over with one notice (also beside the "
      "default checkpoint in the run's own -output_dir), another host's is refused in one line and kept")
def test_checkpoint_file_stale_lock():
    d = os.path.join(WORK, "ck-stale")
    os.makedirs(d, exist_ok=True)
    ck, lock = os.path.join(d, "ck.h5"), os.path.join(d, "ck.h5.lock")
    dead = subprocess.Popen(["true"])
    dead.wait()
    with open(lock, "w") as f:
        f.write("%d %s 2026-01-01T00:00:00\n" % (dead.pid, socket.gethostname()))
    args = CHANNEL + ["-t_final", "0.001", "-checkpoint_every", "10", "-checkpoint_file", ck]
    rc, stdout, err, s = run(args, out=os.path.join(d, "out"))
    notice = [l for l in err.splitlines() if "taking over" in l]
    assert rc == 0 and s and s["steps_done"] == 10 and len(notice) == 1 and \
        notice[0] == "fsiopt: checkpoint file %s: taking over the lock of run %d (started 2026-01-01T00:00:00), " \
        "which no longer runs" % (ck, dead.pid), "stale lock: exit %s, stderr %s" % (rc, err[-300:])
    assert not os.path.exists(lock) and checkpoint_step(ck) == 10, "lock left %s, checkpoint %s" % (
        os.path.exists(lock), os.path.exists(ck))
    # the default checkpoint, in the run's own directory: its directory's lock covers it, and a
    # dead run's lock beside it is removed with the same notice
    own = os.path.join(d, "own")
    os.makedirs(own, exist_ok=True)
    with open(os.path.join(own, "checkpoint.h5.lock"), "w") as f:
        f.write("%d %s 2026-01-01T00:00:00\n" % (dead.pid, socket.gethostname()))
    rc, stdout, err, s = run(CHANNEL + ["-t_final", "0.001", "-checkpoint_every", "10"], out=own)
    notice_own = [l for l in err.splitlines() if "taking over" in l]
    assert rc == 0 and s and notice_own == [notice[0].replace(ck, os.path.join(own, "checkpoint.h5"))] and \
        sorted(f for f in os.listdir(own) if "lock" in f) == [], "own directory: exit %s, %s, left %s" % (
            rc, notice_own, os.listdir(own))
    with open(lock, "w") as f:
        f.write("1 some-other-host 2026-01-01T00:00:00\n")
    other = os.path.join(d, "other")
    rc, stdout, err, _ = run(args, out=other)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and lines[0].startswith("fsiopt: error: option -checkpoint_file %s: in use by "
                                                               "run 1 on some-other-host" % ck) \
        and os.path.exists(lock) and not os.path.exists(other), "other host's lock: exit %s, %s" % (rc, lines)
    return "%s; %s" % (notice[0].replace(d + "/", ""), lines[0].replace(d + "/", ""))


@test("checkpoint integrity: the checksums are what fsiopt's documentation says (tests/harness.py recomputes every "
      "one of a 2-rank split checkpoint from the values), one for every dataset and attribute")
def test_checksums_documented():
    import h5py
    with h5py.File(source_checkpoint(2, ("-structure_ranks", "1")), "r") as f:
        kind, table = checkpoint_checksums(f)
        # the parts of the split ranks: each its own table, written by its ranks
        parts = len(f.attrs) - 1
        in_parts = len(table) - (len(f.attrs["checksums"].decode().splitlines()) - 1)
        assert kind == "fsiopt-mix64-1" and parts >= 2 and sorted(f.attrs) == sorted(
            ["checksums"] + ["checksums %d" % k for k in range(1, parts + 1)]), \
            "kind %s, the root's attributes %s" % (kind, list(f.attrs))
        items = set()
        for g in f.values():
            items.update("dataset %s" % d.name for d in g.values())
            items.update("attribute '%s' in %s" % (a, g.name) for a in g.attrs)
        assert items == set(table), "without a checksum: %s; in the table only: %s" % (
            sorted(items - set(table)), sorted(set(table) - items))
        for item, stored in table.items():
            if item.startswith("dataset "):
                value = f[item.split(" ", 1)[1]][()]
            else:
                name, group = item[len("attribute '"):].split("' in ")
                value = f[group].attrs[name]
            got = checkpoint_checksum(value)
            assert got == stored, "%s: %s, stored %s" % (item, got, stored)
    assert len(table) >= 30, "%d checksums" % len(table)
    return "%d checksums recomputed, %d of them in the tables of %d parts" % (
        len(table), in_parts, parts)
