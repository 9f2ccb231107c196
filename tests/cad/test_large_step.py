"""A large STEP file says what is being read from the first second (issue 21: a 336 MB file
printed nothing for 300 s)."""

from __future__ import annotations

from cadcog.cad import stepread
from cadcog.cli.massprops import LOG_PROGRESS_MIN_STEPS, _log_progress
from cadcog.core.heartbeat import heartbeat
from support.stepfixtures import Assembly, Part, write_step


def test_a_large_file_announces_each_phase_before_occt_starts(tmp_path, monkeypatch, capfd):
    top = Assembly("sat")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    path = write_step(top, tmp_path / "m.step")
    capfd.readouterr()
    stepread.read_step(path)
    assert "cadcog:" not in capfd.readouterr().err  # a small file reads silently
    monkeypatch.setattr(stepread, "STEP_HEARTBEAT_MIN_MB", 0.0)
    model = stepread.read_step(path)
    err = capfd.readouterr().err.splitlines()
    assert err[:2] == [
        f"cadcog: reading {path} (0 MB) ...",
        f"cadcog: building the shapes of {path} ...",
    ]
    assert len(model.bodies) == 1


def test_the_heartbeat_helper_is_gone_when_the_call_ends(monkeypatch, capfd):
    import subprocess

    started: list[subprocess.Popen[bytes]] = []
    real = subprocess.Popen

    def recorded(*args: object, **kwargs: object) -> subprocess.Popen[bytes]:
        child = real(*args, **kwargs)  # type: ignore[call-overload]
        started.append(child)
        return child

    monkeypatch.setattr(subprocess, "Popen", recorded)
    with heartbeat("reading big.step (336 MB)"):
        assert started and started[0].poll() is None  # beating while inside
    assert started[0].poll() is not None  # and ended with the call
    assert capfd.readouterr().err == "cadcog: reading big.step (336 MB) ...\n"


def test_a_log_shows_large_phases_at_once_and_small_ones_not_at_all(capsys):
    _log_progress("integrating bodies", 3)(3)
    assert capsys.readouterr().err == ""
    n = LOG_PROGRESS_MIN_STEPS
    tick = _log_progress("integrating bodies", n)
    assert capsys.readouterr().err == f"cadcog: integrating bodies: 0/{n}\n"
    tick(n)
    assert capsys.readouterr().err == f"cadcog: integrating bodies: {n}/{n}\n"
