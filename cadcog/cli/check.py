"""``cadcog check``: a spacecraft's mass-properties requirements, for people and for CI."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from cadcog.cli._options import add_json
from cadcog.cli._output import print_json, wrote
from cadcog.core.fileio import refuse_overwriting_inputs, staged_file
from cadcog.core.paramfile import TableReader, read_toml

#: Exit status when a requirement does not hold (bad input is 2, as everywhere).
EXIT_FAILED = 1


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "check",
        help="check a model's mass, CoG envelope, inertia and baseline against requirements",
        description="Evaluate a requirements file (TOML: the model, [mass], [cog], [inertia], "
        "[baseline]) and print one line per requirement. Exit 0 when all hold, 1 when one "
        "fails, 2 on bad input. See docs/ci.md.",
    )
    p.add_argument("requirements", type=Path, help="requirements file (TOML)")
    add_json(p)
    p.add_argument("--junit", type=Path, metavar="FILE", help="also write JUnit XML for CI")
    p.add_argument(
        "--strict",
        action="store_true",
        help="a note about the model (surfaces left out, overlaps counted, units) is an error",
    )
    p.add_argument(
        "--update-baseline",
        action="store_true",
        help="write the model's current mass properties to the [baseline] file, then check",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from cadcog.spacecraft.requirements import check_requirements, load_requirements

    started = time.perf_counter()
    path = args.requirements
    if args.junit is not None:
        data = read_toml(path)
        req = load_requirements(TableReader(data, path), path)
        inputs: dict[str, str | Path | None] = {
            "the requirements file": path,
            "the [baseline] file": req.baseline_file,
        }
        for key in ("model", "model_step", "materials"):
            if isinstance(data.get(key), str):
                inputs[f"its {key}"] = path.parent / data[key]
        refuse_overwriting_inputs(args.junit, inputs)
    check = check_requirements(path, strict=args.strict, update_baseline=args.update_baseline)
    results, passed, written = check.results, check.passed, check.baseline_written
    if args.junit is not None:
        from cadcog.reports.junit import junit_xml

        with staged_file(args.junit) as tmp:
            tmp.write_text(
                junit_xml(check.name, results, time.perf_counter() - started), encoding="utf-8"
            )
        wrote(args.junit)
    if written is not None:
        wrote(written)
    if args.json:
        print_json(check.to_dict())
    else:
        width = max((len(r.title) for r in results), default=20)
        print(f"{check.name}: {len(results)} requirement(s), model {check.model}")
        for r in results:
            mark = "pass" if r.passed else "FAIL"
            print(f"  {mark}  {r.title:<{width}}  {r.value}  (required {r.limit})")
            if not r.passed and r.detail:
                print(f"        {r.detail}")
        if written is not None:
            print(f"baseline written to {written}")
        for n in check.notes:
            print(f"note: {n}")
        failed = sum(1 for r in results if not r.passed)
        print(f"{'all requirements hold' if passed else f'{failed} requirement(s) FAILED'}")
    return 0 if passed else EXIT_FAILED
