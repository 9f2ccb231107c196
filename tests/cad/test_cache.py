"""The mass-properties cache: a hit is the computed result to the last bit, any change of an
input is a miss, a damaged entry is recomputed, and the cache can be moved or turned off."""

from __future__ import annotations

import json

import numpy as np
import pytest

from cadcog.cad import cache, cachestore, modelfile
from cadcog.cad.massresults import from_data, to_data
from cadcog.cad.modelfile import load_model
from cadcog.cad.stepmass import model_mass_properties
from cadcog.cad.stepread import read_step
from cadcog.core.paramfile import TableReader, read_toml
from support.stepfixtures import kicad_like_board, write_step

MATERIALS = '[materials]\n"PCB*" = 1850.0\n"*" = 3000.0\n'


@pytest.fixture
def setup_file(tmp_path):
    write_step(kicad_like_board(4), tmp_path / "board.step")
    (tmp_path / "materials.toml").write_text(MATERIALS, encoding="utf-8")
    path = tmp_path / "setup.toml"
    path.write_text(
        'model_step = "board.step"\nmaterials = "materials.toml"\noverlaps = "resolve"\n',
        encoding="utf-8",
    )
    return path


def _load(path):
    return load_model(TableReader(read_toml(path), path), path.parent)


def _bits(result) -> str:
    """Every float of the result, exactly (``repr`` round-trips a double)."""
    return json.dumps(to_data(result), default=lambda v: v.tolist())


def test_the_data_form_gives_back_the_result_to_the_last_bit(setup_file):
    model = read_step(setup_file.parent / "board.step")
    r = model_mass_properties(model, None, overlaps="resolve")
    assert r.overlaps.pairs and any(b.removed_mm3 for b in r.bodies)  # every part filled
    back = from_data(json.loads(_bits(r)))
    assert back.to_json() == r.to_json()
    assert _bits(back) == _bits(r)
    assert back.total.inertia_kg_mm2.tobytes() == r.total.inertia_kg_mm2.tobytes()
    assert back.audit == r.audit and back.overlaps == r.overlaps


def test_a_second_load_is_read_from_the_cache_and_equal(setup_file, monkeypatch):
    first = _load(setup_file)
    folder = cachestore.cache_dir()
    assert folder is not None and len(list(folder.glob("*.json"))) == 1
    monkeypatch.setattr(modelfile, "_read", lambda *a: pytest.fail("read again"))
    second = _load(setup_file)
    assert _bits(second) == _bits(first)


@pytest.mark.parametrize("change", ["materials", "step", "setup"])
def test_any_change_of_an_input_is_computed_afresh(setup_file, change):
    first = _load(setup_file)
    d = setup_file.parent
    if change == "materials":
        (d / "materials.toml").write_text(MATERIALS.replace("3000.0", "3100.0"), encoding="utf-8")
    elif change == "step":
        write_step(kicad_like_board(5), d / "board.step")
    else:
        setup_file.write_text(setup_file.read_text().replace("resolve", "allow"), "utf-8")
    again = _load(setup_file)
    assert again.total.mass_kg != first.total.mass_kg
    fresh = _load(setup_file)  # and that new result is the one kept
    assert _bits(fresh) == _bits(again)


def test_a_damaged_entry_is_recomputed(setup_file):
    first = _load(setup_file)
    folder = cachestore.cache_dir()
    assert folder is not None
    (entry,) = folder.glob("*.json")
    entry.write_text('{"format": 1, "result": {"total": [1.0]}}', encoding="utf-8")
    assert _bits(_load(setup_file)) == _bits(first)


def test_the_same_bytes_from_another_folder_are_a_hit_named_by_their_new_path(
    setup_file, monkeypatch, tmp_path
):
    """The key is the content: a copy of the model and its files elsewhere (or the same files
    by another spelling of their path) reads the entry, and the result names the new files."""
    first = _load(setup_file)
    copy = tmp_path / "copy"
    copy.mkdir()
    for name in ("board.step", "materials.toml", "setup.toml"):
        (copy / name).write_bytes((setup_file.parent / name).read_bytes())
    monkeypatch.setattr(modelfile, "_read", lambda *a: pytest.fail("read again"))
    second = _load(copy / "setup.toml")
    assert second.total.mass_kg == first.total.mass_kg
    assert str(copy / "board.step") in second.audit.source
    assert str(setup_file.parent / "board.step") not in second.audit.source
    ruled = [b.density_source for b in second.bodies if "materials rule" in b.density_source]
    assert ruled and all(str(copy / "materials.toml") in d for d in ruled), ruled[:2]


@pytest.mark.parametrize("damage", ["digit", "other entry", "fifo", "link", "hard link"])
def test_an_entry_that_is_not_this_keys_result_is_never_read(setup_file, tmp_path, damage):
    """A flipped digit, another model's entry copied over it, a pipe or a link in its place
    (a hard link included): each is ignored (the result computed afresh), never returned and
    never blocks, and a file a link names is never touched (not even its time stamp)."""
    import os

    first = _load(setup_file)
    folder = cachestore.cache_dir()
    (entry,) = folder.glob("*.json")
    text = entry.read_text(encoding="utf-8")
    mass = repr(first.total.mass_kg)
    entry.unlink()
    if damage == "digit":
        changed = mass[:-1] + ("1" if mass[-1] != "1" else "2")
        entry.write_text(text.replace(mass, changed), encoding="utf-8")
    elif damage == "other entry":
        other = json.loads(text)
        other["key"] = "0" * 64  # a valid entry of another key, renamed onto this one
        entry.write_text(json.dumps(other), encoding="utf-8")
    elif damage == "fifo":
        os.mkfifo(entry)
    else:
        target = tmp_path / "elsewhere.json"
        target.write_text(text, encoding="utf-8")
        os.utime(target, (1e9, 1e9))
        if damage == "link":
            entry.symlink_to(target)
        else:
            os.link(target, entry)
    assert _bits(_load(setup_file)) == _bits(first)
    if damage.endswith("link"):
        assert target.stat().st_mtime == 1e9 and target.read_text(encoding="utf-8") == text


