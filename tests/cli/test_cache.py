"""``cadcog cache``: the folder the environment chooses, its entries and size, and --clear,
which deletes cadcog's entries and nothing else."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cadcog.cad import cachestore
from cadcog.cli import main


def _json(capsys, argv: list[str]) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_it_counts_what_the_cache_holds_and_clears_only_entries(tmp_path, monkeypatch, capsys):
    folder = tmp_path / "c"
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(folder))
    empty = _json(capsys, ["cache", "--json"])
    assert empty["folder"] == str(folder) and empty["chosen_by"] == "CADCOG_CACHE_DIR"
    assert (empty["entries"], empty["size_bytes"], empty["enabled"]) == (0, 0, True)
    cachestore.store_data("a" * 64, {"v": list(range(100))})
    cachestore.store_data("b" * 64, {"v": 1})
    (folder / "mine.json").write_text("{}", encoding="utf-8")  # not cadcog's
    sizes = sum((folder / f"{c * 64}.json").stat().st_size for c in "ab")
    held = _json(capsys, ["cache", "--json"])
    assert (held["entries"], held["size_bytes"]) == (2, sizes)
    cleared = _json(capsys, ["cache", "--clear", "--json"])
    assert (cleared["cleared_entries"], cleared["cleared_bytes"]) == (2, sizes)
    assert (cleared["entries"], cleared["size_bytes"]) == (0, 0)
    assert sorted(p.name for p in folder.iterdir()) == ["mine.json"]


@pytest.mark.parametrize(
    ("env", "expected", "chosen_by"),
    [
        ({"XDG_CACHE_HOME": "{tmp}/xdg"}, "{tmp}/xdg/cadcog", "XDG_CACHE_HOME"),
        ({"XDG_CACHE_HOME": "relative"}, "{home}/.cache/cadcog", "default"),
        ({}, "{home}/.cache/cadcog", "default"),
    ],
)
def test_the_folder_follows_the_environment(env, expected, chosen_by, tmp_path, monkeypatch):
    monkeypatch.delenv("CADCOG_CACHE_DIR")
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    for k, v in env.items():
        monkeypatch.setenv(k, v.format(tmp=tmp_path))
    folder = expected.format(tmp=tmp_path, home=tmp_path / "home")
    # a fresh interpreter, as a user runs it (the text form)
    run = subprocess.run(
        [sys.executable, "-m", "cadcog", "cache"],
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        check=True,
    )
    how = "the default" if chosen_by == "default" else f"from {chosen_by}"
    assert run.stdout.splitlines()[0] == f"cache folder: {folder} ({how})"
    assert cachestore.where() == (Path(folder), chosen_by)


def test_turned_off_it_says_so_and_can_still_be_cleared(tmp_path, monkeypatch, capsys):
    folder = Path(os.environ["CADCOG_CACHE_DIR"])
    cachestore.store_data("c" * 64, {"v": 3})
    monkeypatch.setenv("CADCOG_NO_CACHE", "1")
    assert main(["cache", "--clear"]) == 0
    out = capsys.readouterr().out
    assert "state: off" in out and "cleared: 1 entries" in out and "entries: 0," in out
    assert not list(folder.glob("*.json"))


def test_an_entry_that_cannot_be_deleted_is_named(monkeypatch, capsys):
    cachestore.store_data("d" * 64, {"v": 4})
    real = Path.unlink

    def refused(self, missing_ok=False):
        if self.name.startswith("d"):
            raise PermissionError(13, "Permission denied")
        real(self, missing_ok)

    monkeypatch.setattr(Path, "unlink", refused)
    assert main(["cache", "--clear"]) == 2
    err = capsys.readouterr().err
    assert f"{'d' * 64}.json: cannot delete (Permission denied)" in err


def test_a_folder_that_cannot_be_listed_is_an_error_not_an_empty_cache(
    tmp_path, monkeypatch, capsys
):
    not_a_folder = tmp_path / "file"
    not_a_folder.write_text("x", encoding="utf-8")
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(not_a_folder))
    for argv in (["cache"], ["cache", "--clear"]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert f"{not_a_folder}: cannot list the cache folder (not a folder)" in err
    assert not_a_folder.read_text(encoding="utf-8") == "x"


def test_small_sizes_read_in_kilobytes(capsys):
    cachestore.store_data("e" * 64, {"v": 5})
    assert main(["cache"]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert line.startswith("entries: 1, ") and " kB (at most 1000.0 MB)" in line
