"""What a run leaves in its -output_dir: summary.json is UTF-8 JSON whatever the bytes of the
paths in it; a run that starts replaces an earlier run's finished outputs rather than leaving
them beside its own; a refused run leaves the directory as it was; a file PETSc would write
over one of the run's own is refused before the first step."""
import json, os, re, shutil

from harness import CHANNEL, WORK, refused, run, same_file, solve, test

SHORT = CHANNEL + ["-t_final", "0.0002"]


@test("summary.json stays UTF-8 JSON when -output_dir holds bytes that are not UTF-8 or control characters: it "
      "parses, and the path's bytes appear as U+FFFD and as escapes")
def test_summary_json_any_path_bytes():
    details = []
    for tag, name in (("latin-1", b"out-\xe9t\xe9-\xff"), ("control", b"out-tab\there-bell\x07")):
        out = os.path.join(os.fsencode(WORK), name)
        r = solve(SHORT, out=os.fsdecode(out))
        assert r is not None
        with open(os.path.join(out, b"summary.json"), "rb") as f:
            raw = f.read()
        text = raw.decode("utf-8")            # raises on a byte that is not UTF-8
        summary = json.loads(text)            # raises on a raw control character
        given = summary["options_given"]["-output_dir"]
        expected = os.fsdecode(out) if tag == "control" else None
        if tag == "latin-1":
            assert given.endswith("out-\ufffdt\ufffd-\ufffd"), "-output_dir recorded as %r" % given
        else:
            assert given == expected, "-output_dir recorded as %r, expected %r" % (given, expected)
        details.append("%s: %r" % (tag, given[-22:]))
    return "; ".join(details)


@test("a run that starts in a directory holding an earlier run's outputs replaces them: the earlier run's fields "
      "are gone when the new one writes none; a restart in the same directory continues its fields; a refused run "
      "leaves the earlier outputs byte for byte")
def test_earlier_outputs_not_left_beside():
    out = os.path.join(WORK, "earlier-outputs")
    shutil.rmtree(out, ignore_errors=True)
    solve(SHORT + ["-write_fields", "1"], out=out)
    assert os.path.exists(os.path.join(out, "fields.h5")), "the first run wrote no fields"
    solve(SHORT, out=out)
    left = sorted(f for f in os.listdir(out) if not f.startswith("."))
    assert left == ["history.csv", "probes.csv", "summary.json"], "after a run without fields: %s" % left
    keep = os.path.join(WORK, "earlier-summary.json")
    shutil.copy(os.path.join(out, "summary.json"), keep)
    rc, _, err, _ = run(SHORT + ["-fluid_density", "water"], out=out)
    assert rc != 0 and "-fluid_density" in err, "the bad option was not refused: %s" % err[-200:]
    assert same_file(keep, os.path.join(out, "summary.json")), "a refused run changed the earlier summary.json"
    assert sorted(f for f in os.listdir(out) if not f.startswith(".")) == left, os.listdir(out)
    # a restart from a checkpoint in the same directory: the fields it continues are the earlier run's
    every = ["-checkpoint_every", "1", "-write_fields", "1"]
    solve(SHORT + every, out=out)
    before = times(os.path.join(out, "fields.xdmf"))
    s = solve(CHANNEL + every + ["-t_final", "0.0004", "-restart", os.path.join(out, "checkpoint.h5")], out=out)
    assert s["first_step"] == 3, "restart at step %s" % s["first_step"]
    after = times(os.path.join(out, "fields.xdmf"))
    assert after[:len(before)] == before and len(after) > len(before), \
        "fields.xdmf lists times %s before the restart, %s after" % (before, after)
    return "fields of the earlier run removed; refused run left %s as they were; restart's fields %s" % (
        ", ".join(left), ", ".join(after))


def times(xdmf):
    """the distinct times a fields.xdmf lists, in order"""
    with open(xdmf) as f:
        found = re.findall(r'<Time Value="([^"]+)"', f.read())
    return sorted(set(found), key=float)


@test("a file PETSc would write over the run's own (-log_view :DIR/summary.json, a viewer's ascii:DIR/probes.csv, "
      "the checkpoint, a path through ..) or in a directory that is not there: one line naming the option before the "
      "first step (not PETSc's banner after the last), no outputs")
def test_viewer_files_over_own_outputs():
    out = os.path.join(WORK, "viewer-clash")
    shutil.rmtree(out, ignore_errors=True)
    cases = [("log_view over summary.json", SHORT + ["-log_view", ":%s/summary.json" % out], "-log_view"),
             ("viewer over probes.csv", SHORT + ["-fluid_snes_view", "ascii:%s/probes.csv" % out],
              "-fluid_snes_view"),
             ("viewer with format over history.csv", SHORT + ["-log_view", "ascii:%s/history.csv:ascii_info_detail"
                                                                  % out], "history.csv"),
             ("log over the checkpoint", SHORT + ["-checkpoint_every", "1", "-log_view", ":%s/checkpoint.h5" % out],
              "checkpoint (-checkpoint_file)"),
             ("through ..", SHORT + ["-log_view", ":%s/../%s/fields.xdmf" % (out, os.path.basename(out))],
              "fields.xdmf"),
             ("log in a directory that is not there", SHORT + ["-log_view", ":/nonexistent-dir/log.txt"],
              "-log_view: PETSc could not write /nonexistent-dir/log.txt (No such file or directory)"),
             ("viewer in a directory that is not there", SHORT + ["-fluid_snes_view", "ascii:/nonexistent-dir/x"],
              "-fluid_snes_view")]
    detail = refused(cases, out=out)
    assert not os.path.exists(out), "refused runs left %s: %s" % (out, os.listdir(out))
    return detail
