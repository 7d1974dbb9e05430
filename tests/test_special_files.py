"""Where a regular file is expected, a device, a FIFO or a directory: a mesh named by them is
refused before anything reads it (a device or a FIFO would be read forever), a checkpoint
before anything is renamed over it (the node of a device would be replaced)."""
import os, stat

from harness import CHANNEL, WORK, refused, test


@test("devices, FIFOs and directories where a file is expected: a mesh file /dev/zero, a copy of /dev/null, a FIFO, "
      "a directory; a checkpoint file that is a device or a FIFO: one line naming the option, the node left a node")
def test_special_files_refused():
    d = os.path.join(WORK, "special-files")
    os.makedirs(d, exist_ok=True)
    fifo = os.path.join(d, "fifo")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    nodes = [fifo]
    null = os.path.join(d, "null")
    if os.geteuid() == 0 and not os.path.exists(null):
        os.mknod(null, 0o666 | stat.S_IFCHR, os.makedev(1, 3))   # a node of our own to lose, not /dev/null
    if os.path.exists(null):
        nodes.append(null)
    short = CHANNEL + ["-t_final", "0.0002"]
    cases = [("mesh /dev/zero", short + ["-fluid_dm_plex_filename", "/dev/zero"], "expected a regular file"),
             ("mesh a FIFO", short + ["-structure_dm_plex_filename", fifo], "-structure_dm_plex_filename"),
             ("mesh a directory", short + ["-fluid_dm_plex_filename", d], "expected a regular file")]
    cases += [("checkpoint %s" % os.path.basename(n), short + ["-checkpoint_every", "1", "-checkpoint_file", n],
               "a directory, device or FIFO") for n in nodes]
    detail = refused(cases)
    for n in nodes:
        mode = os.lstat(n).st_mode
        assert stat.S_ISFIFO(mode) or stat.S_ISCHR(mode), "%s is no longer a FIFO or a device" % n
    return detail + " (%s kept)" % ", ".join(os.path.basename(n) for n in nodes)
