"""Strict inputs: options nothing reads, on the command line and as YAML keys,
stop the run before its first step with one line naming them and the nearest known
option, and leave no outputs; -options_allow_unused lets them through with a warning; an
option fsiopt reads in another set-up is a warning."""
import os
from harness import test, run, out_dir, fr, WORK, NS_STEP, CHANNEL, turek

# (misspelled option or YAML key, its value, the suggestion the line must name)
TYPOS = [
    ("-coupling_tl", "1e-8", "-coupling_tol"),
    ("-fluid_densty", "1", "-fluid_density"),
    ("-fluid_viscocity", "2", "-fluid_viscosity"),
    ("-structure_youngs_modulos", "7.8", "-structure_youngs_modulus"),
    ("-structure_poison_ratio", "0.3", "-structure_poisson_ratio"),
    ("-coupling_tikonov", "1e-6", "-coupling_tikhonov"),
    ("-coupling_max_iter", "5", "-coupling_max_it"),
    ("-refin", "1", "-refine"),
    ("-ouput_dir", "x", "-output_dir"),
    ("-fluid_snes_rtl", "1e-6", "-fluid_snes_rtol"),
    ("-checkpoint_evry", "5", "-checkpoint_every"),
    ("-fluidd_snes_converged_reason", "", "-fluid_snes_converged_reason"),
]
# YAML keys, nested as a user writes them: (yaml text after the scene's lines, bad option, suggestion)
YAML_TYPOS = [
    ("fluid:\n  viscocity: 2\n", "-fluid_viscocity", "-fluid_viscosity"),
    ("structure:\n  densty: 1.9\n", "-structure_densty", "-structure_density"),
    ("coupling_tl: 1e-8\n", "-coupling_tl", "-coupling_tol"),
    ("tao_typ: lmvm\n", "-tao_typ", "-tao_type"),
]
NS_YAML = "scene: mms-ns\nt_start: 0.5\nt_final: 0.500001\ndt: 1e-6\nrefine: 2\ncoupling_control: convective\n"


def refused(args, option, suggestion):
    """The run's problems: not one line, exit 0, no suggestion, outputs left behind."""
    out = out_dir("typo")
    rc, stdout, err, summary = run(args, out=out)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    why = []
    if rc == 0:
        why.append("exit 0")
    if len(lines) != 1:
        why.append("%d lines" % len(lines))
    elif not (lines[0].startswith("fsiopt: error: option") and option in lines[0] and "nearest known: " + suggestion in lines[0]):
        why.append("line '%s' lacks %s or the suggestion %s" % (lines[0], option, suggestion))
    left = [f for f in os.listdir(out)] if os.path.isdir(out) else []
    if left:
        why.append("left %s" % ", ".join(left))
    return ("%s: %s" % (option, "; ".join(why))) if why else None


@test("misspelled options and YAML keys: one line with the nearest known option, exit 1, no outputs", quick=True)
def test_misspelled_options_refused():
    problems = []
    for option, value, suggestion in TYPOS:
        problems.append(refused(NS_STEP + [option] + ([value] if value else []), option, suggestion))
    for i, (text, option, suggestion) in enumerate(YAML_TYPOS):
        path = os.path.join(WORK, "typo-%d.yaml" % i)
        open(path, "w").write(NS_YAML + text)
        problems.append(refused(["-options_file", path], option, suggestion))
    problems = [p for p in problems if p]
    assert not problems, "; ".join(problems)
    return "%d options, %d YAML keys refused with their suggestion" % (len(TYPOS), len(YAML_TYPOS))


@test("a solver options file for a solver the scene lacks: one line naming the prefix, exit 1, no outputs", quick=True)
def test_absent_solver_refused():
    # mms-ns's fluid mesh does not move, so nothing reads options/solvers/mesh-cg-gamg.yaml
    out = out_dir("absent-solver")
    rc, stdout, err, _ = run(NS_STEP + ["-options_file", "options/solvers/mesh-cg-gamg.yaml"], out=out)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1, "exit %d, %d lines: %s" % (rc, len(lines), (stdout + err)[-300:])
    assert lines[0].startswith("fsiopt: error: options -mesh_") and "no solver with the prefix -mesh_" in lines[0] \
        and "nearest known" not in lines[0], "line: %s" % lines[0]
    left = os.listdir(out) if os.path.isdir(out) else []
    assert not left, "left %s" % left
    return lines[0]


