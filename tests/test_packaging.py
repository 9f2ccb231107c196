"""What a wheel would hold: every sub-package of the source tree, and the built-in rig files.

An editable install (the test command's) imports from the source tree, so a sub-package missing
from ``pyproject.toml`` would pass every other test and still be absent from a wheel.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _setuptools() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"][
        "setuptools"
    ]


def test_every_subpackage_is_packaged() -> None:
    listed = set(_setuptools()["packages"])
    on_disk = {
        ".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "cadcog").rglob("__init__.py")
    }
    assert on_disk - listed == set(), "add to [tool.setuptools] packages"
    assert listed - on_disk == {"cadcog._rigs"}


def test_the_rig_files_are_package_data() -> None:
    cfg = _setuptools()
    folder = ROOT / cfg["package-dir"]["cadcog._rigs"]
    patterns = cfg["package-data"]["cadcog._rigs"]
    shipped = {p.name for pattern in patterns for p in folder.glob(pattern)}
    assert {"paper_rig.toml", "cubesat_3u.toml", "cubesat_3u_setup.toml"} <= shipped


@pytest.mark.slow
def test_a_wheel_imports_and_runs(tmp_path: Path) -> None:
    """Build the wheel, install it without dependencies beside the test environment's, and run
    the command from it (not from the source tree)."""
    import shutil
    import subprocess
    import sys

    # a copy of the sources: setuptools writes build/ and *.egg-info beside them
    junk = (".venv", ".git", "build", "*.egg-info", "__pycache__", ".*_cache", ".hypothesis")
    source = tmp_path / "src"
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(*junk))
    wheel_dir = tmp_path / "wheel"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "-q",
            "--no-deps",
            "-w",
            str(wheel_dir),
            str(source),
        ],
        check=True,
        capture_output=True,
    )
    (wheel,) = wheel_dir.glob("cadcog-*.whl")
    target = tmp_path / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-deps",
            "--target",
            str(target),
            str(wheel),
        ],
        check=True,
        capture_output=True,
    )
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import cadcog, cadcog.cli;"
        "assert cadcog.__file__.startswith(sys.argv[1]), cadcog.__file__;"
        "print(cadcog.load_rig().name); sys.exit(cadcog.cli.main(['budget']))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code, str(target)], capture_output=True, text=True, cwd=tmp_path
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("paper_rig\n")
