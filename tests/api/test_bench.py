"""``cadcog.api.bench``: setup_init and acquire are what the commands do."""

from __future__ import annotations

import argparse
import inspect
import json

import pytest

import cadcog
from cadcog import api
from tests.api.commandline import cli_json, subparser


def test_setup_init_is_what_the_command_drafts(tmp_path, capsys) -> None:
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat")
    top.add(Part("frame", [((100.0, 100.0, 5.0), (0.0, 0.0, 0.0))], 2700.0, "Aluminum 6061"))
    top.add(Part("battery", [((60.0, 60.0, 40.0), (20.0, 20.0, 20.0))]))
    step = write_step(top, tmp_path / "sat.step")
    theirs = json.loads(
        cli_json(capsys, "setup", "init", str(step), "--out", str(tmp_path / "a_setup.toml"))
    )
    draft = cadcog.setup_init(step, out=tmp_path / "b_setup.toml")
    paths = {"setup": "", "materials": ""}
    assert draft.to_dict() | paths == theirs | paths
    init = next(
        a for a in subparser("setup")._actions if isinstance(a, argparse._SubParsersAction)
    ).choices["init"]
    signature = inspect.signature(api.setup_init)
    for keyword in ("units", "force"):
        assert signature.parameters[keyword].default == init.get_default(keyword)
    assert draft.n_solids == 2 and draft.n_lacking_material == 1  # the battery's
    assert (tmp_path / "a_materials.toml").read_bytes() == (
        tmp_path / "b_materials.toml"
    ).read_bytes()
    a = (tmp_path / "a_setup.toml").read_text(encoding="utf-8").replace('"a"', '"b"')
    b = (tmp_path / "b_setup.toml").read_text(encoding="utf-8")
    assert a.replace("a_materials", "b_materials") == b


@pytest.mark.slow
def test_acquire_is_the_command_s_simulated_run(tmp_path, capsys) -> None:
    """The same summary as ``acquire --simulate --non-interactive --json`` (the simulated
    device runs in real time, its lost samples vary: the same hangs, keys and verdicts, and
    estimates that agree within their σ)."""
    import numpy as np

    setup = "parts/cubesat_3u_setup.toml"
    points = ["+x_30_90", "-x_-30_90", "+y_-30_-30", "-y_30_-30"]
    theirs = json.loads(
        cli_json(
            capsys,
            "acquire",
            "--simulate",
            "--non-interactive",
            "--setup",
            setup,
            f"--points={','.join(points)}",
            "--seed",
            "2",
            "--out",
            str(tmp_path / "a.csv"),
        )
    )
    run = cadcog.acquire(tmp_path / "b.csv", setup=setup, points=points, seed=2)
    mine = run.to_dict()
    assert sorted(mine) == sorted(theirs)
    assert [h["id"] for h in mine["hangs"]] == [h["id"] for h in theirs["hangs"]] == points
    a, b = (np.array(d["estimate"]["cog_mm"]) for d in (mine, theirs))
    sa, sb = (np.sqrt(np.diag(np.array(d["estimate"]["cov_mm2"]))) for d in (mine, theirs))
    assert np.all(np.abs(a - b) <= 5 * np.hypot(sa, sb))
    assert run.cad is not None and run.truth is not None and run.result.estimate is not None