@test("-options_allow_unused lets a misspelled option through with a warning; another set-up's option warns")
def test_allow_unused_and_other_setups():
    rc, stdout, err, summary = run(NS_STEP + ["-coupling_tl", "1e-8", "-options_allow_unused"])
    assert rc == 0 and summary is not None, "run with -options_allow_unused failed: %s" % (err or stdout)[-300:]
    warnings = [l for l in stdout.splitlines() if l.startswith("fsiopt: warning:")]
    assert len(warnings) == 1 and "-coupling_tl" in warnings[0] and "-coupling_tol" in warnings[0], "warnings %s" % warnings
    # a partitioned method's option with opt, and opt's tolerance with a partitioned method
    rc, stdout, err, summary = run(NS_STEP + ["-coupling_omega", "0.5"])
    warned = [l for l in stdout.splitlines() if l.startswith("fsiopt: warning:") and "-coupling_omega" in l]
    assert rc == 0 and summary is not None and len(warned) == 1, "-coupling_omega with opt: exit %d, %s" % (rc, warned)
    rc, stdout, err, summary = run(CHANNEL + ["-t_final", "2e-4", "-coupling", "aitken", "-coupling_tol", "1e-5"])
    warned = [l for l in stdout.splitlines() if l.startswith("fsiopt: warning:") and "-coupling_tol" in l]
    assert rc == 0 and summary is not None and len(warned) == 1, "-coupling_tol with aitken: exit %d, %s" % (rc, warned)
    # a scene's own defaults that the set-up leaves unread are no warning (mms-ns's Gauss-Newton CG tolerance
    # under the chord iteration)
    rc, stdout, err, summary = run(NS_STEP)
    assert rc == 0 and not [l for l in stdout.splitlines() if "warning" in l], "mms-ns warns: %s" % stdout
    return "allowed with one warning; -coupling_omega under opt and -coupling_tol under aitken warned; scene defaults silent"


@test("summary.json: the options in effect, the version, the units, start time and host", quick=True)
def test_summary_provenance():
    rc, stdout, err, s = run(NS_STEP + ["-fluid_density", "2"])
    assert rc == 0 and s is not None, "run failed: %s" % (err or stdout)[-300:]
    for key in ("options", "version", "units", "start_time", "host"):
        assert s.get(key), "summary.json lacks %s" % key
    assert s["options"].get("-fluid_density") == "2", "options: -fluid_density is %r" % s["options"].get("-fluid_density")
    assert s["options"].get("-scene") == "mms-ns" and s["units"] == "nondimensional", "options %s, units %s" % (s["options"].get("-scene"), s["units"])
    # after defaults: options nobody gave, with the values the objects took
    given, effect = s.get("options_given", {}), s["options"]
    for name, value in (("-fluid_snes_type", "newtonls"), ("-fluid_pc_type", "lu"), ("-coupling_max_it", None),
                        ("-structure_poisson_ratio", None), ("-fluid_viscosity", None)):
        assert name in effect and (value is None or effect[name] == value), "options[%s] = %r" % (name, effect.get(name))
    assert "-fluid_snes_type" not in given and given.get("-fluid_density") == "2", "options_given %s" % sorted(given)[:20]
    assert set(given) <= set(effect), "given but not in effect: %s" % (set(given) - set(effect))
    rc, stdout, err, t = run(turek("csm1"))
    assert rc == 0 and t["units"] == "SI" and t["options"].get("-structure_model") == "svk", "turek-hron: units %s, model %s" % (
        t and t["units"], t and t["options"].get("-structure_model"))
    return "version %s; %d options in effect, %d given (-fluid_density 2 among them); units %s, %s" % (
        s["version"], len(s["options"]), len(given), s["units"], t["units"])


