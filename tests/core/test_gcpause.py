"""The cycle collector paused for massprops, and always restored."""

from __future__ import annotations

import gc

import pytest

from cadcog.core.gcpause import gc_paused


def test_the_collector_is_restored_when_the_block_raises():
    assert gc.isenabled()
    with pytest.raises(RuntimeError, match="boom"), gc_paused():
        assert not gc.isenabled()
        raise RuntimeError("boom")
    assert gc.isenabled()


def test_a_collector_already_off_stays_off():
    gc.disable()
    try:
        with gc_paused():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_massprops_runs_with_the_collector_paused_and_restores_it(monkeypatch, tmp_path):
    import cadcog.cli.massprops as command

    seen = []

    def fake_run(args):
        seen.append(gc.isenabled())
        raise command.CadcogError("stop here")

    monkeypatch.setattr(command, "_run", fake_run)
    from cadcog.cli import main

    assert main(["massprops", str(tmp_path / "missing.step")]) == 2
    assert seen == [False]
    assert gc.isenabled()
