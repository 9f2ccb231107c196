"""Staged outputs: whole or nothing, normal permissions, clear errors, clean on signals."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time

import pytest

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import (
    guarding_inputs,
    note_input,
    refuse_overwriting_inputs,
    staged_file,
    staged_files,
    staged_output_dir,
)


def test_a_staged_file_gets_the_umask_permissions(tmp_path):
    old = os.umask(0o027)
    try:
        with staged_file(tmp_path / "out.csv") as tmp:
            tmp.write_text("x\n", encoding="utf-8")
    finally:
        os.umask(old)
    assert (tmp_path / "out.csv").stat().st_mode & 0o777 == 0o640


def test_a_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError), staged_file(tmp_path / "out.csv") as tmp:
        tmp.write_text("partial", encoding="utf-8")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(RuntimeError), staged_output_dir(tmp_path / "dir") as stage:
        (stage / "a.txt").write_text("partial", encoding="utf-8")
        raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_a_failed_write_removes_the_folders_it_created_and_only_those(tmp_path):
    (tmp_path / "kept").mkdir()
    with pytest.raises(RuntimeError), staged_file(tmp_path / "kept/new/deeper/out.csv"):
        raise RuntimeError("boom")
    with pytest.raises(RuntimeError), staged_output_dir(tmp_path / "kept/a/b/report"):
        raise RuntimeError("boom")
    assert [p.name for p in tmp_path.rglob("*")] == ["kept"]
    with staged_output_dir(tmp_path / "kept/a/b/report") as stage:  # success keeps them
        (stage / "x.txt").write_text("x", encoding="utf-8")
    assert (tmp_path / "kept/a/b/report/x.txt").read_text(encoding="utf-8") == "x"


def test_a_destination_that_cannot_be_replaced_is_named(tmp_path):
    out = tmp_path / "report"
    (out / "index.html").mkdir(parents=True)  # a folder where the page should go
    with pytest.raises(CadcogError, match=r"report: cannot write here"):
        with staged_output_dir(out) as stage:
            (stage / "index.html").write_text("page", encoding="utf-8")
    assert [p.name for p in tmp_path.iterdir()] == ["report"]  # the staging is gone


def test_errors_name_the_path_given_not_the_temporary_one(tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("", encoding="utf-8")
    with pytest.raises(CadcogError, match=r"file\.txt/out\.csv: cannot write here"):
        with staged_file(blocker / "out.csv"):
            pass
    with pytest.raises(CadcogError, match=r"file\.txt/report: cannot write here"):
        with staged_output_dir(blocker / "report"):
            pass
    with pytest.raises(CadcogError, match="is a directory"):
        with staged_file(tmp_path):
            pass


def test_an_output_that_is_an_input_is_refused(tmp_path):
    rig = tmp_path / "r.toml"
    with pytest.raises(CadcogError, match=r"r\.toml: is the command's input \(--rig\)"):
        refuse_overwriting_inputs(tmp_path / "." / "r.toml", {"--rig": rig, "--setup": None})


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigterm_during_report_leaves_no_staging_behind(tmp_path):
    out = tmp_path / "report"
    cmd = [sys.executable, "-m", "cadcog", "report", "--out", str(out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not any(p.name.endswith(".partial") for p in tmp_path.iterdir()):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "terminated; nothing was written" in err
    assert list(tmp_path.iterdir()) == []


class _Terminated(Exception):
    pass


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("kind", ["folder", "file"])
def test_a_signal_as_the_staging_is_made_leaves_nothing_behind(tmp_path, monkeypatch, kind):
    """The race a loaded run met (issue 30): SIGTERM delivered the instant the staging folder
    or file exists, before the code that removes it has started. The signal waits until the
    staging is named, then its handler's exception finds it and removes it."""
    real_mkdtemp, real_mkstemp = tempfile.mkdtemp, tempfile.mkstemp

    def mkdtemp_then_signal(*args, **kwargs):
        made = real_mkdtemp(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGTERM)
        return made

    def mkstemp_then_signal(*args, **kwargs):
        made = real_mkstemp(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGTERM)
        return made

    def handler(signum, frame):
        raise _Terminated

    monkeypatch.setattr(tempfile, "mkdtemp", mkdtemp_then_signal)
    monkeypatch.setattr(tempfile, "mkstemp", mkstemp_then_signal)
    previous = signal.signal(signal.SIGTERM, handler)
    try:
        with pytest.raises(_Terminated):
            staging = staged_output_dir if kind == "folder" else staged_file
            with staging(tmp_path / "out") as stage:
                pytest.fail(f"the body ran with {stage}")
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert list(tmp_path.iterdir()) == []