# (file name, its bytes, words the line must contain): each a mistake PETSc answers with
# its banner, a stack overflow or silence
MALFORMED = [
    ("tab.yaml", b"scene: mms-ns\n\tdt: 0.1\n", ["line 2", "tab"]),
    ("list.yaml", b"- scene\n- mms-ns\n", ["line 1", "mapping", "list"]),
    ("scalar.yaml", b"mms-ns\n", ["line 1", "mapping", "single value"]),
    ("bracket.yaml", b"scene: mms-ns\nfluid: {density: [1, 2}\n", ["line 2", "not valid YAML"]),
    ("binary.yaml", b"scene: mms-ns\n\x00\x01\xff\xfe\n", ["line 2", "binary"]),
    ("twice.yaml", b"scene: mms-ns\ndt: 0.1\ndt: 0.2\n", ["line 3", "'dt' given again", "line 2"]),
    ("nested.yaml", b"scene: mms-ns\nfluid: [[1, 2], [3]]\n", ["line 2", "list inside a list"]),
    ("include.yaml", b"scene: mms-ns\noptions_file: other.yaml\n", ["line 2", "cannot include"]),
    ("empty.yaml", b"", ["empty"]),
    ("comments.yaml", b"# only a comment\n", ["no options"]),
    ("self.opts", None, ["includes itself"]),
    ("loop-a.opts", None, ["loop-b.opts", "includes it again"]),
    ("nodash.opts", b"scene mms-ns\n", ["line 1", "'scene'", "start with -"]),
    ("extra.opts", b"-scene mms-ns\n-dt 0.1 0.2\n", ["line 2", "'0.2'"]),
    ("a-directory.yaml", "dir", ["regular file"]),
    ("missing.yaml", "absent", ["cannot open"]),
]


@test("malformed options files: one line naming the file (and line), exit 1, no banner, no outputs", quick=True)
def test_malformed_options_files():
    problems = []
    base = os.path.join(WORK, "malformed")
    os.makedirs(base, exist_ok=True)
    open(os.path.join(base, "self.opts"), "w").write("-options_file %s\n" % os.path.join(base, "self.opts"))
    open(os.path.join(base, "loop-a.opts"), "w").write("-scene mms-ns\n-options_file %s\n" % os.path.join(base, "loop-b.opts"))
    open(os.path.join(base, "loop-b.opts"), "w").write("-options_file %s\n" % os.path.join(base, "loop-a.opts"))
    for name, text, words in MALFORMED:
        path = os.path.join(base, name)
        if text == "dir":
            os.makedirs(path, exist_ok=True)
        elif isinstance(text, bytes):
            open(path, "wb").write(text)
        out = out_dir("malformed")
        rc, stdout, err, summary = run(["-options_file", path], out=out)
        lines = [l for l in (stdout + err).splitlines() if l.strip()]
        why = []
        if rc == 0 or rc < 0:
            why.append("exit %d" % rc)
        if len(lines) != 1:
            why.append("%d lines: %s" % (len(lines), " | ".join(lines[:3])[:300]))
        elif not lines[0].startswith("fsiopt: error: ") or name not in lines[0] or \
                not all(w in lines[0] for w in words):
            why.append("line '%s' lacks the file name or one of %s" % (lines[0], words))
        if os.path.isdir(out) and os.listdir(out):
            why.append("left %s" % ", ".join(os.listdir(out)))
        if why:
            problems.append("%s: %s" % (name, "; ".join(why)))
    assert not problems, "; ".join(problems)
    return "%d malformed files refused with one line each" % len(MALFORMED)


def laughs():
    """mappings of ten aliases of the mapping before, nine deep: 10^9 options once expanded"""
    lines, prev = ["a: &a {%s}" % ", ".join("x%d: 1" % j for j in range(10))], "a"
    for n in "bcdefghij":
        lines.append("%s: &%s {%s}" % (n, n, ", ".join("k%d: *%s" % (j, prev) for j in range(10))))
        prev = n
    return ("\n".join(lines) + "\n").encode()


def nested(levels):
    """a key under `levels` mappings below the top: levels prefixes"""
    return "".join("  " * i + "l%d:\n" % i for i in range(levels)).encode() + b"  " * levels + b"v: 1\n"


