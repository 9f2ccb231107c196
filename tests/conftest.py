"""Shared fixtures. CAD fixtures build once per session: build123d is slow to import.

Also the order in which pytest-xdist hands the test files to its workers (``-n 2 --dist
loadfile`` in pyproject's addopts; :func:`pytest_xdist_make_scheduler`).
"""

from __future__ import annotations

import os
import sys

# The suite's BLAS runs on one thread, as the console command's does (cadcog.cli.console_main):
# its matrices are small and pytest-xdist already runs a worker per core, so BLAS pools would only
# oversubscribe the CPUs (a loaded run once spent minutes so). Set before numpy is first imported
# (which is here, in every worker; tests/test_imports.py fails if a plugin ever imports it first).
from cadcog.cli import BLAS_THREAD_VARIABLES

for _name in BLAS_THREAD_VARIABLES:
    os.environ.setdefault(_name, "1")
NUMPY_WAS_IMPORTED_FIRST = "numpy" in sys.modules

from pathlib import Path  # noqa: E402

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

from cadcog.rig.file import default_rig_path, load_rig  # noqa: E402
from cadcog.rig.parameters import Rig  # noqa: E402

# The README's test command runs the same examples on every run and every machine, in CI or
# not (a red run is then a real regression, never a lucky draw; the examples are those of the
# hypothesis release pinned in pyproject.toml). New examples are drawn on request:
# ``pytest --hypothesis-profile=explore`` (10x the examples, fresh each run); a failure it finds
# becomes an ``@example`` of the test before it is fixed. No deadline: this 2-core machine is
# shared and its timing noisy.
settings.register_profile("repeatable", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("explore", deadline=None, max_examples=1000, print_blob=True)
settings.load_profile("repeatable")

GOLDEN_DIR = Path(__file__).parent / "golden"

#: The longest test files (CPU seconds of a fresh run on an idle 2-core machine, November 2026),
#: longest first. ``--dist loadfile`` keeps a file on one worker, so its module-scoped fixtures
#: are computed once, not once per worker; by default it hands out the files with the most
#: tests first, so a long file of few tests (the inertia validation: 2 tests, ~22 s) could start
#: last and run alone. These start first instead (longest-processing-time-first); the other
#: files follow in xdist's order. A stale list only costs balance: it selects nothing.
LONG_FILES_FIRST = (
    "tests/cli/test_acquire_log_cli.py",  # ~45 s: 18 phone logs of the independent model
    "tests/test_static.py",  # ~32 s: mypy (no cache in a fresh clone)
    "tests/inertia/test_inertia_validation.py",  # ~22 s: 4 simulated campaigns
    "tests/spacecraft/test_calibration.py",  # ~25 s: 480 simulated campaigns
    "tests/spacecraft/test_update.py",  # ~20 s: two coverage tests
    "tests/validation/test_shared_errors.py",  # ~25 s: 280 independent campaigns
    "tests/validation/test_verification.py",  # ~14 s
    "tests/uncertainty/test_accel_budget.py",  # ~15 s: the accelerometer's plans
    "tests/uncertainty/test_calibration.py",  # ~11 s
    "tests/method/test_plumblines.py",  # ~11 s: hypothesis
    "tests/validation/test_size_adc.py",  # ~9 s
    "tests/test_packaging.py",  # ~7 s: builds and installs a wheel
    "tests/core/test_fuzz_parsers.py",  # ~7 s: hypothesis
    "tests/bench/test_session.py",  # ~6 s
    "tests/core/test_fileio.py",  # ~5 s, mostly a `cadcog report` subprocess
    "tests/cli/test_inertia.py",  # ~5 s
    "tests/test_docs_site.py",  # ~5 s: mkdocs build
)


@pytest.hookimpl(tryfirst=True, optionalhook=True)  # optional: a hook of pytest-xdist
def pytest_xdist_make_scheduler(config: pytest.Config, log: object) -> object:
    """``--dist loadfile`` with :data:`LONG_FILES_FIRST` handed out first (only the order of
    the files changes: which tests run, and with which fixtures, does not)."""
    if config.getvalue("dist") != "loadfile":
        return None
    try:
        from xdist.scheduler import LoadFileScheduling
    except ImportError:  # pragma: no cover - a future xdist: its own order
        return None

    rank = {path: i for i, path in enumerate(LONG_FILES_FIRST)}

    class LongFilesFirst(LoadFileScheduling):  # type: ignore[misc]
        _ordered = False

        def _assign_work_unit(self, node: object) -> None:
            if not self._ordered:  # the queue is complete at the first assignment
                order = sorted(self.workqueue, key=lambda f: rank.get(f, len(rank)))
                self.workqueue = type(self.workqueue)((f, self.workqueue[f]) for f in order)
                self._ordered = True
            super()._assign_work_unit(node)

    return LongFilesFirst(config, log)


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--update-golden",
        action="store_true",
        help="rewrite the golden files from the current code instead of comparing",
    )


@pytest.fixture(autouse=True)
def _own_cache_dir(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    """Each test's mass-properties cache (cadcog.cad.cache) is a fresh temporary folder: never
    the user's ~/.cache, and no test sees another's entries."""
    monkeypatch.setenv("CADCOG_CACHE_DIR", str(tmp_path_factory.mktemp("cadcog-cache")))
    monkeypatch.delenv("CADCOG_NO_CACHE", raising=False)


@pytest.fixture(scope="session")
def paper_rig() -> Rig:
    return load_rig(default_rig_path())


@pytest.fixture(scope="session")
def paper_rig_text() -> str:
    return default_rig_path().read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def cubesat_setup():
    """The example 3U CubeSat set-up (builds its CAD with build123d: once per session)."""
    pytest.importorskip("build123d")
    from cadcog.spacecraft.setup import load_setup

    return load_setup(default_rig_path().parent / "cubesat_3u_setup.toml")
