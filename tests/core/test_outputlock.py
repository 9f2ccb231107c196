"""``cadcog/core/outputlock.py``: special files as outputs (a FIFO streamed into, a device or
``/proc/self/fd`` written through, ``-`` standard output) and one writer per output (a second
run is refused naming the holder; the lock taken once per process). Issue 21: each test
reproduces a failure of the adversarial round first."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from cadcog.cli import main
from cadcog.core.errors import CadcogError
from cadcog.core.fileio import output_lock, staged_file, staged_output_dir

HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"


def _one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# --- 1. special files as outputs ---------------------------------------------------------------


def test_a_fifo_output_is_streamed_into_not_replaced(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # so that the writer's open succeeds
    try:
        assert main(["campaign", "--out", str(fifo)]) == 0
        data = os.read(reader, 1 << 16).decode()
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)  # still a FIFO
    assert HEADER in data and data.count("\nS1,") == 10
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]


def test_a_link_to_proc_self_fd_is_written_through_and_kept(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sink = tmp_path / "captured.txt"
    with open(sink, "w", encoding="utf-8") as fh:
        fh.write("before\n")
        fh.flush()
        link = tmp_path / "junit.xml"
        link.symlink_to(f"/proc/self/fd/{fh.fileno()}")
        assert main(["campaign", "--out", str(link)]) == 0
    assert link.is_symlink()  # the link was not replaced by a file
    text = sink.read_text(encoding="utf-8")
    assert text.startswith("before\n# cadcog virtual campaign") and HEADER in text


def test_a_character_device_output_is_not_replaced(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    dev = tmp_path / "null"
    try:
        os.mknod(dev, stat.S_IFCHR | 0o666, os.makedev(1, 3))  # /dev/null's numbers
    except PermissionError:
        pytest.skip("mknod needs CAP_MKNOD (not root, or a container without it)")
    try:
        with open(dev, "wb"):
            pass
    except OSError:
        pytest.skip("device nodes are not usable on this mount (nodev)")
    assert main(["campaign", "--out", str(dev)]) == 0
    assert stat.S_ISCHR(os.stat(dev).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["null"]


def test_dash_is_standard_output_and_no_file_named_dash(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["campaign", "--out", "-"]) == 0
    got = capsys.readouterr()
    assert HEADER in got.out and got.out.splitlines()[-1].startswith("S6,")  # only the CSV
    assert got.err == "wrote 60 samples of 6 hangs to -\n"
    assert list(tmp_path.iterdir()) == []
    assert main(["report", "--out", "-"]) == 2
    assert "is a folder; standard output cannot hold it" in _one_line(capsys.readouterr().err)
    assert main(["acquire", "--simulate", "--out", "-"]) == 2
    assert "give a file name" in _one_line(capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("words", [["--out", ""], ["--out="]])
def test_an_empty_output_names_the_option(tmp_path, monkeypatch, capsys, words):
    monkeypatch.chdir(tmp_path)
    assert main(["campaign", *words]) == 2
    line = _one_line(capsys.readouterr().err)
    assert "--out: expected a value, got an empty one" in line and "directory" not in line


# --- 2. two runs on one output -----------------------------------------------------------------

_HOLDER = textwrap.dedent(
    """
    import sys
    from cadcog.core.fileio import output_lock
    with output_lock(sys.argv[1]):
        print("held", flush=True)
        sys.stdin.read()
    """
)


def _holding(path: Path) -> subprocess.Popen[str]:
    """Another process holding ``path``'s output lock (until its stdin closes)."""
    child = subprocess.Popen(
        [sys.executable, "-c", _HOLDER, str(path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout is not None and child.stdout.readline() == "held\n"
    return child


def test_a_second_run_on_one_output_is_refused_naming_the_holder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    out, rep = tmp_path / "a.csv", tmp_path / "rep"
    child = _holding(out)
    try:
        assert main(["campaign", "--out", str(out)]) == 2
        line = _one_line(capsys.readouterr().err)
        assert f"a.csv: another cadcog run (PID {child.pid}) is writing it" in line
        assert main(["acquire", "--simulate", "--out", str(out)]) == 2  # before any device
        assert f"PID {child.pid}" in _one_line(capsys.readouterr().err)
        assert not out.exists()
    finally:
        assert child.stdin is not None
        child.stdin.close()
        child.wait()
    assert main(["campaign", "--out", str(out)]) == 0  # released: the next run goes ahead
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]  # no lock file left
    child = _holding(rep)
    try:
        with pytest.raises(CadcogError, match=f"rep: another cadcog run \\(PID {child.pid}\\)"):
            with staged_output_dir(rep):
                pass
    finally:
        assert child.stdin is not None
        child.stdin.close()
        child.wait()
    assert not rep.exists()


def test_a_lock_is_taken_once_per_process(tmp_path):
    with output_lock(tmp_path / "a.csv"), staged_file(tmp_path / "a.csv") as tmp:
        tmp.write_text("x\n", encoding="utf-8")
    assert (tmp_path / "a.csv").read_text(encoding="utf-8") == "x\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]
