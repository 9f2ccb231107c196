"""``cadcog massprops`` at an earlier revision and at this code, alternately, in one sitting.

On a shared machine CPU times drift by tens of per cent between sittings (docs/performance.md);
a before/after comparison is only fair when both run side by side. This checks the earlier
revision out into a temporary ``git worktree``, imports it through ``PYTHONPATH`` with this
virtual environment's libraries, and measures each model with ``bench_commands.measure``
(CPU of the process tree, wall, memory): one warm-up run per model and tree (bytecode), then
``--repeat`` rounds alternating the two trees. It also checks that both trees wrote the same
JSON. Both compute afresh (``CADCOG_NO_CACHE=1``); ``--cached`` adds a third "tree", this code
on a second run, its result read from a cache its warm-up filled (its JSON compared too).

Models: ``--instanced N`` (``satellite(N, instanced)`` with ``--materials``) and any
``--step FILE`` (``--density-kg-m3 1850 --allow-overlap``, e.g. the public KiCad board of
docs/performance.md).

Run: ``.venv/bin/python benchmarks/bench_before_after.py --before c16d270 --instanced 5000
--step board.step --repeat 5``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench_commands import environment, measure, summary
from bench_massprops import MATERIALS, satellite

from support.stepfixtures import write_step

REPO = Path(__file__).resolve().parents[1]


def _json_of(argv: list[str], env: dict[str, str]) -> str:
    return subprocess.run(argv, check=True, capture_output=True, text=True, env=env).stdout


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--before", required=True, help="git revision to compare with")
    parser.add_argument("--instanced", type=int, nargs="*", default=[], metavar="N")
    parser.add_argument("--step", type=Path, nargs="*", default=[], metavar="FILE")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--cached", action="store_true", help="also this code on a second run (result cached)"
    )
    args = parser.parse_args()
    cadcog = str(Path(sys.executable).parent / "cadcog")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        tree = d / "before"
        subprocess.run(
            ["git", "-C", str(REPO), "worktree", "add", "--detach", str(tree), args.before],
            check=True,
            capture_output=True,
        )
        try:
            mats = d / "materials.toml"
            mats.write_text(MATERIALS, encoding="utf-8")
            cases: dict[str, list[str]] = {}
            for n in args.instanced:
                step = write_step(satellite(n, True), d / f"sat{n}.step")
                cases[f"{n} instanced solids"] = [str(step), "--materials", str(mats)]
            for path in args.step:
                cases[path.name] = [str(path), "--density-kg-m3", "1850", "--allow-overlap"]
            trees = {  # first runs: no cache (a revision without one is not affected)
                f"before ({args.before})": environment(PYTHONPATH=str(tree), CADCOG_NO_CACHE="1"),
                "now": environment(CADCOG_NO_CACHE="1"),
            }
            if args.cached:  # the warm-up fills the cache: the measured runs read it
                trees["now, second run (cached)"] = environment(CADCOG_CACHE_DIR=str(d / "cache"))
            print(f"{time.strftime('%Y-%m-%d %H:%M')}; load average {os.getloadavg()[0]:.2f}")
            runs: dict[tuple[str, str], list[dict[str, float]]] = {}
            for case, options in cases.items():
                argv = [cadcog, "massprops", *options, "--json"]
                texts = {name: _json_of(argv, env) for name, env in trees.items()}  # warm-up
                same = len(set(texts.values())) == 1
                print(f"{case}: JSON {'identical' if same else 'DIFFERENT'} in every tree")
                for name in trees:
                    runs[(case, name)] = []
            for _ in range(args.repeat):
                for case, options in cases.items():
                    argv = [cadcog, "massprops", *options, "--json"]
                    for name, env in trees.items():
                        runs[(case, name)].append(measure(argv, env))
            for (case, name), results in runs.items():
                print(f"{case}, {name}: {summary(results)}")
            print(f"{time.strftime('%H:%M')}; load average {os.getloadavg()[0]:.2f}")
        finally:
            subprocess.run(
                ["git", "-C", str(REPO), "worktree", "remove", "--force", str(tree)],
                check=False,
                capture_output=True,
            )


if __name__ == "__main__":
    main()
