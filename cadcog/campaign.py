"""A virtual test campaign: the paper's experiment as a lab would record it.

For each of the rig's suspension points one hang is simulated: the ME's real CoG error is drawn
once for the whole campaign (it is one physical object), each hang draws its own suspension play
and wire offset and the inclinometer's bias (uniform ±accuracy per axis, fixed during the hang);
then N raw samples per axis add sensor noise and are quantised by the ADC to counts. The result
is a readings CSV with ``inc_x_counts, inc_y_counts`` columns: :func:`cadcog.readings.read_readings`
reads it as it reads real data.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cadcog.errormodel import ErrorModel
from cadcog.fileio import staged_file
from cadcog.inclinometer import InclinometerConfig
from cadcog.montecarlo import Scenario, draw_perturbations, hang
from cadcog.rig import Rig
from cadcog.units import rad_to_deg

#: Default sensor noise of one raw sample (degrees), an assumption: enough to dither the ADC.
DEFAULT_NOISE_DEG = 0.05

HEADER = "point_id,x_mm,y_mm,z_mm,inc_x_counts,inc_y_counts,top_face_up"


@dataclass(frozen=True)
class CampaignRow:
    point_id: str
    position_mm: tuple[float, float, float]
    counts_x: int
    counts_y: int
    top_face_up: bool


def virtual_campaign(
    rig: Rig,
    seed: int,
    samples: int = 10,
    noise_deg: float = DEFAULT_NOISE_DEG,
    model: ErrorModel | None = None,
) -> list[CampaignRow]:
    """Rows of a simulated campaign over the rig's suspension points (``samples`` per point)."""
    return simulated_readings(
        Scenario.from_rig(rig),
        model or ErrorModel.from_rig(rig),
        rig.inclinometer,
        seed,
        samples,
        noise_deg,
    )


def simulated_readings(
    scenario: Scenario,
    model: ErrorModel,
    inclinometer: InclinometerConfig,
    seed: int,
    samples: int = 10,
    noise_deg: float = DEFAULT_NOISE_DEG,
) -> list[CampaignRow]:
    """One simulated hang per point of ``scenario``, ``samples`` raw ADC readings each."""
    if samples < 1:
        raise ValueError("samples must be at least 1")
    if noise_deg < 0:
        raise ValueError("noise_deg must be non-negative")
    rng = np.random.default_rng(seed)
    k = len(scenario.ids)
    pert = draw_perturbations(model.only("me_cog", "point_play", "wire_offset"), rng, 1, k)
    u = hang(scenario, model, range(k), pert)[:, 0, :]  # (3, k)
    sensor = inclinometer.sensor
    a = inclinometer.accuracy_deg if "inclinometer" in model.sources else 0.0
    rows = []
    for j, pid in enumerate(scenario.ids):
        signs = (inclinometer.sign_x, inclinometer.sign_y)
        true_deg = rad_to_deg(np.arcsin(np.clip(u[:2, j], -1, 1))) * signs
        bias = rng.uniform(-a, a, 2)
        noisy = true_deg + bias + rng.normal(0.0, noise_deg, (samples, 2))
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
    return rows


def write_campaign(path: str | Path, rows: list[CampaignRow], comment: str = "") -> None:
    """Write rows as a readings CSV (counts), atomically."""
    lines = [f"# {c}" for c in comment.splitlines()] + [HEADER]
    for r in rows:
        x, y, z = r.position_mm
        lines.append(
            f"{r.point_id},{x:.3f},{y:.3f},{z:.3f},{r.counts_x},{r.counts_y},"
            f"{str(r.top_face_up).lower()}"
        )
    with staged_file(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
