"""Issue 21: report folders swapped whole, resource limits. Each test reproduces a failure of
the adversarial round first (special files as outputs and two runs on one output:
``tests/core/test_outputlock.py``)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import cadcog
from cadcog.cli import main
from cadcog.core import fileio
from cadcog.core.fileio import staged_file, staged_output_dir

HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"


def _one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# --- 3. report folders swapped whole -----------------------------------------------------------


def _old_report(tmp_path: Path) -> Path:
    rep = tmp_path / "rep"
    (rep / "sub").mkdir(parents=True)
    (rep / "index.html").write_text("old page", encoding="utf-8")
    (rep / "views.png").write_text("old views", encoding="utf-8")
    (rep / "sub" / "notes.txt").write_text("the user's", encoding="utf-8")
    return rep


def _write_new(stage: Path) -> None:
    (stage / "index.html").write_text("new page", encoding="utf-8")
    (stage / "views.png").write_text("new views", encoding="utf-8")


def _contents(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): p.read_text(encoding="utf-8")
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def test_a_signal_at_the_swap_leaves_the_old_folder_whole(tmp_path, monkeypatch):
    rep = _old_report(tmp_path)
    before = _contents(rep)

    def interrupted(a: Path, b: Path) -> bool:
        raise KeyboardInterrupt

    monkeypatch.setattr(fileio, "_exchange", interrupted)
    with pytest.raises(KeyboardInterrupt), staged_output_dir(rep) as stage:
        _write_new(stage)
    assert _contents(rep) == before  # not a new index.html beside an old views.png
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_a_report_folder_is_replaced_whole_keeping_the_users_files(tmp_path, monkeypatch, exchange):
    rep = _old_report(tmp_path)
    notes_inode = (rep / "sub" / "notes.txt").stat().st_ino
    old_inode = rep.stat().st_ino
    if not exchange:
        monkeypatch.setattr(fileio, "_exchange", lambda a, b: False)
    with staged_output_dir(rep) as stage:
        _write_new(stage)
    assert _contents(rep) == {
        "index.html": "new page",
        "views.png": "new views",
        "sub/notes.txt": "the user's",
    }
    assert rep.stat().st_ino != old_inode  # a new folder, not files moved one by one
    assert (rep / "sub" / "notes.txt").stat().st_ino == notes_inode  # linked, not copied
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


# --- 5. resource limits ------------------------------------------------------------------------

_LIMITED = textwrap.dedent(
    """
    import resource, sys
    from cadcog.cli import main
    import cadcog.cli.campaign, cadcog.validation.campaign
    if sys.argv[1] == "size":
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, resource.RLIM_INFINITY))
    else:
        status = [l for l in open("/proc/self/status") if l.startswith("VmSize")]
        vm = int(status[0].split()[1]) * 1024
        resource.setrlimit(resource.RLIMIT_AS, (vm + 40_000_000, resource.RLIM_INFINITY))
    sys.exit(main(["campaign", "--out", "out/big.csv", "--samples", sys.argv[2]]))
    """
)


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize(
    ("limit", "samples", "expected"),
    [
        (
            "size",
            "1000",
            "out/big.csv: cannot write here (File too large: the disk is full or a "
            "file-size limit (ulimit -f) was reached)",
        ),
        ("memory", "100000", "campaign: ran out of memory on "),
    ],
)
def test_resource_limits_end_in_one_line_naming_the_users_path(tmp_path, limit, samples, expected):
    run = subprocess.run(
        [sys.executable, "-c", _LIMITED, limit, samples],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 2, run.stderr
    assert expected in _one_line(run.stderr)
    # No staging or temporary path: only the user's paths and cadcog's own (the built-in rig
    # file it read), which may themselves live under /tmp (a clone there).
    shown = run.stderr.replace(str(tmp_path), "").replace(str(Path(cadcog.__file__).parents[1]), "")
    assert ".partial" not in shown and ".cadcog-" not in shown and "/tmp" not in shown
    assert list(tmp_path.iterdir()) == []  # nothing written, the folder it made removed


def test_a_memory_error_in_a_command_is_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    import cadcog.cli.campaign as campaign

    def exhausted(args: object) -> int:
        raise MemoryError

    monkeypatch.setattr(campaign, "run", exhausted)
    assert main(["campaign", "--out", "x.csv"]) == 2
    assert "campaign: ran out of memory" in _one_line(capsys.readouterr().err)


def test_after_a_signal_the_message_says_what_was_written_whole(tmp_path, capsys):
    import signal

    from cadcog.cli._main import _stopped

    fileio.reset_written()
    assert _stopped(signal.SIGTERM) == 143
    assert capsys.readouterr().err == "cadcog: terminated; nothing was written\n"
    with staged_file(tmp_path / "a.csv") as tmp:
        tmp.write_text("x\n", encoding="utf-8")
    assert _stopped(signal.SIGINT) == 130
    assert capsys.readouterr().err == (
        f"cadcog: interrupted; written whole before that: {tmp_path / 'a.csv'}\n"
    )
    fileio.reset_written()


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_a_full_standard_output_is_named_with_what_was_written(tmp_path):
    """``--json > /dev/full``: one line naming standard output (not a bare errno), and the
    files already in place."""
    csv = tmp_path / "c.csv"
    with open("/dev/full", "w") as full:
        p = subprocess.run(
            [sys.executable, "-m", "cadcog", "campaign", "--out", str(csv), "--json"],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            check=False,
        )
    assert p.returncode == 2
    (line,) = [x for x in p.stderr.splitlines() if x.startswith("cadcog: error:")]
    assert "standard output: cannot write" in line and str(csv) in line
