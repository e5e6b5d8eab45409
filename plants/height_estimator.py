"""On-line workpiece-height estimation for wire EDM (Liao & Yu, seeds/003), as a batched block.

The model (eqs. 8-14): H F = gamma Fq, so per sample dS(k) = beta dN(k) + noise with
dS = table travel in the sample (mm, feed_actual * dt) and dN = discharges counted in it;
beta = gamma / H. beta is identified recursively (eq. 13, fast least-squares projection):
    beta(k) = beta(k-1) + (1 - lam)(dN + 0.4) / (1e-7 + dN^2) * (dS - dN beta(k-1))
and the uncorrected height is H~ = gamma / beta (eq. 14). gamma is identified once on a known
10-mm cut; it drifts with height (kerf, discharge efficiency), so the paper multiplies by a
correction factor fitted to its Table 1:  CF = 3.84e-5 H~^2 - 0.0047 H~ + 1.04438,  H = CF H~.

Variable forgetting (the paper asks for it without a formula; ours): lam = 0.999 while the
relative prediction error |dS/dN - beta| / beta is within the noise, falling to lam_min as
the error grows past error_scale:  lam = lam_max - (lam_max - lam_min) min(1, (err/scale)^2).
assumption: lam_min = 0.6, error_scale = 0.15 (a 40-ms count of ~1000 discharges has ~3 %
noise; a height step of 20 % or more is then followed within a few samples).

Pulse-mix weighting (ours, from the paper's own eq. 3/7): gamma is proportional to
T_on^2 (1 - r) + A_on^2 r/2, so a fixed gamma is only right at the abnormal ratio of the
calibration cut. Liao & Yu held the servo voltage (hence r) constant while estimating; under
the fuzzy controller r moves with every height step. With `ratio_ref` given (the calibration
cut's mean abnormal ratio) the estimator counts removal-weighted pulses instead,
    dN_w = dN (T_on^2 (1 - r) + A_on^2 r/2) / (T_on^2 (1 - r_ref) + A_on^2 r_ref/2),
with r the ratio counted in the same sample, so beta = gamma_ref / H again. Without it the
estimator is the paper's.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def correction_factor(h_raw: np.ndarray) -> np.ndarray:
    """Liao & Yu's regression of true/estimated height on the estimate (mm)."""
    return 3.84e-5 * h_raw ** 2 - 0.0047 * h_raw + 1.04438


def beta_update(beta: np.ndarray, d_n: np.ndarray, d_s: np.ndarray, lam: np.ndarray
                ) -> np.ndarray:
    """Eq. 13, one sample."""
    gain = (1.0 - lam) * (d_n + 0.4) / (1e-7 + d_n ** 2)
    return beta + gain * (d_s - d_n * beta)


@dataclass
class HeightEstimator:
    """Block: `spark_freq` (kHz), `feed_actual` (mm/min) and, when weighting, `abnormal_ratio`
    -> `height_est`, `height_raw` (mm).

    gamma: mm of table travel x mm of height per discharge, identified on a 10-mm cut
    (`calibrate_gamma`). ratio_ref: the abnormal ratio of that cut (None: no pulse-mix
    weighting); on_time, arc_on_time (us): the generator's settings of eq. 3.
    Before the first usable sample (no discharges) the outputs are NaN.
    """
    gamma: float
    ratio_ref: float | None = None
    on_time: float = 0.5
    arc_on_time: float = 0.2
    lam_max: float = 0.999
    lam_min: float = 0.6
    error_scale: float = 0.15
    correct: bool = True

    output_names = ["height_est", "height_raw", "forgetting"]

    def __post_init__(self) -> None:
        self.input_names = ["spark_freq", "feed_actual"] + (
            [] if self.ratio_ref is None else ["abnormal_ratio"])

    def reset(self, batch: int) -> None:
        self.beta = np.full(batch, np.nan)

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        dt = signals["dt"]
        d_n = np.asarray(signals["spark_freq"], float) * 1000.0 * dt
        if self.ratio_ref is not None:
            d_n = d_n * pulse_weight(np.asarray(signals["abnormal_ratio"], float),
                                     self.ratio_ref, self.on_time, self.arc_on_time)
        d_s = np.asarray(signals["feed_actual"], float) / 60.0 * dt
        usable = (d_n >= 1.0) & np.isfinite(d_s)
        ratio = np.where(usable, d_s / np.maximum(d_n, 1.0), np.nan)
        fresh = np.isnan(self.beta)
        with np.errstate(invalid="ignore", divide="ignore"):
            err = np.abs(ratio - self.beta) / np.abs(self.beta)
        lam = self.lam_max - (self.lam_max - self.lam_min) * np.minimum(
            1.0, np.nan_to_num(err / self.error_scale, nan=0.0) ** 2)
        updated = np.where(fresh, ratio, beta_update(self.beta, d_n, d_s, lam))
        self.beta = np.where(usable & (updated > 0), updated, self.beta)
        with np.errstate(invalid="ignore", divide="ignore"):
            raw = self.gamma / self.beta
        height = correction_factor(raw) * raw if self.correct else raw
        return {"height_est": height, "height_raw": raw, "forgetting": lam}


def pulse_weight(ratio, ratio_ref, on_time, arc_on_time):
    """Eq. 3's removal weight of a pulse at abnormal ratio r relative to r_ref (arcs = r/2)."""
    def mix(r):
        return on_time ** 2 * (1 - r) + arc_on_time ** 2 * r / 2
    return mix(np.clip(ratio, 0.0, 1.0)) / mix(ratio_ref)


def calibrate_gamma(spark_freq: np.ndarray, feed_actual: np.ndarray, height: float,
                    ratio: np.ndarray | None = None, on_time: float = 0.5,
                    arc_on_time: float = 0.2) -> tuple[float, float | None]:
    """(gamma, ratio_ref) from a cut of known height (eq. 14 inverted): H sum(dS) / sum(dN).

    spark_freq (kHz), feed_actual (mm/min) and, for the weighted estimator, the abnormal
    ratio over the steady part of the calibration cut; ratio_ref is its mean (None without)."""
    d_n = spark_freq * 1000.0
    ratio_ref = None
    if ratio is not None:
        ratio_ref = float(np.mean(ratio))
        d_n = d_n * pulse_weight(ratio, ratio_ref, on_time, arc_on_time)
    return float(height * np.sum(feed_actual / 60.0) / np.sum(d_n)), ratio_ref
