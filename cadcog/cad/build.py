"""``cadcog parts build``: from a rig file to STEP, STL and ground truth on disk."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from cadcog.cad.export import write_step, write_stl
from cadcog.cad.groundtruth import ground_truth
from cadcog.cad.rigsolids import build_rig
from cadcog.core.fileio import staged_output_dir
from cadcog.core.jsontext import dumps_json
from cadcog.rig.parameters import Rig

GROUND_TRUTH_FILE = "ground_truth.json"
STEP_FILE = "assembly.step"
STL_DIR = "stl"


@dataclass(frozen=True)
class BuildResult:
    """What a build wrote, and the ground truth it computed."""

    out_dir: Path
    files: tuple[Path, ...]
    ground_truth: dict[str, Any]


def build_parts(rig: Rig, out_dir: str | Path) -> BuildResult:
    """Build the rig's solids and write its STEP assembly, one STL per body and the ground truth.

    Files appear in ``out_dir`` only once all of them have been produced.
    """
    out = Path(out_dir)
    model = build_rig(rig)
    truth = ground_truth(rig, model)
    names = [STEP_FILE, GROUND_TRUTH_FILE] + [f"{STL_DIR}/{s.label}.stl" for s in model.bodies]
    with staged_output_dir(out) as stage:
        (stage / STL_DIR).mkdir()
        write_step(model.assembly(rig.name), stage / STEP_FILE)
        for solid in model.bodies:
            write_stl(solid, stage / STL_DIR / f"{solid.label}.stl")
        (stage / GROUND_TRUTH_FILE).write_text(dumps_json(truth), encoding="utf-8")
    return BuildResult(out, tuple(out / n for n in names), truth)
