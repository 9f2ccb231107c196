"""A virtual campaign written as a lab would record it: ``cadcog campaign`` and
:func:`cadcog.campaign`.

One hang per suspension point of the rig (or per listed candidate of a set-up), drawn from the
error model every command uses (:func:`cadcog.validation.campaign.simulated_campaign`), written
as a readings CSV; with ``swings``, the same hangs' swings too. Both files are computed before
either is written, and written together: a failure (a full disk, a bad path) leaves neither.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from cadcog.core.errors import CadcogError
from cadcog.core.fileio import is_stream, refuse_overwriting_inputs, staged_files
from cadcog.core.results import JsonResult
from cadcog.method.errormodel import ErrorModel
from cadcog.rig.parameters import Rig
from cadcog.runs import check_distinct_ids
from cadcog.spacecraft.plan import check_candidate
from cadcog.spacecraft.setup import Setup
from cadcog.uncertainty.montecarlo import Scenario
from cadcog.validation.campaign import (
    VIRTUAL_CAMPAIGN,
    campaign_suspensions,
    campaign_text,
    simulated_campaign,
)


@dataclass(frozen=True, repr=False)  # JsonResult's one-line repr
class CampaignRun(JsonResult):
    """What a campaign wrote.

    Attributes
    ----------
    out : str
        The readings CSV.
    n_samples : int
        Rows written.
    n_hangs : int
        Hangs.
    seed : int
    swings : str or None
        The swing file, when asked for.
    warnings : tuple of str
        Hangs ``cadcog plan`` says cannot work (simulated as the sensor would read them).
    """

    out: str
    n_samples: int
    n_hangs: int
    seed: int
    swings: str | None = None
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "out": self.out,
            "n_samples": self.n_samples,
            "n_hangs": self.n_hangs,
            "seed": self.seed,
        }
        if self.swings is not None:
            data["swings"] = self.swings
        if self.warnings:
            data["warnings"] = list(self.warnings)
        return data


def with_overrides(
    model: ErrorModel, *, samples: int | None = None, noise_deg: float | None = None
) -> ErrorModel:
    """The error model with a campaign's overrides (the rig file's keys ``samples`` and
    ``sensor_noise_deg``), checked.

    Raises
    ------
    CadcogError
        ``samples`` below 1, ``noise_deg`` negative or not a number.
    """
    if samples is not None:
        if samples < 1:
            raise CadcogError(f"--samples must be at least 1, got {samples}")
        model = replace(model, samples=samples)
    if noise_deg is not None:
        if not noise_deg >= 0:
            raise CadcogError(f"--noise-deg must be non-negative, got {noise_deg}")
        model = replace(model, sensor_noise_deg=noise_deg)
    return model


def check_points(points: Sequence[str] | None) -> list[str]:
    """A set-up campaign's point ids: at least two, distinct (checked before the CAD)."""
    ids = [i.strip() for i in points or ()]
    if not ids:
        raise CadcogError("--setup needs --points ID,ID,... (see cadcog plan)")
    check_distinct_ids(ids)
    return ids


#: The first line of every readings file ``campaign`` writes (and the only kind it replaces):
#: its comment, as :func:`~cadcog.validation.campaign.campaign_text` writes it.
VIRTUAL_CAMPAIGN_MARK = f"# {VIRTUAL_CAMPAIGN}"


