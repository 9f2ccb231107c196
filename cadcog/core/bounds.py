"""The range of every number cadcog accepts, from a file or the command line: one place.

cadcog's names carry their unit (``size_mm``, ``mass_kg``, ``--noise-deg``), so a value's
physical range follows from its name's unit suffix (:data:`UNIT_BOUNDS`); counts and other
unitless values have a bound of their own, by name (:data:`NAMED_BOUNDS`). Every parameter-file
key read through :class:`cadcog.core.paramfile.TableReader` and every numeric command-line option
(:func:`cadcog.cli._main.main`) is checked here, after the finiteness check, so that a value
beyond what a small spacecraft, its test rig or the machine can hold is refused up front with
the bound and the reason, instead of computing nonsense, running for hours or exhausting
memory. ``docs/inputs.md`` lists them (:func:`markdown_table`, checked by a test).

Examples
--------
>>> check("size_mm", 1e300)
'expected at most 20000 (lengths and positions within 20 m)'
>>> check("adc_bits", 12) is None, check("unknown_name", 1e300) is None
(True, True)
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Bound:
    """A closed range ``[lo, hi]`` and why; ``integer`` says the value counts something;
    ``above`` makes the range ``(lo, hi]`` (a σ or a duration that must be more than 0)."""

    lo: float
    hi: float
    why: str
    integer: bool = False
    above: bool = False

    def message(self, value: float) -> str | None:
        """None when ``value`` is inside, else what was expected."""

        def fmt(x: float) -> str:
            return f"{int(x)}" if self.integer else f"{x:g}"

        if self.above and value <= self.lo:
            return f"expected more than {fmt(self.lo)} ({self.why})"
        if value < self.lo:
            return f"expected at least {fmt(self.lo)} ({self.why})"
        if value > self.hi:
            return f"expected at most {fmt(self.hi)} ({self.why})"
        return None


#: Lengths and positions: 20 m is beyond any small spacecraft and its test rig.
LENGTH_MAX_MM = 20_000.0
#: Masses: 10 t is beyond any small spacecraft.
MASS_MAX_KG = 10_000.0
#: Monte Carlo trials per pair of suspension points (`simulate`) or per finalist set (`plan`):
#: about 0.5-1 s per 10⁶ on one core at the measured throughput (docs/performance.md).
MAX_TRIALS_PER_PAIR = 10_000_000
#: Raw samples per hang (`campaign`, `simulate`, rig files): 10⁵ is 1.4 h at 20 Hz; a virtual
#: campaign holds about 500 bytes per sample in memory (300 MB for six such hangs).
MAX_SAMPLES_PER_HANG = 100_000
#: Candidate suspension points of a set-up: every pair is screened.
MAX_CANDIDATES = 2_000
#: Simulated campaigns (`validate`).
MAX_CAMPAIGNS = 1_000_000

#: By the unit suffix of a name, longest suffix first.
UNIT_BOUNDS: dict[str, Bound] = {
    "_v_per_deg": Bound(0.0, 100.0, "sensor sensitivity, V per degree"),
    "_kg_mm2": Bound(-1e12, 1e12, "inertia within that of 10 t at 10 m"),
    "_n_mm2": Bound(0.0, 1e12, "bending stiffness"),
    "_kg_m3": Bound(10.0, 25_000.0, "kg/m³ of solids, foams to osmium; is it in g/cm³?"),
    "_kg_m2": Bound(0.0, 1_000.0, "areal densities of sheets and blankets"),
    "_mm2": Bound(0.0, LENGTH_MAX_MM**2, "variances of lengths within 20 m"),
    "_mm": Bound(-LENGTH_MAX_MM, LENGTH_MAX_MM, "lengths and positions within 20 m"),
    "_kg": Bound(0.0, MASS_MAX_KG, "masses up to 10 t"),
    "_deg": Bound(-360.0, 360.0, "angles within a turn"),
    "_s": Bound(0.0, 86_400.0, "durations up to a day"),
    "_v": Bound(-100.0, 100.0, "sensor and reference voltages"),
}

#: By the whole name: counts and unitless values.
NAMED_BOUNDS: dict[str, Bound] = {
    "adc_bits": Bound(1, 32, "ADCs of inclinometers have 8-24 bits", integer=True),
    "units": Bound(1, 12, "CubeSat units along the rails", integer=True),
    "samples_per_suspension": Bound(1, MAX_SAMPLES_PER_HANG, "samples per hang", integer=True),
    "samples": Bound(1, MAX_SAMPLES_PER_HANG, "samples per hang", integer=True),
    "trials": Bound(
        2, MAX_TRIALS_PER_PAIR, "Monte Carlo trials: about 1 s per 10⁶ on one core", integer=True
    ),
    "points": Bound(
        0, 200, "random suspension points, 0 for the rig's: every pair is simulated", True
    ),
    "group_size": Bound(2, 12, "suspensions per estimate", integer=True),
    "max_set": Bound(2, 8, "hangs per set: every set of candidates is screened", integer=True),
    "campaigns": Bound(1, MAX_CAMPAIGNS, "simulated campaigns", integer=True),
    "seed": Bound(0, 2**63 - 1, "seeds are non-negative 64-bit integers", integer=True),
    "workers": Bound(1, 64, "processes; more than the machine has CPUs only costs memory", True),
    "depth": Bound(0, 100, "levels of the budget tree shown", integer=True),
    "baud": Bound(300, 4_000_000, "serial line rates", integer=True),
    "max_redo": Bound(0, 100, "redos per hang", integer=True),
    "time_scale": Bound(0.01, 10_000.0, "simulated device speed-up"),
    "level": Bound(1e-6, 0.5, "significance level of a test"),
    "candidates": Bound(2, MAX_CANDIDATES, "candidate points: every pair is screened", True),
    "min_angle_deg": Bound(0.0, 90.0, "the angle between two plumb lines"),
    "offset_deg": Bound(0.0, 5.0, "a sensor's zero offset per channel; datasheets: tenths of °"),
    "scale_error_rel": Bound(0.0, 0.2, "a channel's sensitivity error, a fraction (1 % is 0.01)"),
    "mounting_misalignment_deg": Bound(0.0, 10.0, "the sensor's axes against the object's"),
    "offset_g": Bound(0.0, 0.3, "an accelerometer's zero offset per axis; datasheets: tens of mg"),
    "accuracy_g": Bound(0.0, 0.1, "an accelerometer's unmodelled error per axis (nonlinearity)"),
    "cross_axis_rel": Bound(0.0, 0.1, "an accelerometer's cross-axis sensitivity (2 % is 0.02)"),
    "frequency_model_rel": Bound(0.0, 0.1, "a frequency's model error (default: air carried)"),
    "me_inertia_rel": Bound(0.0, 1.0, "the ME's inertia uncertainty, a fraction (0.3)"),
    "total_mass_kg": Bound(1e-6, MASS_MAX_KG, "a weighed total from 1 mg to 10 t"),
    "object_mass_kg": Bound(1e-6, MASS_MAX_KG, "the object's mass, from 1 mg to 10 t"),
    "weighed_mass_kg": Bound(1e-6, MASS_MAX_KG, "a weighed mass, from 1 mg to 10 t"),
    # Spreads and durations a command divides by or waits on: more than zero (the name rule
    # for spreads allows zero, which these cannot use).
    "mass_sigma_kg": Bound(0.0, MASS_MAX_KG, "a weighing's 1 σ", above=True),
    "unmodelled_sigma_kg": Bound(0.0, MASS_MAX_KG, "the unmodelled mass's prior 1 σ", above=True),
    "angle_sigma_deg": Bound(
        0.0, 360.0, "a reading's 1 σ, given instead of the model's", above=True
    ),
    "point_sigma_mm": Bound(
        0.0, LENGTH_MAX_MM, "a point's 1 σ, given instead of the model's", above=True
    ),
    "settle_threshold_deg": Bound(
        0.0, 360.0, "the swing below which a hang has settled", above=True
    ),
    "average_s": Bound(0.0, 86_400.0, "seconds averaged once settled", above=True),
    "settle_window_s": Bound(0.0, 86_400.0, "the window a swing is measured over", above=True),
    "settle_hold_s": Bound(0.0, 86_400.0, "how long a swing stays settled", above=True),
    "max_settle_s": Bound(0.0, 86_400.0, "the longest wait for a hang to settle", above=True),
    "timeout_s": Bound(
        0.0, 86_400.0, "seconds without a sample before the link is lost", above=True
    ),
    "duration_s": Bound(0.0, 86_400.0, "how long a recording runs", above=True),
}


#: Names holding one of these words are spreads: never negative, whatever their unit (unless
#: the name has a bound of its own in :data:`NAMED_BOUNDS`).
NONNEGATIVE_WORDS = ("sigma", "noise", "uncertainty", "tolerance", "accuracy")


@functools.lru_cache(maxsize=1024)
def bound_for(name: str) -> Bound | None:
    """The bound of a key or option (its ``dest``), by name then by unit suffix."""
    key = name.lstrip("-").replace("-", "_")
    if key in NAMED_BOUNDS:
        return NAMED_BOUNDS[key]
    for suffix in sorted(UNIT_BOUNDS, key=len, reverse=True):
        if key.endswith(suffix):
            return UNIT_BOUNDS[suffix]
    return None


def check(name: str, value: float) -> str | None:
    """None when ``value`` is a finite number within ``name``'s bound (or ``name`` has none),
    else what was expected."""
    if not math.isfinite(value):
        return "expected a finite number"
    key = name.lstrip("-").replace("-", "_")
    if key not in NAMED_BOUNDS and value < 0 and any(w in key for w in NONNEGATIVE_WORDS):
        return "expected a number >= 0 (a standard deviation, noise or uncertainty)"
    bound = bound_for(name)
    return None if bound is None else bound.message(value)


def markdown_table() -> str:
    """The bounds as the Markdown table of ``docs/inputs.md``."""
    rows = ["| name or unit suffix | accepted | why |", "|---|---|---|"]

    def fmt(b: Bound, x: float) -> str:
        return f"{int(x)}" if b.integer else f"{x:g}"

    for suffix, b in sorted(UNIT_BOUNDS.items(), key=lambda kv: -len(kv[0])):
        rows.append(f"| `*{suffix}` | {fmt(b, b.lo)} … {fmt(b, b.hi)} | {b.why} |")
    for name, b in NAMED_BOUNDS.items():
        low = f"more than {fmt(b, b.lo)}, up to" if b.above else f"{fmt(b, b.lo)} …"
        rows.append(f"| `{name}` | {low} {fmt(b, b.hi)} | {b.why} |")
    return "\n".join(rows) + "\n"