# (file name, its bytes, words the line must contain): YAML that PETSc 3.18's reader crashes on
# (a loop), spends minutes on (aliases expanded, deep flow nesting, many anchors), answers
# with its banner (depth, list items, merge lists) or reads otherwise than YAML means
# (a merge key after the keys it would replace, a second document giving an option again)
YAML_LIMITS = [
    ("loop.yaml", b"a: &x\n  b: *x\n", ["line 2", "alias *x refers to its own anchor", "line 1", "loop"]),
    ("loop-list.yaml", b"scene: mms-ns\na: &x [{k: *x}]\n", ["line 2", "alias *x", "the list of line 2"]),
    ("loop-merge.yaml", b"a: &a {<<: *a}\n", ["line 1", "alias *a refers to its own anchor"]),
    ("laughs.yaml", laughs(), ["more than 256 options given in all", "PETSc holds 512"]),
    ("laughs-list.yaml", b"$$v: &v [%s]\n" % b", ".join([b"1"] * 1000) + b"".join(b"k%d: *v\n" % i for i in range(200)),
     ["more than 100000 keys and values once its aliases and merge keys are expanded"]),
    ("laughs-bytes.yaml", b'$$v: &v "%s"\na: [%s]\n' % (b"x" * (1 << 20), b", ".join([b"*v"] * 20)),
     ["more than 16 MiB of keys and values"]),
    ("two-documents.yaml", b"t_final: 0.001\n---\nt_final: 0.5\n", ["line 3", "option -t_final given again", "line 1"]),
    ("second-document-list.yaml", b"scene: mms-ns\n---\n- dt\n", ["line 3", "at the top", "found a list"]),
    ("merge-after.yaml", b"fluid:\n  density: 7\n  <<: {density: 3}\n",
     ["line 3", "merge key '<<' comes after key 'density'", "put '<<' first"]),
    ("merge-list.yaml", b"a: &a {x: 1}\nb: &b {x: 2}\nfluid:\n  <<: [*a, *b]\n", ["line 4", "'<<' takes one mapping", "list"]),
    ("merge-scalar.yaml", b"fluid:\n  <<: 5\n", ["line 2", "'<<' takes one mapping", "single value"]),
    ("merge-mapping.yaml", b"$$b: &b {snes: {rtol: 1}}\nfluid:\n  <<: *b\n  snes: {atol: 2}\n",
     ["line 4", "key 'snes' replaces the mapping", "line 1"]),
    ("merge-in-list.yaml", b"fluid: [{<<: {a: 1}}]\n", ["line 1", "no merge key"]),
    ("list-item-keys.yaml", b"fluid: [{a: 1, b: 2}]\n", ["line 1", "holds one key", "found 2"]),
    ("deep26.yaml", nested(26), ["line 27", "key 'l25'", "26 deep below the top", "at most 25"]),
    ("deep200.yaml", nested(200), ["line 27", "at most 25"]),
    ("flow-lists.yaml", b"a: " + b"[" * 1000000 + b"]" * 1000000 + b"\n", ["line 1", "list inside a list"]),
    ("flow-mappings.yaml", b"a: " + b"{b: " * 500000 + b"1" + b"}" * 500000 + b"\n", ["line 1", "26 deep", "at most 25"]),
    ("anchors.yaml", b"a:\n" + b"".join(b"  k%d: &a%d 1\n" % (i, i) for i in range(1001)), ["line 1002", "more than 1000 anchors"]),
    ("anchor-twice.yaml", b"a: &x 1\nb: &x 2\n", ["line 2", "duplicate anchor", "line 1"]),
    ("long-key.yaml", b"k" * 600 + b": 1\n", ["line 1", "PETSc's 511 characters"]),
    ("null-key.yaml", b"~: 1\n", ["line 1", "key '~' is not an option name"]),
    ("number-key.yaml", b"1: {a: 2}\n", ["line 1", "key '1' is not an option name"]),
    ("merged-number-key.yaml", b"$$m: &m {1: {a: 2}}\n<<: *m\n", ["line 1", "key '1' is not an option name at the top"]),
    ("complex-key.yaml", b"? [a]\n: 1\n", ["line 1", "expected a name as the key, found a list"]),
    ("include-self.yaml", b"$$i: !include include-self.yaml\n", ["line 1", "'!include' is not followed"]),
    ("include-value.yaml", b"fluid: !include other.yaml\n", ["line 1", "'!include' is not followed"]),
    ("spelled-twice.yaml", b"fluid: {density: 1}\nfluid_density: 2\n", ["line 2", "option -fluid_density given again"]),
    ("yaml2.yaml", b"%YAML 2.0\n---\ndt: 1\n", ["line 1", "incompatible YAML document"]),
    ("huge.yaml", b"# x\n" * (5 << 20), ["too large for an options file"]),
    ("a-fifo.yaml", "fifo", ["expected a regular file"]),
    ("/dev/zero", None, ["expected a regular file"]),
]