def _is_virtual_campaign(path: Path) -> bool:
    """Whether ``path`` is a readings file ``campaign`` wrote (its first line says so)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return fh.readline(200).startswith(VIRTUAL_CAMPAIGN_MARK)
    except OSError:
        return False


def _refuse_replacing_measurements(out: Path, swings: Path | None) -> None:
    """A virtual campaign replaces only a virtual campaign: an existing ``out`` that is not
    one (a test day's readings) is refused, and an existing ``swings`` unless it goes with a
    virtual campaign at ``out`` (a swing file carries no mark of its own). Streams (``-``, a
    FIFO, a device) are written into as ever.

    Raises
    ------
    CadcogError
        Naming the option and the file.
    """
    virtual = False
    if not is_stream(out) and Path(out).exists() and Path(out).is_file():
        virtual = _is_virtual_campaign(Path(out))
        if not virtual:
            raise CadcogError(
                f"--out {out}: exists and is not a virtual campaign (its first line is not "
                f"{VIRTUAL_CAMPAIGN_MARK!r}): a test's readings are not replaced; give another "
                "--out, or remove the file"
            )
    if swings is not None and not is_stream(swings) and Path(swings).is_file() and not virtual:
        raise CadcogError(
            f"--swings {swings}: exists, and --out is not the virtual campaign it goes with: a "
            "test's swings are not replaced; give another --swings, or remove the file"
        )


def run_campaign(
    out: Path,
    *,
    rig: Rig | None = None,
    setup: Setup | None = None,
    points: Sequence[str] | None = None,
    seed: int = 0,
    samples: int | None = None,
    noise_deg: float | None = None,
    swings: Path | None = None,
) -> CampaignRun:
    """Simulate a campaign of ``rig`` (every suspension point) or of ``setup`` (the candidates
    ``points``) and write it to ``out`` (and its swings to ``swings``).

    Raises
    ------
    CadcogError
        Neither or both of ``rig`` and ``setup``; ``points`` without a set-up, or unknown ids;
        a bad override; an output that cannot be written (then neither file is).
    """
    if (rig is None) == (setup is None):
        raise CadcogError("give a rig or a set-up")
    if seed < 0:
        raise CadcogError("--seed must be non-negative")
    inputs: dict[str, str | Path | None] = {
        "--rig": None if rig is None else rig.source,
        "--setup": None if setup is None else setup.source,
    }
    refuse_overwriting_inputs(out, inputs)
    _refuse_replacing_measurements(out, swings)
    if swings is not None:
        refuse_overwriting_inputs(swings, inputs)
        if str(swings) not in ("", "-") and Path(swings).resolve() == Path(out).resolve():
            raise CadcogError(f"--swings and --out name the same file: {out}")
        if Path(swings).exists() and not Path(swings).is_file():  # a device takes its bytes
            raise CadcogError(  # after the readings are in place: all or nothing fails
                f"{swings}: exists and is not a regular file: give another --swings"
            )
    if setup is None:
        assert rig is not None
        if points is not None:
            raise CadcogError("--points goes with --setup")
        model = with_overrides(ErrorModel.from_rig(rig), samples=samples, noise_deg=noise_deg)
        rows, truth = simulated_campaign(Scenario.from_rig(rig), model, rig.inclinometer, seed)
        comment = (
            f"{VIRTUAL_CAMPAIGN}: rig {rig.name}, seed {seed}, "
            f"{model.samples} samples per hang; {model.summary()}"
        )
        inclinometer = rig.inclinometer
        n_hangs = len(rig.suspension_points)
        warnings: tuple[str, ...] = ()
    else:
        ids = check_points(points)
        by_id = {c.id: c for c in setup.candidates}
        unknown = [i for i in ids if i not in by_id]
        from cadcog.bench.target import REVERSAL_SUFFIX

        turned = [i for i in unknown if i.endswith(REVERSAL_SUFFIX) and i[:-1] in by_id]
        if turned:
            raise CadcogError(
                f"--points: {', '.join(turned)}: a reversal (the sensor turned on its mount) is "
                "hung at the bench (cadcog acquire); a virtual campaign hangs each candidate "
                "once, as its error model reads it"
            )
        if unknown:
            raise CadcogError(
                f"--points: unknown candidate(s) {', '.join(unknown)} in {setup.source}"
            )
        model = with_overrides(setup.error_model(), samples=samples, noise_deg=noise_deg)
        warnings = tuple(
            f"{i}: cannot work, as `cadcog plan` says ({c.reason}): simulated as the sensor "
            "would read it"
            for i in ids
            if not (c := check_candidate(setup, by_id[i])).usable
        )
        scenario = setup.scenario(tuple(by_id[i] for i in ids))
        rows, truth = simulated_campaign(scenario, model, setup.rig.inclinometer, seed)
        comment = f"{VIRTUAL_CAMPAIGN}: setup {setup.name}, seed {seed}; {model.summary()}"
        inclinometer = setup.rig.inclinometer
        n_hangs = len(ids)
    swing_text = None
    if swings is not None:
        from cadcog.dynamics.context import context_for_rig, context_for_setup
        from cadcog.dynamics.swingfile import swings_text
        from cadcog.dynamics.virtual import virtual_swings

        context = (
            context_for_setup(setup, np.zeros((6, 6)))
            if setup is not None
            else context_for_rig(rig)  # type: ignore[arg-type]  # rig is given (checked above)
        )
        hangs = campaign_suspensions(rows, inclinometer)
        swing_text = swings_text(
            virtual_swings(
                context,
                hangs,
                seed=seed,
                pivots_mm=truth.pivots_mm,
                me_cog_error_mm=truth.me_cog_error_mm,
                top_hinge_mm=truth.wire_lambda_mm,
            )
        )
    # Both staged and filled, then put in place together (or neither).
    outputs = [out] if swing_text is None else [out, swings]
    with staged_files(*outputs) as staged:
        staged[0].write_text(campaign_text(rows, comment), encoding="utf-8")
        if swing_text is not None:
            staged[1].write_text(swing_text, encoding="utf-8")
    return CampaignRun(
        str(out), len(rows), n_hangs, seed, None if swings is None else str(swings), warnings
    )