class _Interrupted(Exception):
    pass


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_two_held_signals_are_both_delivered():
    """SIGINT and SIGTERM both arrive while held: each handler runs when the block ends, the
    second even though the first raised (the last one's exception propagates)."""
    from cadcog.core.fileio import _signals_held

    ran: list[str] = []

    def on_int(signum, frame):
        ran.append("int")
        raise _Interrupted

    def on_term(signum, frame):
        ran.append("term")
        raise _Terminated

    previous = {signal.SIGINT: signal.signal(signal.SIGINT, on_int),
                signal.SIGTERM: signal.signal(signal.SIGTERM, on_term)}  # fmt: skip
    try:
        with pytest.raises(_Terminated) as info:
            with _signals_held():
                os.kill(os.getpid(), signal.SIGINT)
                os.kill(os.getpid(), signal.SIGTERM)
                ran.append("body")
        assert isinstance(info.value.__context__, _Interrupted)
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    assert ran == ["body", "int", "term"]


def test_outputs_never_replace_a_file_the_command_read(tmp_path):
    """Inside guarding_inputs, a file noted as read is refused as an output, whatever the name
    it is reached by (here through a folder and ``..``), and nothing of the output is moved."""
    rig = tmp_path / "out" / "rig.png"
    rig.parent.mkdir()
    rig.write_text("the rig file")
    with guarding_inputs():
        note_input(tmp_path / "out" / ".." / "out" / "rig.png", "the rig it reads")
        with pytest.raises(CadcogError, match=r"rig\.png: is the command's input \(the rig it"):
            with staged_output_dir(tmp_path / "out") as stage:
                (stage / "index.html").write_text("page")
                (stage / "rig.png").write_bytes(b"png")
        with pytest.raises(CadcogError, match=r"rig\.png: is the command's input"):
            with staged_file(rig) as tmp:
                tmp.write_text("other")
    assert rig.read_text() == "the rig file"
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["rig.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_outside_a_command_inputs_are_not_tracked(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")
    note_input(target, "ignored: no command is running")
    with staged_file(target) as tmp:
        tmp.write_text("new")
    assert target.read_text() == "new"


@pytest.mark.parametrize("planted", ["link", "hard link", "fifo", "folder"])
def test_a_lock_file_that_is_not_a_plain_file_is_refused_untouched(tmp_path, planted):
    """A link planted where the lock goes would make cadcog write its PID through it (into
    any file the link names, a hard link included); a pipe could block; a folder would let
    the run go on unlocked beside another. All are refused, the target never written."""
    from cadcog.core.fileio import output_lock

    outside = tmp_path / "outside.txt"
    outside.write_text("keep\n", encoding="utf-8")
    folder = tmp_path / "out"
    folder.mkdir()
    lock = folder / ".c.csv.cadcog-lock"
    if planted == "link":
        lock.symlink_to(outside)
    elif planted == "hard link":
        os.link(outside, lock)
    elif planted == "folder":
        lock.mkdir()
    else:
        os.mkfifo(lock)
    with pytest.raises(CadcogError, match="lock file"), output_lock(folder / "c.csv"):
        pass
    assert outside.read_text(encoding="utf-8") == "keep\n"
    assert not (folder / "c.csv").exists()


def test_several_outputs_are_written_all_or_none(tmp_path, monkeypatch):
    """staged_files: both appear on success; an error in the body leaves neither (nor any
    staging file); a failure putting the second in place takes the first away again."""
    a, b = tmp_path / "a.csv", tmp_path / "sub" / "b.csv"
    with staged_files(a, b) as (ta, tb):
        ta.write_text("A")
        tb.write_text("B")
    assert a.read_text() == "A" and b.read_text() == "B"
    c, d = tmp_path / "c.csv", tmp_path / "new" / "d.csv"
    with pytest.raises(RuntimeError), staged_files(c, d) as (tc, td):
        tc.write_text("C")
        raise RuntimeError("half way")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "sub"]
    calls = []
    real = os.replace

    def second_fails(src, dst):
        calls.append(dst)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return real(src, dst)

    monkeypatch.setattr(os, "replace", second_fails)
    with pytest.raises(CadcogError, match="cannot write here"), staged_files(c, d) as (tc, td):
        tc.write_text("C")
        td.write_text("D")
    assert len(calls) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "sub"]