@test("YAML options files PETSc's reader would crash, stall on or misread (loops, expanded aliases, merge keys, documents, depth, keys): one line, no banner")
def test_yaml_reader_limits():
    base = os.path.join(WORK, "yaml-limits")
    os.makedirs(base, exist_ok=True)
    problems = []
    for name, text, words in YAML_LIMITS:
        path = name if name.startswith("/") else os.path.join(base, name)
        if text == "fifo":
            os.mkfifo(path)
        elif text is not None:
            open(path, "wb").write(text)
        out = out_dir("yaml-limits")
        rc, stdout, err, summary = run(CHANNEL + ["-options_file", path, "-t_final", "0.0002"], out=out, timeout=60)
        lines = [l for l in (stdout + err).splitlines() if l.strip()]
        why = []
        if rc == 0 or rc < 0 or rc > 128:
            why.append("exit %d" % rc)
        if "PETSC ERROR" in stdout + err:
            why.append("PETSc's banner")
        if len(lines) != 1:
            why.append("%d lines: %s" % (len(lines), " | ".join(lines[:3])[:300]))
        elif not lines[0].startswith("fsiopt: error: options file %s" % path) and \
                not lines[0].startswith("fsiopt: error: option -options_file %s:" % path) or \
                not all(w in lines[0] for w in words):
            why.append("line '%s' lacks the file name or one of %s" % (lines[0][:300], words))
        if summary is not None or (os.path.isdir(out) and os.listdir(out)):
            why.append("left %s" % ", ".join(os.listdir(out)))
        if why:
            problems.append("%s: %s" % (name, "; ".join(why)))
    assert not problems, "; ".join(problems)
    # what fsiopt takes, read as YAML means: 25 prefixes (PETSc's limit: the option reaches the
    # check of unread options), a merge key first with a key replacing a merged value, an anchor
    # under a $$ key (no options of its own) and a second document
    deep = os.path.join(base, "deep25.yaml")
    open(deep, "wb").write(nested(25))
    rc, stdout, err, _ = run(CHANNEL + ["-options_file", deep], timeout=60)
    option = "-" + "_".join("l%d" % i for i in range(25)) + "_v"
    assert rc == 1 and (stdout + err).strip() == "fsiopt: error: option %s: nothing reads it; " \
        "-options_allow_unused lets it through" % option, "25 prefixes: exit %d, %s" % (rc, (stdout + err)[-300:])
    merged = os.path.join(base, "merge-first.yaml")
    open(merged, "w").write("$$fluid: &f {density: 3, viscosity: 0.5}\nfluid:\n  <<: *f\n  density: 7\n---\nt_final: 0.0002\n")
    rc, stdout, err, s = run(CHANNEL + ["-options_file", merged], timeout=300)
    assert rc == 0 and s is not None, "merge key first: %s" % (stdout + err)[-300:]
    given = s["options_given"]
    assert (given.get("-fluid_density"), given.get("-fluid_viscosity"), given.get("-t_final")) == ("7", "0.5", "0.0002") \
        and not [o for o in given if "$" in o], "merged and second document's options: %s" % sorted(given.items())
    return "%d files refused with one line each; 25 prefixes, a merge key first and a second document taken" % len(YAML_LIMITS)


@test("an option given without its value (-fluid_density alone, a YAML key with nothing after it) is refused", quick=True)
def test_option_without_value():
    rc, stdout, err, _ = run(NS_STEP + ["-fluid_density"])
    line = (stdout + err).strip()
    assert rc != 0 and line == "fsiopt: error: option -fluid_density: expected a value after the name", \
        "-fluid_density alone: exit %d, %r" % (rc, line[-300:])
    path = os.path.join(WORK, "novalue.yaml")
    open(path, "w").write(NS_YAML + "fluid:\n  viscosity:\n")
    rc, stdout, err, _ = run(["-options_file", path])
    line = (stdout + err).strip()
    assert rc != 0 and "-fluid_viscosity: expected a value" in line, "YAML key without value: exit %d, %r" % (rc, line[-300:])
    # a flag needs none
    rc, stdout, err, s = run(NS_STEP + ["-fluid_extrapolate"])
    assert rc == 0 and s is not None, "a flag without value refused: %s" % (stdout + err)[-300:]
    return "-fluid_density and a bare YAML key refused; the flag -fluid_extrapolate accepted"


