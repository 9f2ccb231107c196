"""What the catalogue of bad inputs is made of: the shipped example files as text, the edits a
case makes to them, and :class:`Case`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from cadcog.cli import main
from cadcog.rig.file import default_rig_path

PARTS = default_rig_path().parent
RIG = (PARTS / "paper_rig.toml").read_text(encoding="utf-8")
SPEC = (PARTS / "cubesat_3u.toml").read_text(encoding="utf-8")
SETUP = (
    (PARTS / "cubesat_3u_setup.toml")
    .read_text(encoding="utf-8")
    .replace('"cubesat_3u.toml"', f'"{(PARTS / "cubesat_3u.toml").as_posix()}"')
    .replace('"paper_rig.toml"', f'"{(PARTS / "paper_rig.toml").as_posix()}"')
)
REQUIREMENTS = (
    (PARTS / "cubesat_3u_requirements.toml")
    .read_text(encoding="utf-8")
    .replace('"cubesat_3u.toml"', f'"{(PARTS / "cubesat_3u.toml").as_posix()}"')
    .replace('"cubesat_3u_baseline.json"', f'"{(PARTS / "cubesat_3u_baseline.json").as_posix()}"')
)
HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_deg,inc_y_deg,top_face_up\n"
RIG_READINGS = (PARTS.parent / "docs" / "examples" / "paper_rig_readings.csv").read_text("utf-8")
GOOD_ROWS = "S1,45,20,82,-50.6,-14.2,true\nS2,-45,20,82,50.2,14.1,true\n"


def readings_with(old: str, new: str) -> str:
    """The example readings with ``old`` replaced on every line (every sample of a hang)."""
    assert old in RIG_READINGS, old
    return RIG_READINGS.replace(old, new)


def campaign_at(path: Path) -> None:
    """A virtual campaign of the paper rig at ``path`` with its swings beside it (s.csv), its
    report lines kept out of the case's standard error."""
    import contextlib
    import io

    argv = ["campaign", "--seed", "3", "--out", str(path), "--swings", str(path.parent / "s.csv")]
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 0


def _edited(text: str, old: str, new: str) -> str:
    """``text`` with its first ``old`` replaced (which must be there: an edit that no longer
    applies would test the unedited file)."""
    assert old in text, old
    return text.replace(old, new, 1)


def rig_with(old: str, new: str) -> str:
    return _edited(RIG, old, new)


def spec_with(old: str, new: str) -> str:
    return _edited(SPEC, old, new)


def setup_with(old: str, new: str) -> str:
    return _edited(SETUP, old, new)


def requirements_with(old: str, new: str) -> str:
    return _edited(REQUIREMENTS, old, new)


def box_step(path: Path) -> None:
    from support.stepfixtures import Assembly, Part, write_step

    top = Assembly("sat")
    top.add(Part("box", [((10.0, 10.0, 10.0), (0.0, 0.0, 0.0))]))
    write_step(top, path)


@dataclass(frozen=True)
class Case:
    id: str
    argv: list[str]
    message: str  # a regular expression the one-line message must match
    files: dict[str, str | bytes | Callable[[Path], None]] = field(default_factory=dict)
