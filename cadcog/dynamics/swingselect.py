"""Which swings, and which of their modes, the tensor is fitted to.

A hang's swing is used only when its record can show its modes (seconds, fast enough for the
highest mode the CAD predicts, enough samples) and its fit shows a body mode; a hang that
cannot is left out with a note, not the whole run (:func:`usable_swings`). Of the frequencies
kept, those the others contradict are left out one at a time, the least likely first
(:func:`worst_contradiction`: a weak mode fitted off, or a hang's whole swing).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import numpy.typing as npt

from cadcog.core.errors import DegenerateGeometryError
from cadcog.core.fittest import chi2_sf
from cadcog.dynamics.context import HangTerms
from cadcog.dynamics.hungbody import HangGeometry, hang_modes
from cadcog.dynamics.modalfit import ModalFit, fit_swing
from cadcog.dynamics.swingfile import MIN_SAMPLES, Swing
from cadcog.dynamics.tensorfit import Geometry, SwingData, deleted_chi2
from cadcog.mass.properties import MassProperties
from cadcog.method.readings import Suspension

FloatArray = npt.NDArray[np.float64]

#: A frequency, or a hang's frequencies, whose deleted-residual χ² has a p-value below this
#: over the number of candidates (Bonferroni: a campaign loses a good mode or hang with
#: probability below this) is left out.
MODE_OUTLIER_P = 0.01

#: A hang's record longer than this (s) is not a swing in seconds (t_s in ms?).
MAX_RECORD_S = 3600.0
#: The record's median rate must exceed the highest predicted mode by this factor (Nyquist's
#: 2, with room for the fit).
MIN_RATE_OVER_MODE = 2.5


def record_problem(sw: Swing, highest_hz: float) -> str | None:
    """Why a hang's record cannot show its modes whatever the fit: a duration that is not
    seconds, or a rate too low for the highest mode the model predicts (or None)."""
    duration = float(sw.t_s[-1] - sw.t_s[0])
    if duration > MAX_RECORD_S:
        return (
            f"hang {sw.point_id}: its record lasts {duration:.6g} s (expected seconds: is t_s "
            "in milliseconds?)"
        )
    rate = 1.0 / float(np.median(np.diff(sw.t_s)))
    if rate < MIN_RATE_OVER_MODE * highest_hz:
        return (
            f"hang {sw.point_id}: sampled at {rate:.3g} Hz, too slow for its modes up to "
            f"{highest_hz:.3g} Hz (at least {MIN_RATE_OVER_MODE * highest_hz:.3g} Hz; record at "
            "20 samples/s or more)"
        )
    return None


def body_modes(fit: ModalFit, n_modes: int, point_id: str) -> ModalFit:
    """The fit's body modes only: the two fastest of a hang (its only two on a pivot). On a
    wire the two slow modes are the wire's own pendulum, set by its length far more than by the
    inertia, and close enough together to be mis-fitted; they are fitted (the signal has them)
    but not used."""
    keep = fit.mode_index >= n_modes - 2
    if not keep.any():
        raise DegenerateGeometryError(
            f"hang {point_id}: neither body mode of the swing stands out (only the wire's own "
            "pendulum was seen): release the object tilted 2-3° about its wire exit, not only "
            "the wire swung (docs/bench.md)"
        )
    return fit.take(keep)


def worst_contradiction(
    fits: Sequence[ModalFit], p_asm: FloatArray, data: SwingData, geo: Geometry
) -> tuple[int, set[int], float, float] | None:
    """The frequencies the others contradict most, when beyond the Bonferroni threshold: their
    hang, which of its modes, the χ² they add and its p-value; None when none is, or when no
    check would remain (one dof and three hangs).

    The candidates are every single mode and every hang's whole swing (a weak mode fitted off,
    or a swing off as a whole: something moved), compared by the p-value of their
    deleted-residual χ² (:func:`cadcog.dynamics.tensorfit.deleted_chi2`).
    """
    n = len(data.frequencies_hz)
    counts = [len(f.frequencies_hz) for f in fits]
    starts = np.cumsum([0, *counts])
    candidates: list[tuple[tuple[int, int], ...]] = [
        ((h, j),) for h in range(len(fits)) for j in range(counts[h])
    ]
    candidates += [
        tuple((h, j) for j in range(counts[h])) for h in range(len(fits)) if counts[h] > 1
    ]
    candidates = [
        c for c in candidates
        if n - len(c) - 6 >= 1 and (len(c) < counts[c[0][0]] or len(fits) > 3)
    ]  # fmt: skip
    if not candidates:
        return None
    d = deleted_chi2(p_asm, data, geo, [[int(starts[h]) + j for h, j in c] for c in candidates])
    pv = np.array([chi2_sf(x, len(c)) for x, c in zip(d, candidates, strict=True)])
    best = int(np.argmin(pv))
    if not pv[best] < MODE_OUTLIER_P / len(candidates):
        return None
    return candidates[best][0][0], {j for _, j in candidates[best]}, float(d[best]), float(pv[best])


@dataclass(frozen=True)
class UsedHangs:
    """The hangs the tensor is fitted to: each one's swing and suspension, its modal fit, its
    record's length (s), and the geometry's terms (each pivot, the top clamp's hinge and their
    joint covariance with the CoG: :class:`~cadcog.dynamics.context.HangTerms`)."""

    pairs: tuple[tuple[Swing, Suspension], ...]
    fits: tuple[ModalFit, ...]
    records_s: tuple[float, ...]
    terms: HangTerms

    @property
    def pivots_mm(self) -> FloatArray:
        return self.terms.pivots_mm

    def only(self, hangs: Sequence[int]) -> UsedHangs:
        """These hangs alone, in this order."""
        return UsedHangs(
            tuple(self.pairs[i] for i in hangs),
            tuple(self.fits[i] for i in hangs),
            tuple(self.records_s[i] for i in hangs),
            self.terms.only(hangs),
        )

    def without(self, hang: int, modes: set[int]) -> UsedHangs:
        """Hang ``hang`` without its modes ``modes`` (without the hang if that is all of
        them)."""
        fit = self.fits[hang]
        n = len(fit.frequencies_hz)
        if len(modes) == n:
            return self.only([i for i in range(len(self.fits)) if i != hang])
        fits = list(self.fits)
        fits[hang] = fit.take(np.array([j not in modes for j in range(n)]))
        return replace(self, fits=tuple(fits))

    def halves_notes(self) -> list[str]:
        """The frequencies whose record's two halves disagreed beyond their noise (their σ
        holds it) and those a half did not show (not checked), one note each kind."""
        widened, unchecked = [], []
        for fit in self.fits:
            if fit.halves_excess_hz2 is None:
                continue
            for f, x in zip(fit.frequencies_hz, fit.halves_excess_hz2, strict=True):
                where = f"{fit.point_id} ({f:.3f} Hz"
                if np.isnan(x):
                    unchecked.append(f"{where})")
                elif x > 0:
                    widened.append(f"{where}: ± {100 * np.sqrt(x) / f:.2g} %)")
        notes = []
        if widened:
            notes.append(
                "the two halves of these swings disagree beyond their noise, and each "
                f"frequency's σ holds it: {', '.join(widened)} (a large swing's nonlinearity; "
                "docs/method.md, 'The fit checked against itself')"
            )
        if unchecked:
            notes.append(
                "a half of the record did not show these modes (they died away in the first "
                "half, or half a record cannot resolve them), so their fit is not checked "
                "against itself: " + ", ".join(unchecked)
            )
        return notes

    def weak_note(self) -> str:
        """What to add to a refusal when hangs showed one body mode of two: their swings were
        too small, or released along one face, to show both (more hangs would not help as
        much)."""
        weak = [sw.point_id for fit, (sw, _) in zip(self.fits, self.pairs, strict=True)
                if len(fit.mode_index) < 2]  # fmt: skip
        if not weak:
            return ""
        return (
            f"; hang(s) {', '.join(weak)} showed one body mode of two: release each with a "
            "push of 2-3° in a direction between two of its faces, tilting it about its wire "
            "exit, and record until it settles (docs/bench.md)"
        )


def usable_swings(
    pairs: Sequence[tuple[Swing, Suspension]],
    terms: HangTerms,
    cad_assembly: MassProperties,
    geometry: Sequence[HangGeometry],
) -> tuple[UsedHangs, list[str]]:
    """Each hang's body modes, fitted from the modes the CAD's assembly predicts on its
    ``geometry``; the hangs whose record or fit cannot show one left out, each with a note.
    ``terms``: as :meth:`~cadcog.dynamics.context.InertiaContext.hang_terms` gives them.

    Raises
    ------
    DegenerateGeometryError
        If fewer than three hangs remain (naming why each other one was left out).
    """
    fits, records, kept, dropped = [], [], [], []
    for i, ((sw, _), geo) in enumerate(zip(pairs, geometry, strict=True)):
        predicted = hang_modes(
            cad_assembly.inertia_kg_mm2, cad_assembly.mass_kg, cad_assembly.cog_mm, geo
        )
        n_modes = len(predicted.frequencies_hz)
        if len(sw.t_s) < MIN_SAMPLES:
            dropped.append(
                f"hang {sw.point_id}: {len(sw.t_s)} swing samples, the fit needs "
                f"{MIN_SAMPLES} (record from the release until it settles)"
            )
            continue
        record = record_problem(sw, float(np.max(predicted.frequencies_hz)))
        if record is not None:
            dropped.append(record)
            continue
        try:  # a hang whose swing shows no body mode is left out, not the whole run
            fit = body_modes(fit_swing(sw, predicted.frequencies_hz), n_modes, sw.point_id)
        except DegenerateGeometryError as exc:
            dropped.append(str(exc))
            continue
        fits.append(fit)
        records.append(sw.duration_s)
        kept.append(i)
    if len(kept) < 3:
        raise DegenerateGeometryError(
            f"{len(kept)} of {len(pairs)} hangs have a body mode to use, the whole tensor needs "
            "three: " + "; ".join(dropped)
        )
    used = UsedHangs(tuple(pairs[i] for i in kept), tuple(fits), tuple(records), terms.only(kept))
    return used, dropped
