"""A virtual test campaign: the paper's experiment as a lab would record it.

For each suspension point one hang is simulated from the error model
(:class:`cadcog.method.errormodel.ErrorModel`, the same one every Monte Carlo draws from): the ME's
real CoG error is drawn once for the whole campaign (it is one physical object), the wire's
stiffness too (one wire); each hang draws its own suspension play and wire offset and, in the
``hang-bias`` model, the inclinometer's bias (uniform ±accuracy per axis, fixed during the hang).
Then ``model.samples`` raw samples per axis add sensor noise (``sensor_noise_deg``) and are
quantised by the ADC to counts: the averaging and the quantisation happen here for real, where the
Monte Carlo uses their closed forms. A sensor's shared errors (``offset_deg``,
``scale_error_rel``, ``mounting_misalignment_deg`` of ``[inclinometer]``) are drawn once for the
campaign: one sensor. The result is a readings CSV with ``inc_x_counts,
inc_y_counts`` columns: :func:`cadcog.method.readings.read_readings` reads it as it reads real data.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cadcog.core.fileio import staged_file
from cadcog.method.errormodel import ErrorModel
from cadcog.method.readings import (
    COUNT_COLUMNS,
    Suspension,
    format_face,
    header_columns,
    suspension_from_samples,
)
from cadcog.rig.inclinometer import InclinometerConfig, sensor_readings
from cadcog.rig.parameters import Rig
from cadcog.uncertainty.montecarlo import Scenario, draw_perturbations
from cadcog.uncertainty.trials import true_pivots, verticals

#: The first words of a virtual campaign's comment line (``campaign`` replaces only a file that
#: begins with them).
VIRTUAL_CAMPAIGN = "cadcog virtual campaign"

#: The header of a virtual campaign: raw counts, as the bench records them.
HEADER = ",".join(header_columns(COUNT_COLUMNS))


@dataclass(frozen=True)
class CampaignRow:
    point_id: str
    position_mm: tuple[float, float, float]
    counts_x: int
    counts_y: int
    top_face_up: bool


def virtual_campaign(rig: Rig, seed: int, model: ErrorModel | None = None) -> list[CampaignRow]:
    """Rows of a simulated campaign over the rig's suspension points (the rig's error model)."""
    return simulated_readings(
        Scenario.from_rig(rig), model or ErrorModel.from_rig(rig), rig.inclinometer, seed
    )


@dataclass(frozen=True)
class CampaignTruth:
    """What a simulated campaign drew once for its hangs: each hang's true virtual suspension
    point (k, 3), the ME's CoG error (3,) and the one wire's offset scale ``λ`` (None for the
    paper's per-hang offsets), mm. The virtual swings swing about the same points."""

    pivots_mm: np.ndarray
    me_cog_error_mm: np.ndarray
    wire_lambda_mm: float | None


def simulated_readings(
    scenario: Scenario, model: ErrorModel, inclinometer: InclinometerConfig, seed: int
) -> list[CampaignRow]:
    """One simulated hang per point of ``scenario``, ``model.samples`` raw ADC readings each."""
    return simulated_campaign(scenario, model, inclinometer, seed)[0]


def simulated_campaign(
    scenario: Scenario, model: ErrorModel, inclinometer: InclinometerConfig, seed: int
) -> tuple[list[CampaignRow], CampaignTruth]:
    """:func:`simulated_readings` and the truth it drew."""
    rng = np.random.default_rng(seed)
    k = len(scenario.ids)
    pert = draw_perturbations(model.only("me_cog", "point_play", "wire_offset"), rng, 1, k)
    pivots, g_true, lam = true_pivots(scenario, model, range(k), pert)
    u = verticals(pivots, g_true)[:, :, 0]  # (3, k)
    truth = CampaignTruth(
        pivots[:, :, 0].T.copy(),
        pert.me_mm[:, 0].astype(float),
        None if model.wire_model == "paper" else float(lam[0, 0]),
    )
    # One sensor for the whole campaign: its offsets, sensitivities and mounting drawn once
    # (nothing is drawn when the model declares none).
    shared = model.sample_shared_sensor(rng, 1)[:, 0]
    # What the device reports for each true vertical, before its per-hang errors (its signs).
    seen_x, seen_y, _ = sensor_readings(u.T, shared, inclinometer)
    sensor = inclinometer.sensor
    a = model.accuracy_deg if "inclinometer" in model.sources else 0.0
    noise = model.sensor_noise_deg if "inclinometer" in model.sources else 0.0
    n = model.samples
    per_sample = model.inclinometer_model == "paper-averaged"
    rows = []
    for j, pid in enumerate(scenario.ids):
        true_deg = np.array([seen_x[j], seen_y[j]])
        bias = rng.uniform(-a, a, (n, 2) if per_sample else 2)
        noisy = true_deg + bias + rng.normal(0.0, noise, (n, 2))
        counts = np.clip(np.floor(sensor.deg_to_counts(noisy) + 0.5), 0, sensor.max_counts)
        p = scenario.points_mm[j]
        for cx, cy in counts.astype(int):
            rows.append(
                CampaignRow(
                    pid,
                    (float(p[0]), float(p[1]), float(p[2])),
                    int(cx),
                    int(cy),
                    bool(u[2, j] > 0),
                )
            )
    return rows, truth


def campaign_text(rows: list[CampaignRow], comment: str = "") -> str:
    """Rows as the text of a readings CSV (counts), the comment's lines first."""
    lines = [f"# {c}" for c in comment.splitlines()] + [HEADER]
    for r in rows:
        x, y, z = r.position_mm
        lines.append(
            f"{r.point_id},{x:.3f},{y:.3f},{z:.3f},{r.counts_x},{r.counts_y},"
            f"{format_face(r.top_face_up)}"
        )
    return "\n".join(lines) + "\n"


def write_campaign(path: str | Path, rows: list[CampaignRow], comment: str = "") -> None:
    """Write rows as a readings CSV (counts), atomically."""
    with staged_file(path) as tmp:
        tmp.write_text(campaign_text(rows, comment), encoding="utf-8")


def campaign_suspensions(
    rows: list[CampaignRow], inclinometer: InclinometerConfig
) -> list[Suspension]:
    """The averaged suspensions of campaign rows, as :func:`cadcog.method.readings.read_readings`
    would read them back from the CSV (without the file; positions rounded as written)."""
    groups: dict[str, list[CampaignRow]] = {}
    for r in rows:
        groups.setdefault(r.point_id, []).append(r)
    out = []
    line = 2
    for pid, rs in groups.items():
        x = inclinometer.sensor.counts_to_deg([r.counts_x for r in rs])
        y = inclinometer.sensor.counts_to_deg([r.counts_y for r in rs])
        n = len(rs)
        pos = tuple(float(f"{c:.3f}") for c in rs[0].position_mm)
        out.append(
            suspension_from_samples(pid, (pos[0], pos[1], pos[2]), rs[0].top_face_up, x, y, line)
        )
        line += n
    return out