def test_the_cache_follows_the_environment(setup_file, monkeypatch, tmp_path):
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(tmp_path / "elsewhere"))
    _load(setup_file)
    assert len(list((tmp_path / "elsewhere").glob("*.json"))) == 1
    monkeypatch.setenv("CADCOG_NO_CACHE", "1")
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(tmp_path / "off"))
    assert cachestore.cache_dir() is None
    _load(setup_file)
    assert not (tmp_path / "off").exists()
    monkeypatch.delenv("CADCOG_NO_CACHE")
    monkeypatch.delenv("CADCOG_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cachestore.cache_dir() == tmp_path / "xdg" / "cadcog"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/ignored")  # the spec: absolute paths only
    assert cachestore.cache_dir() == cachestore.Path.home() / ".cache" / "cadcog"


def test_an_unwritable_cache_changes_nothing(setup_file, monkeypatch, tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder", encoding="utf-8")
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(blocker / "cache"))
    r = _load(setup_file)
    assert np.isfinite(r.total.mass_kg) and blocker.read_text(encoding="utf-8") == "not a folder"


def test_the_kernel_versions_are_the_installed_metadata():
    from importlib import metadata

    def installed(dist):
        try:
            return metadata.version(dist)
        except metadata.PackageNotFoundError:
            return "absent"

    versions = cache.kernel_versions()
    dists = [d for _, ds in cache.KERNEL_PACKAGES for d in ds]
    assert {d: versions[d] for d in dists} == {d: installed(d) for d in dists}
    assert versions["build123d"] != "absent"


def test_a_kernel_installed_without_metadata_beside_it_is_fingerprinted(tmp_path, monkeypatch):
    """An editable or conda install: no dist-info beside the package. Its files identify it,
    and a rebuilt file changes the versions (so every key)."""
    import importlib.util

    package = tmp_path / "src" / "OCP"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("", encoding="utf-8")
    (package / "OCP.so").write_bytes(b"v1")
    real = importlib.util.find_spec
    spec = importlib.util.spec_from_file_location(
        "OCP", package / "__init__.py", submodule_search_locations=[str(package)]
    )
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name: spec if name == "OCP" else real(name)
    )
    before = cache.kernel_versions()
    (package / "OCP.so").write_bytes(b"v2 rebuilt")
    after = cache.kernel_versions()
    assert "OCP files" in before and before["OCP files"] != after["OCP files"]


def test_another_kernel_is_another_key(monkeypatch):
    before = cache.key({"a": 1}, [])
    monkeypatch.setattr(cache, "_code_digest", {})
    monkeypatch.setattr(cache, "kernel_versions", lambda: {"cadquery-ocp-novtk": "9.9"})
    assert cache.key({"a": 1}, []) != before


def test_trimming_deletes_the_entries_used_least_recently_and_nothing_else(tmp_path):
    import os

    names = [f"{i:064x}.json" for i in range(5)]
    for age, name in enumerate(names):  # names[0] the newest
        (tmp_path / name).write_bytes(b"x" * 100)
        os.utime(tmp_path / name, (1e9 - age, 1e9 - age))
    (tmp_path / "notes.json").write_bytes(b"y" * 1000)  # not an entry: never deleted
    (tmp_path / ".entry-abc.tmp").write_bytes(b"z")  # a killed writer's, long ago
    os.utime(tmp_path / ".entry-abc.tmp", (1e9, 1e9))
    (tmp_path / ".entry-new.tmp").write_bytes(b"z")  # another process writing now
    cachestore.trim(tmp_path, keep=names[4], max_bytes=250)
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted([names[0], names[4], "notes.json", ".entry-new.tmp"])


def test_a_hit_marks_its_entry_used_so_trimming_spares_it(monkeypatch, tmp_path):
    import os

    monkeypatch.setenv("CADCOG_CACHE_DIR", str(tmp_path))
    cachestore.store_data("a" * 64, {"v": 1})
    cachestore.store_data("b" * 64, {"v": 2})
    os.utime(tmp_path / f"{'a' * 64}.json", (1e9, 1e9))
    os.utime(tmp_path / f"{'b' * 64}.json", (1e9 + 1, 1e9 + 1))
    assert cachestore.load_data("a" * 64) == {"v": 1}  # now the most recently used
    cachestore.trim(tmp_path, max_bytes=(tmp_path / f"{'a' * 64}.json").stat().st_size)
    assert [p.name for p in tmp_path.iterdir()] == [f"{'a' * 64}.json"]


def test_clear_removes_a_linked_entry_and_never_its_target(setup_file, tmp_path):
    first = _load(setup_file)
    folder = cachestore.cache_dir()
    (entry,) = folder.glob("*.json")
    target = tmp_path / "outside.json"
    target.write_bytes(entry.read_bytes())
    before = target.stat().st_mtime_ns
    entry.unlink()
    entry.symlink_to(target)
    assert _bits(_load(setup_file)) == _bits(first)  # recomputed: the link is never read
    assert target.stat().st_mtime_ns == before  # ... nor touched
    (entry,) = folder.glob("*.json")  # the recomputed result replaced the link
    assert not entry.is_symlink()
    entry.unlink()
    entry.symlink_to(target)
    n, _ = cachestore.clear(folder)
    assert n == 1 and not entry.is_symlink() and not entry.exists() and target.is_file()
