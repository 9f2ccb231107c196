"""``cadcog/spacecraft/setup.py``: a set-up file's candidate points are checked against its
model, and an estimate that cannot be the spacecraft's is said."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("build123d")

from cadcog.cli import main
from cadcog.rig.file import default_rig_path

SETUP = default_rig_path().parent / "cubesat_3u_setup.toml"


def test_setup_point_inside_the_model_names_the_key(tmp_path, capsys):
    text = SETUP.read_text(encoding="utf-8").replace(
        "position_mm = [30.0, 30.0, -170.25]", "position_mm = [0.0, 0.0, 0.0]"
    )
    bad = tmp_path / "setup.toml"
    bad.write_text(
        text.replace(
            'model = "cubesat_3u.toml"', f'model = "{SETUP.parent / "cubesat_3u.toml"}"'
        ).replace('rig = "paper_rig.toml"', f'rig = "{SETUP.parent / "paper_rig.toml"}"'),
        encoding="utf-8",
    )
    assert main(["plan", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "candidates.points[0].position_mm" in err and "inside the model" in err


def test_a_cog_outside_the_model_is_said_to_be_unlocated(cubesat_setup):
    """A compensated CoG more than 3 σ outside the bounding box cannot be the spacecraft's;
    outside within its noise, the test cannot place it within the object along that axis (a
    KiCad board's CoG at z = -6.4 ± 6.3 mm under a 1.5 mm board said nothing)."""
    from cadcog.spacecraft.setup import _outside_warning

    cov = np.eye(3) * 4.0  # 2 mm
    assert _outside_warning(cubesat_setup, np.array([0.0, 0.0, 10.0]), cov) == ""
    noisy = _outside_warning(cubesat_setup, np.array([55.0, 0.0, 10.0]), cov)  # 2.5 σ out
    assert "along x by 5 mm (2.5 σ): within its noise" in noisy and "did not locate" not in noisy
    text = _outside_warning(cubesat_setup, np.array([0.0, 57.0, 10.0]), cov)
    assert "outside the model's bounding box along y" in text and "did not locate it" in text