@test("a 100-step run prints its first line before step 1 and progress lines while it runs; -quiet prints none", quick=True)
def test_progress_lines():
    import subprocess, time
    out = out_dir("progress")
    cmd = fr.fsiopt_command(["-options_file", "options/mms-stokes.yaml", "-dt", "1e-3", "-t_final", "0.6",
                             "-progress_interval", "10"], 1, out)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=fr.ROOT,
                            env=fr.fsiopt_env())
    lines = []   # (line, whether the run was still going when it arrived)
    for line in proc.stdout:
        lines.append((line.rstrip("\n"), proc.poll() is None and not os.path.exists(os.path.join(out, "summary.json"))))
    proc.wait(timeout=300)
    err = proc.stderr.read()
    assert proc.returncode == 0, "run failed: %s" % err[-300:]
    texts = [l for l, _ in lines]
    steps = [l for l in texts if l.startswith("fsiopt: step ")]
    assert texts and texts[0].startswith("fsiopt: mms-stokes: fluid ") and "unknowns" in texts[0] and \
        "steps 1 to 100 of dt 0.001" in texts[0], "first line: %r" % texts[:1]
    assert [l.split()[2].rstrip(",") for l in steps] == ["%d/100" % k for k in range(10, 100, 10)], "progress lines %s" % steps
    for field in ("t = ", "coupling iterations ", "per step", "jump ", "wall ", "ETA "):
        assert all(field in l for l in steps), "a progress line lacks %r: %s" % (field, steps[0])
    early = [l for l, going in lines if going and l.startswith("fsiopt: step ")]
    assert len(early) >= 5, "only %d of %d progress lines arrived before the run ended (buffered?)" % (len(early), len(steps))
    rc, stdout, err, s = run(CHANNEL + ["-t_final", "0.002", "-progress_interval", "1", "-quiet"])
    assert rc == 0 and not [l for l in stdout.splitlines() if l.startswith("fsiopt: step ") or "unknowns" in l], \
        "-quiet printed: %s" % stdout[:300]
    return "first line before step 1, %d progress lines (%d while the run went); -quiet none" % (len(steps), len(early))


@test("the SLURM job stops with one line naming what is missing (srun, gmsh, Python with numpy)", quick=True)
def test_slurm_job_checks_tools():
    import subprocess
    job = os.path.join(fr.ROOT, "scripts", "slurm", "tube3d.sbatch")
    fake = os.path.join(WORK, "fake-bin")
    os.makedirs(fake, exist_ok=True)
    for tool in ("srun", "gmsh"):
        path = os.path.join(fake, tool)
        open(path, "w").write("#!/bin/sh\nexit 0\n")
        os.chmod(path, 0o755)
    found = []
    for path_dirs, python, expect, present in (
            ("/usr/bin:/bin", "/usr/bin/python3", "srun", "/usr/bin/python3"),
            (fake + ":/usr/bin:/bin", "/nonexistent/python3", "/nonexistent/python3", "srun")):
        env = {"PATH": path_dirs, "PYTHON": python, "SLURM_SUBMIT_DIR": fr.ROOT, "HOME": WORK}
        r = subprocess.run(["/bin/bash", job], env=env, cwd=WORK, capture_output=True, text=True, timeout=60)
        lines = [l for l in (r.stdout + r.stderr).splitlines() if l.strip()]
        assert r.returncode != 0 and len(lines) == 1 and lines[0].startswith("missing on ") and expect in lines[0], \
            "PATH=%s PYTHON=%s: exit %d, %s" % (path_dirs, python, r.returncode, lines)
        named = lines[0].split(":", 1)[1].split("(load")[0].split()
        assert present not in named, "names %s, which is there: %s" % (present, lines[0])
        found.append(" ".join(named))
    return "; ".join(found)
