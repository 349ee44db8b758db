"""Self-contained HTML reports of an identification, a prediction or a tracked log.

One HTML file per report, readable offline and safe to mail: every figure is
an embedded PNG (``data:`` URI), the style sheet is inline, and there is no
JavaScript and no external URL. Figures are drawn with matplotlib's Agg
renderer through :class:`matplotlib.figure.Figure` objects (no pyplot, so the
caller's backend and open figures are left alone). matplotlib is imported
only when a report is written: ``import massid`` never needs it.

From Python::

    ident = massid.identify("robot.urdf", "data.csv")
    massid.report.write_identify_report("report.html", ident)
    massid.report.write_predict_report("pred.html", "robot.urdf", "params.json", "holdout.csv")
    massid.report.write_tracking_report("track.html", "tracked.csv")  # compensate --track's CSV

From the shell (the CLI's ``--report`` runs these)::

    python3 -m massid.report identify ROBOT DATA -o REPORT.html [identify options]
    python3 -m massid.report identify ROBOT LOG -o REPORT.html --dynamic [--cutoff HZ]
    python3 -m massid.report predict ROBOT PARAMS DATA -o REPORT.html [--cutoff HZ]
    python3 -m massid.report track TRACKED.csv -o REPORT.html   # compensate --track's output
    python3 -m massid.report --check      # exit 0 when matplotlib is usable

docs/report.md explains what each part shows and how to read it.
"""

from __future__ import annotations

import argparse
import base64
import html
import io
import json
import math
import os
import re
import sys
import warnings
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

import massid
from massid import _massid

AXES = ("fx", "fy", "fz", "mx", "my", "mz")
UNITS = ("N", "N", "N", "N m", "N m", "N m")
DPI = 90
#: Scatter plots show at most about this many samples (every k-th sample).
MAX_SCATTER = 20000
#: Most joints in one residual-against-joint figure (more are split).
JOINTS_PER_FIGURE = 4
#: A base parameter whose std exceeds this fraction of its scale (the robot's
#: M L^k for a parameter in kg m^k: the params file's "scale", report.hpp's
#: kPoorStdOfScale) is poorly determined.
POOR_STD_OF_SCALE = 0.01
#: Without a scale (a URDF without masses): this fraction of |value|.
POOR_RELATIVE_STD = 0.10
MATPLOTLIB_MISSING = "--report needs matplotlib (Debian: apt-get install python3-matplotlib)"

PathType = Union[str, "os.PathLike[str]"]


class MatplotlibMissing(ImportError):
    """matplotlib cannot be imported (the CLI reports it with exit code 2)."""


def _matplotlib() -> Any:
    """Import matplotlib with the Agg canvas; raise MatplotlibMissing if absent."""
    try:
        import matplotlib
        import matplotlib.backends.backend_agg  # the canvas we draw on
        import matplotlib.figure
        import matplotlib.ticker
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise MatplotlibMissing(MATPLOTLIB_MISSING) from e
    return matplotlib


# --------------------------------------------------------------------------
# Formatting


def format_value(v: float) -> str:
    """A parameter value as the report prints it: 6 significant digits ("—" if not identified)."""
    return "—" if v is None or not math.isfinite(v) else f"{v:.6g}"


def format_std(v: float) -> str:
    """A standard deviation as the report prints it: 2 significant digits."""
    return "—" if v is None or not math.isfinite(v) else f"{v:.2g}"


def _fmt(v: float, digits: int = 4) -> str:
    return "—" if v is None or not math.isfinite(float(v)) else f"{float(v):.{digits}g}"


def _e(text: Any) -> str:
    return html.escape(str(text), quote=True)


# Verdicts on the condition number: (good below, fair below, poor below) and
# the sentences, static (eq. 36, first moments from poses) and in motion (the
# column-scaled regressor of a trajectory).
_CONDITION_VERDICTS = {
    False: ((10, 100, 1e4), (
        "good: the poses determine every first moment well",
        "fair: some combinations of first moments are determined less well; check the "
        "relative standard deviations below",
        "poor: the poses hardly separate some parameters; plan a better experiment with "
        "massid design",
        "very poor: some parameters are nearly undetermined; add poses that move every joint "
        "and tilt the platform (massid design)")),
    True: ((30, 300, 1e4), (
        "good: the trajectory excites every base parameter well",
        "fair: some parameters are excited less well; check the relative standard deviations "
        "below",
        "poor: the trajectory hardly separates some parameters; move every joint faster and "
        "over more of its range (massid design --dynamic)",
        "very poor: some parameters are nearly undetermined; use an exciting trajectory "
        "(massid design --dynamic, massid.fourier_trajectory)")),
}


def condition_verdict(cond: float, dynamic: bool = False) -> tuple[str, str]:
    """Plain-language verdict on the condition number: (css class, sentence)."""
    if cond is None or not math.isfinite(cond):
        return "bad", "not available: the data do not determine every parameter"
    limits, sentences = _CONDITION_VERDICTS[dynamic]
    for limit, cls, sentence in zip(limits, ("good", "fair", "bad"), sentences):
        if cond < limit:
            return cls, sentence
    return "bad", sentences[-1]


def chi2_verdict(chi2: float, sigma_estimated: bool) -> tuple[str, str]:
    """Verdict on chi^2 per degree of freedom: (css class, sentence)."""
    if chi2 is None or not math.isfinite(chi2):
        return "fair", "not available"
    if sigma_estimated:
        return "good", "1 by construction: the noise was estimated from the residuals"
    if 0.5 <= chi2 <= 2.0:
        return "good", "consistent with the given sensor noise"
    if chi2 > 2.0:
        return "bad", ("the residuals exceed the given noise: the noise is larger "
                       "than stated, or the model is wrong (frames, signs, units)")
    return "fair", "the residuals are smaller than the given noise: it is overstated"


# --------------------------------------------------------------------------
# Small numerics


def _subsample(n: int, flagged: np.ndarray, limit: int = MAX_SCATTER) -> tuple[np.ndarray, int]:
    """Every k-th sample index (k chosen so that about `limit` remain) plus the flagged ones."""
    k = max(1, math.ceil(n / limit))
    idx = np.arange(0, n, k)
    if k > 1 and flagged.size:
        idx = np.union1d(idx, flagged[: limit // 4])
    return idx, k


def _tilt(gravity: np.ndarray) -> Optional[dict[str, Any]]:
    """Gravity directions in the sensor frame as tilt and azimuth (degrees, radians).

    The reference is the sensor axis (signed) nearest to the mean gravity
    direction, e.g. +z for the PUMA whose sensor z points down when level:
    tilt is the angle from that axis, azimuth the direction of the tilt in the
    plane of the other two axes (from the first towards the second, cyclic:
    x -> y for z, y -> z for x, z -> x for y).
    """
    g = np.asarray(gravity, dtype=float)
    if g.ndim != 2 or g.shape[0] == 0:
        return None
    norm = np.linalg.norm(g, axis=1)
    ok = np.isfinite(norm) & (norm > 0)
    if not ok.any():
        return None
    u = g[ok] / norm[ok, None]
    mean = u.mean(axis=0)
    if np.linalg.norm(mean) < 1e-9:
        mean = u[0]
    mean = mean / np.linalg.norm(mean)
    axis = int(np.argmax(np.abs(mean)))
    sign = 1.0 if mean[axis] >= 0 else -1.0
    a1, a2 = (axis + 1) % 3, (axis + 2) % 3
    tilt = np.degrees(np.arccos(np.clip(sign * u[:, axis], -1.0, 1.0)))
    azimuth = np.arctan2(u[:, a2], u[:, a1])
    names = "xyz"
    return {"tilt": tilt, "azimuth": azimuth, "mean": mean,
            "axis": ("+" if sign > 0 else "-") + names[axis], "a1": names[a1], "a2": names[a2]}


def _correlation_from_covariance(cov: np.ndarray) -> np.ndarray:
    d = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = cov / np.outer(d, d)
    c[~np.isfinite(c)] = np.nan
    return np.clip(c, -1.0, 1.0)


@dataclass
class _JointInfo:
    name: str
    kind: str  # "revolute" / "prismatic" / "" (unknown)
    limited: bool
    lower: float
    upper: float
    velocity_limit: float = math.nan  # the URDF's <limit velocity>, rad/s or m/s; nan if none

    @property
    def scale(self) -> float:
        """Factor from SI (rad, m) to the displayed unit (deg, m)."""
        return 180.0 / math.pi if self.kind != "prismatic" else 1.0

    @property
    def unit(self) -> str:
        return "m" if self.kind == "prismatic" else "deg"


def _joint_infos(model: Any) -> list[_JointInfo]:
    by_name = {j.name: j for j in getattr(model, "joints", [])}
    out = []
    for name in model.joint_names:
        j = by_name.get(name)
        if j is None:
            out.append(_JointInfo(name, "revolute", False, math.nan, math.nan))
        else:
            vmax = float(getattr(j, "velocity_limit", 0.0))
            out.append(_JointInfo(name, str(j.type), bool(j.limited), float(j.lower), float(j.upper),
                                  vmax if vmax > 0 else math.nan))
    return out


# --------------------------------------------------------------------------
# Figures


class _Figures:
    """Draws the report's figures and turns them into data: URIs."""

    def __init__(self) -> None:
        self.mpl = _matplotlib()
        from matplotlib.figure import Figure
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        self._Figure = Figure
        self._Canvas = FigureCanvasAgg
        self.rc = {
            "font.size": 10,
            "axes.titlesize": 10.5,
            "axes.labelsize": 10,
            "xtick.labelsize": 9,
            "ytick.labelsize": 9,
            "legend.fontsize": 9,
            "axes.grid": True,
            "axes.axisbelow": True,
            "grid.alpha": 0.3,
            "axes.spines.top": False,
            "axes.spines.right": False,
        }

    def __enter__(self) -> "_Figures":
        self._rc = self.mpl.rc_context(self.rc)
        self._rc.__enter__()
        return self

    def __exit__(self, *exc: Any) -> None:
        self._rc.__exit__(*exc)

    def new(self, width: float, height: float,
            margins: Optional[tuple[float, float, float, float]] = None) -> Any:
        """A figure, laid out by matplotlib (constrained layout), or with fixed
        margins (left, right, bottom, top in inches): a grid of many axes then
        draws several times faster."""
        if margins is None:
            fig = self._Figure(figsize=(width, height), constrained_layout=True)
        else:
            left, right, bottom, top = margins
            fig = self._Figure(figsize=(width, height))
            fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height,
                                top=1 - top / height, wspace=0.06, hspace=0.1)
        self._Canvas(fig)
        return fig

    def png(self, fig: Any, tight: bool = False) -> str:
        """The figure as a PNG data: URI (tight: crop to the drawn extent, one more draw)."""
        buf = io.BytesIO()
        extra = {"bbox_inches": "tight", "pad_inches": 0.08} if tight else {}
        fig.savefig(buf, format="png", dpi=DPI, facecolor="white", **extra)
        # No pyplot: nothing holds the figure once it is dropped (fig.clear() would only cost time).
        return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")

    # -- wrench plots ----------------------------------------------------

    def measured_vs_model(self, measured: np.ndarray, model: np.ndarray, idx: np.ndarray,
                          rejected: np.ndarray, outlier: np.ndarray, model_label: str) -> str:
        fig = self.new(11.5, 7.0)
        axs = fig.subplots(2, 3)
        for k, ax in enumerate(axs.flat):
            x, y = measured[idx, k], model[idx, k]
            rej, out = rejected[idx], outlier[idx] & ~rejected[idx]
            ok = ~rej
            ax.scatter(x[ok], y[ok], s=_dot_size(idx.size) ** 2, color="C0", alpha=0.6, linewidths=0,
                       label="used" if rejected.any() else "samples", rasterized=True)
            if out.any():
                ax.scatter(x[out], y[out], s=36, facecolors="none", edgecolors="C1",
                           linewidths=1.2, label="outlier")
            if rej.any():
                ax.scatter(x[rej], y[rej], s=30, marker="x", color="C3", linewidths=1.2,
                           label="rejected")
            finite = np.concatenate([x[np.isfinite(x)], y[np.isfinite(y)]])
            if finite.size:
                lo, hi = float(finite.min()), float(finite.max())
                pad = 0.05 * (hi - lo) if hi > lo else max(1e-9, abs(hi) * 0.05 + 1e-9)
                line = [lo - pad, hi + pad]
                ax.plot(line, line, color="0.25", lw=0.8, ls="--", label="y = x", zorder=0)
                ax.set_xlim(line)
                ax.set_ylim(line)
            ax.set_aspect("equal", adjustable="box")
            ax.set_title(AXES[k])
            ax.set_xlabel(f"measured {AXES[k]} [{UNITS[k]}]")
            ax.set_ylabel(f"{model_label} {AXES[k]} [{UNITS[k]}]")
            if k == 0:
                ax.legend(loc="upper left", frameon=False)
        return self.png(fig)

    def against_index(self, values: np.ndarray, idx: np.ndarray, rejected: np.ndarray,
                      outlier: np.ndarray, ylabel: str, sigma: Optional[np.ndarray] = None,
                      zero_line: bool = True, x: Optional[np.ndarray] = None,
                      xlabel: str = "sample index (row of the data, from 0)") -> str:
        """Each axis against the sample index (or against x, e.g. time, when given)."""
        fig = self.new(11.5, 9.0)
        axs = fig.subplots(6, 1, sharex=True)
        xs = (np.asarray(x, dtype=float) if x is not None else np.arange(values.shape[0]))[idx]
        for k, ax in enumerate(axs):
            v = values[idx, k]
            rej, out = rejected[idx], outlier[idx] & ~rejected[idx]
            ok = ~rej
            ax.plot(xs[ok], v[ok], ".", ms=_dot_size(idx.size), color="C0", alpha=0.7, rasterized=True,
                    label="used" if rejected.any() else "samples")
            if out.any():
                ax.plot(xs[out], v[out], "o", ms=6, mfc="none", mec="C1", mew=1.2,
                        label="outlier")
            if rej.any():
                ax.plot(xs[rej], v[rej], "x", ms=5, color="C3", mew=1.2, label="rejected")
            if zero_line:
                ax.axhline(0.0, color="0.3", lw=0.7)
            if sigma is not None and math.isfinite(float(sigma[k])) and sigma[k] > 0:
                for s in (-2.0, 2.0):
                    ax.axhline(s * sigma[k], color="C2", lw=0.8, ls="--",
                               label="±2σ noise" if s > 0 else None)
            ax.set_ylabel(f"{AXES[k]} [{UNITS[k]}]")
            if k == 0:
                ax.set_title(ylabel, loc="left")
                if sigma is not None or outlier.any() or rejected.any():
                    ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=4,
                              frameon=False, borderaxespad=0.2)
        axs[-1].set_xlabel(xlabel)
        return self.png(fig)

    def along_time(self, measured: np.ndarray, model: np.ndarray, x: np.ndarray, idx: np.ndarray,
                   model_label: str, xlabel: str) -> str:
        """Measured and model wrench of each axis along time: two lines per panel."""
        fig = self.new(11.5, 9.5)
        axs = fig.subplots(6, 1, sharex=True)
        xs = np.asarray(x, dtype=float)[idx]
        for k, ax in enumerate(axs):
            ax.plot(xs, measured[idx, k], "-", lw=0.9, color="0.55", label="measured",
                    rasterized=True)
            ax.plot(xs, model[idx, k], "-", lw=0.9, color="C0", alpha=0.85, label=model_label,
                    rasterized=True)
            ax.set_ylabel(f"{AXES[k]} [{UNITS[k]}]")
            if k == 0:
                ax.set_title(f"measured and {model_label} wrench along time", loc="left")
                ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=2, frameon=False,
                          borderaxespad=0.2)
        axs[-1].set_xlabel(xlabel)
        return self.png(fig)

    def spectrum(self, freq: np.ndarray, residual: np.ndarray, measured: Optional[np.ndarray],
                 xlabel: str, residual_label: str, cutoff: Optional[float] = None,
                 sigma_floor: Optional[np.ndarray] = None) -> str:
        """Amplitude spectra per axis (3 x 2 panels, log-log): residual and measured."""
        fig = self.new(11.5, 8.0)
        axs = fig.subplots(3, 2, sharex=True)
        for k in range(6):
            ax = axs[k % 3, k // 3]
            f, r = _envelope(freq, residual[:, k])
            if measured is not None:
                fm, m = _envelope(freq, measured[:, k])
                ax.loglog(fm[1:], np.maximum(m[1:], 1e-300), "-", lw=0.7, color="0.65",
                          label="measured", rasterized=True)
            ax.loglog(f[1:], np.maximum(r[1:], 1e-300), "-", lw=0.8, color="C0",
                      label=residual_label, rasterized=True)
            if sigma_floor is not None and math.isfinite(float(sigma_floor[k])) and sigma_floor[k] > 0:
                ax.axhline(sigma_floor[k], color="C2", lw=0.8, ls="--",
                           label="white noise of σ" if k == 0 else None)
            if cutoff is not None and math.isfinite(cutoff) and freq.size and cutoff <= freq[-1] * 1.001:
                ax.axvline(cutoff, color="C3", lw=0.8, ls=":",
                           label="filter cutoff" if k == 0 else None)
            finite = r[1:][np.isfinite(r[1:]) & (r[1:] > 0)]
            if finite.size:
                lo = max(float(np.percentile(finite, 1)) / 3.0, 1e-300)
                hi = max(float(finite.max()), float(m[1:].max()) if measured is not None and m.size > 1 else 0.0)
                ax.set_ylim(lo, hi * 2.0)
            ax.set_title(AXES[k])
            ax.set_ylabel(f"amplitude [{UNITS[k]}]")
            if k % 3 == 2:
                ax.set_xlabel(xlabel)
            if freq.size > 1:
                ax.set_xlim(freq[1], freq[-1])
            ax.yaxis.set_major_locator(self.mpl.ticker.LogLocator(numticks=6))
            if k == 0:
                ax.legend(loc="lower left", frameon=False)
        return self.png(fig)

    def against_joints(self, values: np.ndarray, q: np.ndarray, joints: Sequence[_JointInfo],
                       idx: np.ndarray, rejected: np.ndarray, outlier: np.ndarray,
                       title: str, velocity: bool = False) -> list[str]:
        """Residuals of each axis (rows) against each joint (columns), split by 4 joints.

        q holds joint positions, or velocities with velocity=True (axis labels in deg/s, m/s)."""
        images = []
        for start in range(0, len(joints), JOINTS_PER_FIGURE):
            chunk = list(range(start, min(start + JOINTS_PER_FIGURE, len(joints))))
            nc = len(chunk)
            # Fixed margins: constrained layout of 24 shared axes took most of the report's time.
            fig = self.new(2.7 * nc + 1.3, 9.5, margins=(0.95, 0.2, 0.6, 0.6))
            axs = np.atleast_2d(fig.subplots(6, nc, sharex="col", sharey="row", squeeze=False))
            for c, j in enumerate(chunk):
                info = joints[j]
                x_all = q[:, j] * info.scale
                x = x_all[idx]
                rej, out = rejected[idx], outlier[idx] & ~rejected[idx]
                for k in range(6):
                    ax = axs[k, c]
                    y = values[idx, k]
                    ax.plot(x[~rej], y[~rej], ".", ms=_dot_size(idx.size), color="C0", alpha=0.6,
                            rasterized=True)
                    if out.any():
                        ax.plot(x[out], y[out], "o", ms=5, mfc="none", mec="C1", mew=1.0)
                    if rej.any():
                        ax.plot(x[rej], y[rej], "x", ms=4, color="C3", mew=1.0)
                    ax.axhline(0.0, color="0.3", lw=0.7)
                    trend = _binned_mean(x_all[~rejected], values[~rejected, k])
                    if trend is not None:
                        ax.plot(trend[0], trend[1], "-", color="C1", lw=1.4)
                    if c == 0:
                        ax.set_ylabel(f"{AXES[k]} [{UNITS[k]}]")
                    if k == 0:
                        ax.set_title(info.name)
                    if k == 5:
                        ax.set_xlabel(f"{info.name} velocity [{info.unit}/s]" if velocity
                                      else f"{info.name} [{info.unit}]")
            fig.suptitle(title + (f" (joints {chunk[0] + 1}–{chunk[-1] + 1} of {len(joints)})"
                                  if len(joints) > JOINTS_PER_FIGURE else ""), fontsize=10)
            images.append(self.png(fig))
        return images

    # -- parameters ------------------------------------------------------

    def correlation(self, corr: np.ndarray, names: Sequence[str]) -> str:
        p = corr.shape[0]
        size = min(max(5.0, 0.45 * p + 2.6), 15.0)
        fig = self.new(size + 1.0, size)
        ax = fig.subplots()
        masked = np.ma.masked_invalid(corr)
        im = ax.imshow(masked, cmap="RdBu_r", vmin=-1.0, vmax=1.0, interpolation="nearest")
        ax.set_xticks(range(p))
        ax.set_yticks(range(p))
        ax.set_xticklabels(names, rotation=90)
        ax.set_yticklabels(names)
        ax.grid(False)
        ax.tick_params(length=0)
        if p <= 20:
            fs = max(6.5, 10.5 - 0.16 * p)
            for i in range(p):
                for j in range(p):
                    v = corr[i, j]
                    if math.isfinite(v):
                        ax.text(j, i, f"{v:.2f}" if abs(v) >= 0.005 else "0", ha="center", va="center", fontsize=fs,
                                color="white" if abs(v) > 0.6 else "0.15")
        fig.colorbar(im, ax=ax, fraction=0.046, pad=0.03, label="correlation")
        ax.set_title("correlation of the estimates")
        return self.png(fig, tight=True)  # constrained layout clips long labels beside imshow

    # -- coverage --------------------------------------------------------

    def joint_coverage(self, q: np.ndarray, joints: Sequence[_JointInfo],
                       derivative: int = 0) -> str:
        """Histograms of each joint's position (derivative 0) against its limits,
        velocity (1) against the URDF's velocity limit, or acceleration (2)."""
        n = len(joints)
        nc = min(4, n)
        nr = math.ceil(n / nc)
        fig = self.new(3.0 * nc + 0.6, 2.5 * nr + 0.3)
        axs = np.atleast_1d(fig.subplots(nr, nc, squeeze=False)).flat
        for j, ax in zip(range(n), axs):
            info = joints[j]
            x = q[:, j] * info.scale
            x = x[np.isfinite(x)]
            limited = info.limited if derivative == 0 else (
                derivative == 1 and math.isfinite(info.velocity_limit))
            if derivative == 1 and limited:
                lo, hi = -info.velocity_limit * info.scale, info.velocity_limit * info.scale
            elif limited and math.isfinite(info.lower) and math.isfinite(info.upper):
                lo, hi = info.lower * info.scale, info.upper * info.scale
            elif x.size:
                lo, hi = float(x.min()), float(x.max())
            else:
                lo, hi = -1.0, 1.0
            rng_lo = min(lo, float(x.min())) if x.size else lo
            rng_hi = max(hi, float(x.max())) if x.size else hi
            if rng_hi <= rng_lo:
                rng_lo, rng_hi = rng_lo - 1.0, rng_hi + 1.0
            ax.hist(x, bins=36, range=(rng_lo, rng_hi), color="C0", alpha=0.85)
            if limited:
                for v in (lo, hi):
                    ax.axvline(v, color="C3", lw=1.0, ls="--")
            if derivative == 1 and limited and x.size:
                peak = float(np.max(np.abs(x))) / hi
                covered = f"\npeaks at {peak * 100:.0f} % of its limit"
            elif derivative == 2 and x.size:
                covered = f"\npeak {float(np.max(np.abs(x))):.3g} {info.unit}/s²"
            else:
                span = (float(x.max() - x.min()) / (hi - lo)) if x.size and hi > lo else math.nan
                covered = f", spans {span * 100:.0f} % of its limits" \
                    if math.isfinite(span) and limited else ""
            ax.set_title(f"{info.name}{covered}")
            ax.set_xlabel([f"{info.name} [{info.unit}]", f"{info.name} velocity [{info.unit}/s]",
                           f"{info.name} acceleration [{info.unit}/s²]"][derivative])
            ax.set_ylabel("samples")
            ax.yaxis.set_major_locator(self.mpl.ticker.MaxNLocator(integer=True))
        for ax in list(axs):
            ax.set_visible(False)
        return self.png(fig)

    def delay_scan(self, scan: np.ndarray, value: float, std: float) -> str:
        fig = self.new(11.0, 3.6)
        ax1, ax2 = fig.subplots(1, 2)
        order = np.argsort(scan[:, 0])
        d, chi2 = scan[order, 0] * 1e3, scan[order, 1]
        best = float(np.min(chi2))
        near = np.zeros(d.size, dtype=bool)
        near[np.argsort(chi2, kind="stable")[:7]] = True  # the fine scan about the best point
        for ax, sel, title in ((ax1, np.ones(d.size, dtype=bool), "whole scan"),
                               (ax2, near, "the best fits")):
            ax.plot(d[sel], chi2[sel] - best, "o-", color="C0", ms=3, lw=1)
            ax.axvline(value * 1e3, color="C3", lw=1.2)
            if std > 0:
                ax.axvspan((value - std) * 1e3, (value + std) * 1e3, color="C3", alpha=0.15, lw=0)
            ax.set_xlabel("delay of the wrench behind the joints [ms]")
            ax.set_ylabel("χ² − its minimum")
            ax.set_title(title)
        return self.png(fig)

    def tilt(self, tilt: Mapping[str, Any], idx: np.ndarray) -> str:
        fig = self.new(11.0, 4.4)
        ax1 = fig.add_subplot(1, 2, 1, projection="polar")
        ax2 = fig.add_subplot(1, 2, 2)
        t, a = tilt["tilt"], tilt["azimuth"]
        sel = idx[idx < t.size]
        ax1.scatter(a[sel], t[sel], s=14, color="C0", alpha=0.6, linewidths=0, rasterized=True)
        # Few distinct directions (a plan of a few tilts): say how many samples share each.
        keys = np.round(np.column_stack([t, np.where(t < 0.05, 0.0, a)]), 2)
        distinct, counts = np.unique(keys, axis=0, return_counts=True)
        if len(distinct) <= 12 and counts.max() > 1:
            for (tt, aa), c in zip(distinct, counts):
                ax1.annotate(f"{c}×", (aa, tt), xytext=(5, 5), textcoords="offset points",
                             fontsize=9, color="C0")
        ax1.set_rlim(0, max(5.0, float(np.nanmax(t)) * 1.1 if t.size else 5.0))
        ax1.set_title(f"gravity direction in the sensor frame: angle from sensor "
                      f"{tilt['axis']} [deg] (radius),\ndirection of the tilt (0° towards +{tilt['a1']}, "
                      f"90° towards +{tilt['a2']})", fontsize=9.5)
        ax1.tick_params(labelsize=7.5)
        top = max(5.0, float(np.nanmax(t)) * 1.05 if t.size else 5.0)
        ax2.hist(t, bins=30, range=(0, top), color="C0", alpha=0.85)
        ax2.yaxis.set_major_locator(self.mpl.ticker.MaxNLocator(integer=True))
        ax2.set_xlabel(f"angle between gravity and sensor {tilt['axis']} [deg]")
        ax2.set_ylabel("samples")
        ax2.set_title("tilt")
        return self.png(fig, tight=True)


def _dot_size(n: int) -> float:
    """Marker size (points) for n plotted samples: bigger when few."""
    return 5.0 if n <= 300 else 3.5 if n <= 3000 else 2.0


def _binned_mean(x: np.ndarray, y: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """Mean of y in bins of x (about 12 samples a bin, 4 to 16 bins); None for few samples."""
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    bins = min(16, x.size // 12)
    if bins < 4 or x.max() <= x.min():
        return None
    edges = np.linspace(x.min(), x.max(), bins + 1)
    which = np.clip(np.digitize(x, edges) - 1, 0, bins - 1)
    count = np.bincount(which, minlength=bins)
    total = np.bincount(which, weights=y, minlength=bins)
    keep = count >= 3
    centres = 0.5 * (edges[:-1] + edges[1:])
    return centres[keep], total[keep] / count[keep]


#: Most points of a spectrum drawn (more are reduced to the largest value per group).
MAX_SPECTRUM_POINTS = 4000


def _envelope(freq: np.ndarray, amp: np.ndarray,
              limit: int = MAX_SPECTRUM_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """A long spectrum reduced for drawing: the largest amplitude of each group of bins
    (peaks stay visible), at the group's first frequency; the DC bin kept first."""
    n = amp.size
    if n <= limit:
        return freq, amp
    k = math.ceil((n - 1) / (limit - 1))
    m = (n - 1) // k
    body = amp[1:1 + m * k].reshape(m, k).max(axis=1)
    return (np.concatenate([freq[:1], freq[1:1 + m * k:k]]), np.concatenate([amp[:1], body]))


def amplitude_spectrum(x: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided amplitude spectrum of each column of x sampled every dt seconds.

    The mean is removed and a Hann window applied; amplitudes are 2|X_k| / sum(w), so
    that a sinusoid of amplitude A shows as a peak of height A. Returns the
    frequencies (Hz; cycles per sample for dt = 1) and [frequencies x columns].
    """
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    n = x.shape[0]
    w = np.hanning(n) if n > 2 else np.ones(n)
    X = np.fft.rfft((x - x.mean(axis=0)) * w[:, None], axis=0)
    return np.fft.rfftfreq(n, dt), 2.0 * np.abs(X) / max(w.sum(), 1e-300)


def white_noise_level(sigma: np.ndarray, n: int) -> np.ndarray:
    """The mean amplitude that amplitude_spectrum gives white noise of standard deviation
    sigma over n samples: sigma sqrt(pi sum(w^2)) / sum(w) (a Rayleigh mean, Hann window)."""
    w = np.hanning(n) if n > 2 else np.ones(n)
    return np.asarray(sigma, dtype=float) * math.sqrt(math.pi * float((w * w).sum())) / max(float(w.sum()), 1e-300)


def _sample_period(t: Optional[np.ndarray]) -> tuple[float, bool, str]:
    """(dt, uniform, unit) of the samples' times: the median step; dt = 1 'sample' without t."""
    if t is None:
        return 1.0, True, "cycles per sample"
    t = np.asarray(t, dtype=float)
    if t.size < 3:
        return 1.0, True, "cycles per sample"
    d = np.diff(t)
    dt = float(np.median(d))
    if not (dt > 0):
        return 1.0, False, "cycles per sample"
    return dt, bool(np.all(np.abs(d - dt) <= 0.01 * dt)), "Hz"


# --------------------------------------------------------------------------
# HTML

_CSS = """
:root{--ink:#1d2330;--muted:#5b6474;--line:#e2e5ea;--bg:#f3f4f6;--card:#fafbfc}
*{box-sizing:border-box}
body{margin:0;background:var(--bg);color:var(--ink);
 font-family:"DejaVu Sans","Segoe UI",Roboto,Helvetica,Arial,sans-serif;font-size:15px;line-height:1.45}
main{max-width:1200px;margin:0 auto;padding:26px 34px 60px;background:#fff;min-height:100vh}
h1{font-size:1.65em;margin:0 0 .15em}
h2{font-size:1.25em;margin:2.2em 0 .6em;padding-bottom:.25em;border-bottom:2px solid var(--line)}
h3{font-size:1.05em;margin:1.4em 0 .4em}
p{margin:.4em 0 .7em}
.sub{color:var(--muted);margin:0 0 1.2em}
.sub span{display:inline-block;margin-right:1.4em;overflow-wrap:anywhere}
nav{font-size:.9em;margin:.6em 0 1.2em;color:var(--muted)}
nav a{color:#0b5cad;text-decoration:none;margin-right:1.1em}
.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(250px,1fr));gap:12px;margin:.8em 0}
.card{border:1px solid var(--line);border-radius:8px;padding:10px 14px;background:var(--card)}
.card .label{font-size:.76em;color:var(--muted);text-transform:uppercase;letter-spacing:.05em}
.card .value{font-size:1.35em;font-weight:600;margin:.1em 0}
.card .note{font-size:.84em;line-height:1.35}
.good{color:#1a7f37}.fair{color:#9a6700}.bad{color:#c62828}
table{border-collapse:collapse;font-size:.88em;margin:.5em 0 1em}
th,td{padding:4px 10px;border-bottom:1px solid var(--line);text-align:right;vertical-align:top}
th{background:#eef0f3;font-weight:600;white-space:nowrap}
.l{text-align:left}
td{white-space:nowrap}td.expr{white-space:normal}
td.mono,.mono{font-family:"DejaVu Sans Mono",Menlo,Consolas,monospace;font-size:.92em}
tr.poor td{background:#fff3cd}
tr.section td{background:#f6f7f9;color:var(--muted);font-weight:600;text-align:left}
.flag{color:#9a6700;font-weight:600}
ul.warnings{padding-left:1.2em}
ul.warnings li{margin:.3em 0;color:#8a3b00}
.ok{color:#1a7f37}
figure{margin:1em 0 1.6em}
figure img{display:block;max-width:100%;height:auto;border:1px solid #edf0f3;margin:0 auto}
figcaption{font-size:.86em;color:var(--muted);margin-top:.4em;max-width:62em}
footer{margin-top:3em;font-size:.8em;color:var(--muted)}
"""


@dataclass
class _Doc:
    title: str
    parts: list[str] = field(default_factory=list)
    images: int = 0

    def add(self, text: str) -> None:
        self.parts.append(text)

    def figure(self, uri: str, alt: str, caption: str) -> None:
        self.images += 1
        self.add(f'<figure><img src="{uri}" alt="{_e(alt)}">'
                 f"<figcaption>{caption}</figcaption></figure>")

    def render(self) -> str:
        return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                "<link rel=\"icon\" href=\"data:,\">\n"
                f"<title>{_e(self.title)}</title>\n<style>{_CSS}</style>\n</head>\n<body>\n<main>\n"
                + "\n".join(self.parts)
                + f"\n<footer>massid {_e(_version())} report. Figures: matplotlib.</footer>\n"
                  "</main>\n</body>\n</html>\n")


def _version() -> str:
    return str(getattr(massid, "__version__", "unknown"))


def _card(label: str, value: str, note: str = "", cls: str = "") -> str:
    c = f' class="note {cls}"' if cls else ' class="note"'
    return (f'<div class="card"><div class="label">{_e(label)}</div>'
            f'<div class="value">{value}</div>'
            + (f"<div{c}>{note}</div>" if note else "") + "</div>")


def _axis_table(rows: Sequence[tuple[str, Sequence[float]]]) -> str:
    head = "".join(f"<th>{a} [{_e(u)}]</th>" for a, u in zip(AXES, UNITS))
    body = "".join(
        f'<tr><td class="l">{_e(label)}</td>' + "".join(f"<td class=\"mono\">{_fmt(v, 4)}</td>" for v in vals)
        + "</tr>" for label, vals in rows)
    return f'<table><tr><th class="l"></th>{head}</tr>{body}</table>'


def _warnings_html(items: Sequence[str]) -> str:
    if not items:
        return '<p class="ok">No warnings.</p>'
    return '<ul class="warnings">' + "".join(f"<li>{_e(w)}</li>" for w in items) + "</ul>"


@dataclass
class _ParamRow:
    name: str
    value: float
    std: float
    unit: str
    expression: str
    judge: bool = True  # offsets and drift terms are not judged (0 is a fine offset)
    scale: float = math.nan  # what the std is judged against (the params file's "scale")


def _param_flags(row: _ParamRow) -> list[str]:
    """Why a parameter is poorly determined (empty: it is not).

    Judged by its std against its scale, M L^k: the part of the robot's gravity
    wrench the parameter can move. A value near zero (a link symmetric about an
    axis) is not a problem when its std is small on that scale.
    """
    v, s = row.value, row.std
    if not math.isfinite(v):
        return ["not identified"]
    if not row.judge or not math.isfinite(s):
        return []
    if math.isfinite(row.scale) and row.scale > 0:
        if abs(s) > POOR_STD_OF_SCALE * row.scale:
            return [f"std {abs(s) / row.scale * 100:.2g} % of the robot's scale "
                    f"{format_value(row.scale)} {row.unit}"]
        return []
    flags = []
    if abs(s) > POOR_RELATIVE_STD * abs(v):
        flags.append(f"std > {POOR_RELATIVE_STD * 100:.0f} % of |value|")
    if abs(v) < 2.0 * abs(s):
        flags.append("within 2 std of 0")
    return flags


def _param_note(row: _ParamRow) -> str:
    """An informative note that is not a flag: a value consistent with zero."""
    if (row.judge and math.isfinite(row.scale) and math.isfinite(row.value)
            and math.isfinite(row.std) and abs(row.value) < 2.0 * abs(row.std)):
        return "0 within 2 std (zero by symmetry?)"
    return ""


def _param_table(groups: Sequence[tuple[str, Sequence[_ParamRow]]]) -> tuple[str, int]:
    """The parameter table; returns (html, number of poorly determined rows)."""
    poor = 0
    out = ['<table class="params"><tr><th class="l">name</th><th>value</th><th>± std</th>'
           '<th>rel. std</th><th class="l">unit</th><th class="l">expression</th>'
           '<th class="l">note</th></tr>']
    for heading, rows in groups:
        if not rows:
            continue
        if heading:
            out.append(f'<tr class="section"><td colspan="7">{_e(heading)}</td></tr>')
        for r in rows:
            flags = _param_flags(r)
            poor += bool(flags)
            note = "; ".join(flags) or _param_note(r)
            rel = (_percent(abs(r.std / r.value) * 100)
                   if math.isfinite(r.value) and math.isfinite(r.std) and r.value != 0 else "—")
            cls = ' class="poor"' if flags else ""
            out.append(
                f'<tr{cls}><td class="l mono">{_e(r.name)}</td>'
                f'<td class="mono">{_e(format_value(r.value))}</td>'
                f'<td class="mono">{_e(format_std(r.std))}</td><td class="mono">{_e(rel)}</td>'
                f'<td class="l">{_e(r.unit)}</td><td class="l mono expr">{_e(r.expression)}</td>'
                f'<td class="l flag">{_e(note)}</td></tr>')
    out.append("</table>")
    return "".join(out), poor


def _percent(v: float) -> str:
    return f"{v:.0f} %" if v >= 100 else f"{v:.2g} %"


def _strong_pairs(corr: np.ndarray, names: Sequence[str], limit: float = 0.9) -> list[str]:
    pairs = []
    p = corr.shape[0]
    for i in range(p):
        for j in range(i + 1, p):
            v = corr[i, j]
            if math.isfinite(v) and abs(v) >= limit:
                pairs.append((abs(v), f"{names[i]} – {names[j]}: {v:+.3f}"))
    pairs.sort(reverse=True)
    shown = [t for _, t in pairs[:8]]
    if len(pairs) > len(shown):
        shown.append(f"and {len(pairs) - len(shown)} more")
    return shown


_NAME_UNIT = re.compile(r"^(.*\S)\s+\[([^\[\]]*)\]$")


def _drift_row(name: str, value: float, std: float, drift: Optional[str]) -> _ParamRow:
    """A drift term; its name may carry the unit ("drift_fx [N/s]")."""
    m = _NAME_UNIT.match(name)
    label, unit = (m.group(1), m.group(2)) if m else (name, _drift_unit(name, drift))
    what = "offset rate" if drift == "linear" else "offset step between blocks" if drift == "per-block" \
        else "drift"
    return _ParamRow(label, value, std, unit, f"{what} ({drift} drift)", judge=False)


def _drift_unit(name: str, drift: Optional[str]) -> str:
    force = any(a in name for a in ("fx", "fy", "fz"))
    moment = any(a in name for a in ("mx", "my", "mz"))
    base = "N" if force and not moment else "N m" if moment and not force else ""
    if not base:
        return ""
    return f"{base}/s" if drift == "linear" else base


def _offset_unit(name: str) -> str:
    return "N m" if any(name.endswith(a) for a in ("mx", "my", "mz")) else "N"


# --------------------------------------------------------------------------
# Sections shared by both reports


def _coverage_section(doc: _Doc, figs: _Figures, q: np.ndarray, joints: Sequence[_JointInfo],
                      gravity: Optional[np.ndarray], n: int, gravity_note: str,
                      qd: Optional[np.ndarray] = None, qdd: Optional[np.ndarray] = None) -> None:
    doc.add('<h2 id="coverage">Coverage of the experiment</h2>')
    if qd is None:
        doc.add("<p>How much of each joint's range the samples visit, and in how many directions "
                "gravity acts on the sensor. Parameters are well determined when the joints "
                "travel over most of their range and gravity comes from several directions "
                "(tilts). Predictions outside what was visited are extrapolations.</p>")
    else:
        doc.add("<p>How much of each joint's range and speed the samples visit, and in how many "
                "directions gravity acts on the sensor. The inertial parameters are determined "
                "by the motion: joints that move fast over most of their range, in every "
                "combination, determine them well. Predictions at speeds or positions outside "
                "what was visited are extrapolations.</p>")
    if joints and q.size:
        doc.figure(figs.joint_coverage(q, joints), "joint position histograms",
                   "Histogram of each joint's position over its range (dashed red: the URDF "
                   "limits; the data range for joints without limits). Revolute joints in "
                   "degrees, prismatic in metres.")
    if qd is not None and joints and qd.size:
        doc.figure(figs.joint_coverage(qd, joints, derivative=1),
                   "joint velocity histograms",
                   "Histogram of each joint's velocity (degrees per second for revolute joints, "
                   "metres per second for prismatic ones); dashed red: the URDF's velocity limit "
                   "(&lt;limit velocity&gt;), where it gives one. Velocities near the limits "
                   "excite the inertial parameters best.")
    if qdd is not None and joints and qdd.size:
        doc.figure(figs.joint_coverage(qdd, joints, derivative=2),
                   "joint acceleration histograms",
                   "Histogram of each joint's acceleration (degrees per second squared for "
                   "revolute joints, metres per second squared for prismatic ones). A URDF "
                   "gives no acceleration limit: compare with the limits the trajectory was "
                   "designed for (massid design --dynamic --acceleration-limit).")
    tilt = _tilt(gravity) if gravity is not None else None
    if tilt is not None:
        idx, k = _subsample(tilt["tilt"].size, np.empty(0, dtype=int))
        m = tilt["mean"]
        spread = float(np.max(tilt["tilt"])) if tilt["tilt"].size else 0.0
        sub = f" One sample in every {k} is shown in the polar plot." if k > 1 else ""
        doc.figure(figs.tilt(tilt, idx), "gravity directions in the sensor frame",
                   f"Gravity direction in the sensor frame{_e(gravity_note)}: its angle from "
                   f"the sensor axis nearest to the mean direction ({m[0]:+.3f}, {m[1]:+.3f}, "
                   f"{m[2]:+.3f}), and which way it is tilted. Largest tilt {spread:.1f}°. "
                   f"Points spread in several directions determine every first moment; a "
                   f"single point means gravity never changed direction, and then the sensor "
                   f"offsets and some first moments cannot be told apart.{sub}")


def _fit_figures(doc: _Doc, figs: _Figures, measured: np.ndarray, model: np.ndarray,
                 residual: np.ndarray, q: np.ndarray, joints: Sequence[_JointInfo],
                 rejected: np.ndarray, outlier: np.ndarray, sigma: Optional[np.ndarray],
                 model_label: str, residual_label: str) -> None:
    n = measured.shape[0]
    flagged = np.flatnonzero(rejected | outlier)
    idx, k = _subsample(n, flagged)
    sub = (f" For legibility one sample in every {k} of the {n} is plotted"
           f"{' (plus the flagged ones)' if flagged.size else ''}." if k > 1 else "")
    marks = " ".join(t for t, on in (("Orange rings: outliers.", (outlier & ~rejected).any()),
                                     ("Red crosses: samples rejected by the robust fit.",
                                      rejected.any())) if on)
    marks = " " + marks if marks else ""
    doc.add(f'<h2 id="fit">{_e(model_label.capitalize())} against measured</h2>')
    doc.figure(figs.measured_vs_model(measured, model, idx, rejected, outlier, model_label),
               f"{model_label} against measured wrench",
               f"Each axis of the wrench: {_e(model_label)} (vertical) against measured "
               f"(horizontal). Points on the dashed line y = x are explained exactly; the "
               f"scatter around it is the residual.{marks}{sub}")
    doc.add(f'<h2 id="residuals">{_e(residual_label.capitalize())}</h2>')
    doc.add("<p>Good residuals look like noise: centred on zero, of even spread, without "
            "trends, steps or curves against the sample index or against any joint. A trend "
            "against time points to sensor drift (<code>--drift</code>, in Python "
            "<code>drift=</code>); a curve against a joint points to a model error (a joint "
            "offset, wrong link frames, a cable); a few isolated large values are outliers "
            "(<code>--robust</code>, in Python <code>robust=True</code>).</p>")
    doc.figure(figs.against_index(residual, idx, rejected, outlier,
                                  f"{residual_label} against sample index", sigma),
               f"{residual_label} against sample index",
               f"{_e(residual_label.capitalize())} of each axis against the sample's row in the "
               f"data{'. Dashed green: ± 2 noise sigma' if sigma is not None else ''}.{marks}{sub}")
    if joints and q.size:
        for uri in figs.against_joints(residual, q, joints, idx, rejected, outlier,
                                       f"{residual_label} against joint positions"):
            doc.figure(uri, f"{residual_label} against joint positions",
                       f"{_e(residual_label.capitalize())} of each axis (rows) against each "
                       f"joint (columns); orange line (with enough samples): the mean in bins "
                       f"over the joint's travel. It should stay flat at zero.{sub}")


def _dynamic_fit_figures(doc: _Doc, figs: _Figures, measured: np.ndarray, model: np.ndarray,
                         residual: np.ndarray, t: Optional[np.ndarray], q: np.ndarray,
                         qd: Optional[np.ndarray], joints: Sequence[_JointInfo],
                         rejected: np.ndarray, outlier: np.ndarray, sigma: Optional[np.ndarray],
                         cutoff: Optional[float], model_label: str, residual_label: str) -> None:
    """The pages of a fit in motion: along time, the residual spectrum, against velocity."""
    n = measured.shape[0]
    flagged = np.flatnonzero(rejected | outlier)
    idx, k = _subsample(n, flagged)
    sub = (f" For legibility one sample in every {k} of the {n} is plotted"
           f"{' (plus the flagged ones)' if flagged.size else ''}." if k > 1 else "")
    marks = " ".join(txt for txt, on in (("Orange rings: outliers.", (outlier & ~rejected).any()),
                                         ("Red crosses: samples rejected by the robust fit.",
                                          rejected.any())) if on)
    marks = " " + marks if marks else ""
    if t is not None:
        x, xlabel = np.asarray(t, dtype=float), "time t [s]"
    else:
        x, xlabel = np.arange(n, dtype=float), "sample index (no column t)"
    order = np.argsort(x[idx], kind="stable")
    line_idx = idx[order]

    doc.add(f'<h2 id="fit">{_e(model_label.capitalize())} and measured along time</h2>')
    doc.figure(figs.along_time(measured, model, x, line_idx, model_label, xlabel),
               f"{model_label} and measured wrench along time",
               f"Each axis of the wrench along {'time (column t)' if t is not None else 'the samples'}: "
               f"measured (grey) and {_e(model_label)} (blue). In motion the wrench is the weight "
               f"plus the inertial forces; where the lines part, the model misses something "
               f"(a time lag between the joint and wrench signals, a cable dragging, a wrong "
               f"frame, a filter cutoff below the motion).{sub}")
    doc.figure(figs.measured_vs_model(measured, model, idx, rejected, outlier, model_label),
               f"{model_label} against measured wrench",
               f"Each axis: {_e(model_label)} (vertical) against measured (horizontal), the line "
               f"y = x dashed.{marks}{sub}")

    doc.add(f'<h2 id="residuals">{_e(residual_label.capitalize())}</h2>')
    doc.add("<p>Good residuals look like noise: centred on zero, of even spread, without "
            "trends against time, without peaks in the spectrum and without curves against "
            "any joint's position or velocity. A slope or steps along time point to sensor "
            "drift (<code>--drift</code>, in Python <code>drift=</code>); peaks in the "
            "spectrum at the trajectory's "
            "frequencies, or a curve against a joint velocity, to motion the model does not "
            "explain: a time lag between the joint and wrench signals, motor rotors spinning "
            "faster than their joints (their inertia is not in the rigid-body model), a cable "
            "dragging, flexible links, wrong frames, a filter cutoff too low. (Friction inside "
            "a joint acts between two measured bodies and does not reach the sensor.)</p>")
    doc.figure(figs.against_index(residual, idx, rejected, outlier,
                                  f"{residual_label} along time", sigma, x=x, xlabel=xlabel),
               f"{residual_label} along time",
               f"{_e(residual_label.capitalize())} of each axis along "
               f"{'time' if t is not None else 'the samples'}"
               f"{'. Dashed green: ± 2 noise sigma' if sigma is not None else ''}.{marks}{sub}")

    dt, uniform, unit = _sample_period(t)
    if n >= 8:
        freq, amp = amplitude_spectrum(residual, dt)
        _, amp_m = amplitude_spectrum(measured, dt)
        floor = white_noise_level(sigma, n) if sigma is not None else None
        doc.add('<h3 id="spectrum">Residual spectrum</h3>')
        note = ("" if uniform else " The samples are not evenly spaced in time (blocks or gaps): "
                "the spectrum treats them as consecutive, at the median step.")
        rate = f"{1.0 / dt:.4g} Hz" if unit == "Hz" else "one per sample"
        doc.figure(figs.spectrum(freq, amp, amp_m, "frequency [Hz]" if unit == "Hz" else "frequency [cycles per sample]",
                                 "residual", cutoff if unit == "Hz" else None, floor),
                   "amplitude spectrum of the residuals",
                   f"Amplitude spectrum of each axis' residual (blue; numpy FFT, mean removed, "
                   f"Hann window: a sine of amplitude A shows as a peak of height A) and of the "
                   f"measured wrench (grey), over the {n} samples at {rate}"
                   f"{' (the rate of the samples kept after decimation)' if cutoff else ''}."
                   + (" Dashed green: the mean level of white noise of the noise sigma."
                      if floor is not None else "")
                   + (" Dotted red: the filter's cutoff." if cutoff and unit == "Hz" else "")
                   + " Noise is flat; peaks that stand above it are motion the model does not "
                   "explain, at the frequencies the measured wrench has them." + note)

    if joints and q.size:
        for uri in figs.against_joints(residual, q, joints, idx, rejected, outlier,
                                       f"{residual_label} against joint positions"):
            doc.figure(uri, f"{residual_label} against joint positions",
                       f"{_e(residual_label.capitalize())} of each axis (rows) against each joint's "
                       f"position (columns); orange line: the mean in bins. It should stay flat at "
                       f"zero.{sub}")
    if joints and qd is not None and qd.size:
        for uri in figs.against_joints(residual, qd, joints, idx, rejected, outlier,
                                       f"{residual_label} against joint velocities", velocity=True):
            doc.figure(uri, f"{residual_label} against joint velocities",
                       f"{_e(residual_label.capitalize())} of each axis (rows) against each joint's "
                       f"velocity (columns); orange line: the mean in bins. It should stay flat at zero; "
                       f"a slope points to a time lag between the joint and wrench signals or to "
                       f"motor rotors, a step at zero velocity to a cable or hose dragging on the "
                       f"mechanism.{sub}")


def _delay_section(doc: _Doc, figs: _Figures, delay: Mapping[str, Any]) -> None:
    """The lag of the wrench behind the joints: the value applied and, when
    estimated, the scan of fits it was read from."""
    value, std = float(delay["value"]), float(delay.get("std", 0.0))
    scan = np.asarray(delay.get("scan") or [], dtype=float).reshape(-1, 2)
    doc.add('<h3 id="delay">Clock alignment</h3>')
    if not delay.get("estimated") or scan.shape[0] < 3:
        doc.add(f"<p>The wrench was taken as lagging the joints by {value * 1e3:.4g} ms (given, "
                f"<code>--delay</code>), applied before the fit.</p>")
        return
    doc.add(f"<p>The wrench lags the joints by <b>{value * 1e3:.4g} ± {std * 1e3:.2g} ms</b> "
            f"(estimated, applied before the fit). A lag of a millisecond between the streams "
            f"already shows as residuals proportional to the joints' accelerations.</p>")
    doc.figure(figs.delay_scan(scan, value, std), "delay scan",
               "The fit's χ² (weighted residual sum, with the noise of the fit at zero delay) "
               "for each delay tried: a coarse scan over the window, then a fine one about its "
               "best point. The estimate (red) is the vertex of the parabola through the best "
               "fits, its std (shaded) from the parabola's curvature, √(2/χ²''). A minimum at "
               "the window's edge would be an error; a flat curve means the motion cannot tell "
               "the lag.")


# --------------------------------------------------------------------------
# Identification report


def _identify_html(ident: Any, title: Optional[str], figs: _Figures) -> str:
    model = ident.model
    name = getattr(model, "name", "robot")
    doc = _Doc(title or f"massid identification — {name}")
    n = int(ident.samples)
    used = np.asarray(ident.used, dtype=bool).reshape(-1)
    if used.size != n:
        used = np.ones(n, dtype=bool)
    rejected = ~used
    outlier = np.zeros(n, dtype=bool)
    outliers = list(ident.outliers)
    for o in outliers:
        if 0 <= int(o.sample) < n:
            outlier[int(o.sample)] = True
    sigma = np.asarray(ident.sigma, dtype=float)
    joints = _joint_infos(model)
    q = np.asarray(ident.q, dtype=float).reshape(n, -1) if n else np.zeros((0, len(joints)))
    dynamic = bool(getattr(ident, "dynamic", False))
    qd = getattr(ident, "qd", None) if dynamic else None
    qd = np.asarray(qd, dtype=float).reshape(n, -1) if qd is not None and n else None
    qdd = getattr(ident, "qdd", None) if dynamic else None
    qdd = np.asarray(qdd, dtype=float).reshape(n, -1) if qdd is not None and n else None
    t = getattr(ident, "time", None)
    t = np.asarray(t, dtype=float).reshape(-1) if t is not None and np.size(t) == n else None
    filt = getattr(ident, "filter", None) if dynamic else None
    motion = _motion_of(ident) if dynamic else {}

    gravity_from = ("the measured force (eq. 37)" if getattr(ident, "gravity_from_force", False)
                    else "the gx, gy, gz columns")
    doc.add(f"<h1>{_e(doc.title)}</h1>")
    doc.add('<p class="sub">'
            f"<span>robot: <b>{_e(name)}</b></span>"
            f"<span>data: <b>{_e(ident.source)}</b></span>"
            f"<span><b>{n}</b> samples"
            + (f" ({int(rejected.sum())} rejected)" if rejected.any() else "") + "</span>"
            f"<span>sensor link: <b>{_e(getattr(model, 'sensor_link', ''))}</b></span>"
            + ("<span>model: <b>dynamic</b> (in motion)</span>" if dynamic else "")
            + f"<span>massid {_e(_version())}</span></p>")
    doc.add('<nav><a href="#summary">summary</a><a href="#fit">fit</a>'
            '<a href="#residuals">residuals</a>'
            + ('<a href="#spectrum">spectrum</a>' if dynamic else "")
            + ('<a href="#delay">delay</a>' if dynamic and getattr(ident, "delay", None) else "")
            + '<a href="#parameters">parameters</a>'
            + ('<a href="#physical">bodies</a>' if getattr(ident, "physical", None) is not None else "")
            + '<a href="#correlation">correlation</a><a href="#coverage">coverage</a></nav>')

    # a) key figures
    cond_cls, cond_text = condition_verdict(float(ident.condition_number), dynamic)
    chi_cls, chi_text = chi2_verdict(float(ident.chi2_per_dof), bool(getattr(ident, "sigma_estimated", True)))
    robust = bool(getattr(ident, "robust", False))
    threshold = float(ident.outlier_threshold)
    outlier_note = ("samples whose residuals are implausible for the noise"
                    + (f" (score d above {_fmt(threshold, 3)})" if threshold > 0 else "")
                    + ("; rejected by the robust fit" if robust and outliers
                       else "; robust fit" if robust else ""))
    mass_known = math.isfinite(float(ident.total_mass))
    cards = [
        _card("total mass", f"{format_value(ident.total_mass)} kg" if mass_known else "not identifiable",
              f"± {_e(format_std(ident.total_mass_std))} kg (one standard deviation)" if mass_known
              else _e("gravity was the same in every sample and the offsets were estimated: the "
                      "weight cannot be told from offset_fz"),
              "" if mass_known else "fair"),
        _card("condition number" + (" (columns scaled)" if dynamic else " (eq. 36)"),
              _e(_fmt(ident.condition_number, 4)), _e(cond_text), cond_cls),
        _card("χ² per degree of freedom", _e(_fmt(ident.chi2_per_dof, 3)), _e(chi_text), chi_cls),
        _card("outliers", str(len(outliers)), _e(outlier_note), "bad" if outliers else "good"),
    ]
    if filt:
        cards.append(_card(
            "derivatives from positions", f"{_fmt(filt['cutoff'], 3)} Hz",
            _e(f"zero-phase low-pass of t and the positions at {_fmt(filt['rate'], 4)} Hz: "
               f"{int(filt['half_width'])} rows dropped at each end, one filtered row in "
               f"{int(filt['decimation'])} kept ({n} of {int(filt['rows'])} rows)")))
    doc.add('<h2 id="summary">Summary</h2>')
    doc.add(f'<div class="cards">{"".join(cards)}</div>')
    doc.add(f"<p>Gravity from {_e(gravity_from)}"
            + ("; sensor offsets estimated" if ident.offset is not None else "")
            + (f"; drift model: {_e(ident.drift)}" if getattr(ident, "drift", None) else "")
            + ".</p>")
    if dynamic:
        level = motion.get("gravity") == "fixed"
        doc.add("<p>Identified in motion: the wrench is the weight plus the inertial forces, "
                "ten parameters per link (mass, first moment, inertia about the link origin), "
                "combined into the base parameters the motion determines. "
                + ("Gravity was the same in every sample (a level platform): some constants "
                   "cannot be told from the offsets. " if level else
                   "Gravity varied between samples. ")
                + ("The sensor frame moved. " if motion.get("sensor_moving") else
                   "The sensor frame was at rest. ")
                + ("Joint velocities and accelerations were derived from the positions by the "
                   "zero-phase filter, which smoothed the wrench alike." if filt else
                   "Joint velocities and accelerations were given (JOINT_vel, JOINT_acc).")
                + "</p>")
    sig_label = "noise sigma (estimated)" if getattr(ident, "sigma_estimated", True) else "noise sigma (given)"
    doc.add(_axis_table([
        (sig_label, sigma),
        ("residual RMS", np.asarray(ident.residual_rms, dtype=float)),
        ("residual max |r|", np.asarray(ident.residual_max, dtype=float)),
        ("measured range", np.ptp(np.asarray(ident.wrench, dtype=float), axis=0) if n else [math.nan] * 6),
    ]))
    doc.add("<h3>Warnings</h3>")
    doc.add(_warnings_html(list(ident.warnings)))
    if outliers:
        doc.add("<h3>Outliers</h3>")
        doc.add("<p>Samples whose standardised residual norm d exceeds the threshold "
                f"{_e(_fmt(threshold, 3))} (clean data exceed it with 1 % "
                "probability over the whole file), worst first"
                + (". They were rejected." if robust
                   else ". Check them, or reject them with --robust (Python: robust=True).") + "</p>")
        rows = sorted(outliers, key=lambda o: -float(o.score))
        shown = rows[:50]
        doc.add('<table class="outliers"><tr><th>line</th><th>sample</th><th>score d</th>'
                '<th class="l">status</th></tr>'
                + "".join(f'<tr><td class="mono">{int(o.line)}</td><td class="mono">{int(o.sample)}</td>'
                          f'<td class="mono">{_fmt(o.score, 4)}</td><td class="l">'
                          f'{"rejected" if 0 <= int(o.sample) < n and rejected[int(o.sample)] else "used"}</td></tr>'
                          for o in shown)
                + "</table>"
                + (f"<p>… and {len(rows) - len(shown)} more.</p>" if len(rows) > len(shown) else ""))

    # b), c)
    if n:
        wrench = np.asarray(ident.wrench, dtype=float).reshape(n, 6)
        fitted = np.asarray(ident.fitted, dtype=float).reshape(n, 6)
        residuals = np.asarray(ident.residuals, dtype=float).reshape(n, 6)
        if dynamic:
            _dynamic_fit_figures(doc, figs, wrench, fitted, residuals, t, q, qd, joints, rejected,
                                 outlier, sigma, float(filt["cutoff"]) if filt else None,
                                 "fitted", "residuals (measured − fitted)")
        else:
            _fit_figures(doc, figs, wrench, fitted, residuals, q, joints, rejected, outlier, sigma,
                         "fitted", "residuals (measured − fitted)")
    delay = getattr(ident, "delay", None) if dynamic else None
    if delay:
        _delay_section(doc, figs, delay)

    # d) parameters
    params = list(ident.base_parameters)
    scales = _scales(json.loads(ident.to_json()))
    groups: list[tuple[str, list[_ParamRow]]] = [
        ("", [_ParamRow(p.name, float(p.value), float(p.std), p.unit, p.expression,
                        scale=scales.get(p.name, math.nan)) for p in params])]
    names = list(ident.unknown_names)
    values = np.asarray(ident.values, dtype=float)
    stds = np.asarray(ident.std, dtype=float)
    extra = [(nm, values[i], stds[i]) for i, nm in enumerate(names)
             if i >= len(params) and i < values.size]
    drift = getattr(ident, "drift", None)
    if extra:
        where = " at the end of the log" if drift else ""
        groups.append(("sensor offsets" + where, [
            _ParamRow(nm, float(v), float(s), _offset_unit(nm), "sensor offset" + where, judge=False)
            for nm, v, s in extra]))
    drift_names = list(getattr(ident, "drift_names", []) or [])
    if drift_names:
        dv = np.asarray(ident.drift_values, dtype=float).reshape(-1)
        ds = np.asarray(ident.drift_std, dtype=float).reshape(-1)
        groups.append((f"drift ({drift})", [
            _drift_row(nm, float(dv[i]), float(ds[i]) if i < ds.size else math.nan, drift)
            for i, nm in enumerate(drift_names) if i < dv.size]))
    _parameter_section(doc, groups, dynamic)
    physical = getattr(ident, "physical", None)
    if physical is not None:
        _physical_section(doc, physical, [p.name for p in ident.base_parameters])

    # e) correlation
    corr = np.asarray(ident.correlation, dtype=float)
    if corr.ndim == 2 and corr.shape[0] == corr.shape[1] and corr.shape[0] > 0:
        labels = names if len(names) == corr.shape[0] else [f"u{i + 1}" for i in range(corr.shape[0])]
        _correlation_section(doc, figs, corr, labels)

    # f) coverage
    gravity = np.asarray(ident.gravity, dtype=float).reshape(n, 3) if n else None
    _coverage_section(doc, figs, q, joints, gravity, n,
                      " (taken along the measured force)" if getattr(ident, "gravity_from_force", False) else "",
                      qd, qdd)
    return doc.render()


def _motion_of(ident: Any) -> dict[str, Any]:
    """The params file's "motion" object of an identification (gravity, sensor_moving)."""
    try:
        m = json.loads(ident.to_json()).get("motion")
    except (AttributeError, ValueError):
        return {}
    return m if isinstance(m, dict) else {}


def _physical_section(doc: _Doc, physical: Any, names: Sequence[str]) -> None:
    """The physically consistent bodies (identify --physical): one row per link with its
    consistency mark, and the base parameters the bodies reproduce only beyond their std."""
    doc.add('<h2 id="physical">Physically consistent bodies</h2>')
    rest = bool(getattr(physical, "static_layout", False))
    doc.add("<p>Ten standard parameters per link that are a real body (mass &gt; 0, positive "
            "semi-definite pseudo-inertia, hence the triangle inequalities), reproduce the base "
            "parameters above and keep the URDF where the data cannot see"
            + (" (at rest: each link's inertia about its centre of mass is the URDF's)" if rest
               else "") + ". Centre of mass in the link frame; principal moments about it.</p>")
    rows = []
    for link in physical.links:
        c = np.asarray(link.com, dtype=float).reshape(3)
        pm = np.asarray(link.principal_moments, dtype=float).reshape(3)
        mark = "✓ real body" if link.consistent else "✗ NOT a real body"
        note = "; no mass in the URDF: tiny prior body" if link.prior_body else ""
        rows.append(f'<tr class="{"" if link.consistent else "poor"}"><td class="l">{_e(link.name)}</td>'
                    f'<td class="mono">{_fmt(link.mass, 5)}</td>'
                    + "".join(f'<td class="mono">{_fmt(v, 4)}</td>' for v in c)
                    + "".join(f'<td class="mono">{_fmt(v, 4)}</td>' for v in pm)
                    + f'<td class="l">{mark} (min eig J {_fmt(link.min_eigenvalue, 2)}){_e(note)}</td></tr>')
    doc.add('<table class="params"><tr><th>link</th><th>m [kg]</th><th>cx [m]</th><th>cy [m]</th>'
            '<th>cz [m]</th><th>I1 [kg m²]</th><th>I2</th><th>I3</th><th>consistency</th></tr>'
            + "".join(rows) + "</table>")
    mismatch = np.asarray(physical.mismatch, dtype=float).reshape(-1)
    beyond = [(names[i], float(mismatch[i])) for i in np.argsort(-np.abs(mismatch))
              if i < len(names) and abs(mismatch[i]) > 1.0]
    worst = int(physical.worst)
    summary = (f"Worst base-parameter mismatch (K π_phys − identified) / std: "
               f"{_e(names[worst]) if 0 <= worst < len(names) else '—'} "
               f"{float(physical.worst_mismatch):+.3g} std. ")
    if beyond:
        summary += ("Beyond their std (the URDF's bodies pull there, or no real bodies reproduce "
                    "the estimate): " + ", ".join(f"{_e(n)} {v:+.2g}" for n, v in beyond[:12])
                    + (" …" if len(beyond) > 12 else "") + ".")
    else:
        summary += "Every base parameter is reproduced within its std."
    doc.add(f"<p>{summary} Solver: {int(physical.iterations)} iterations, "
            f"{float(physical.solve_seconds) * 1e3:.3g} ms"
            f"{'' if physical.converged else ' (not converged)'}.</p>")


def _parameter_section(doc: _Doc, groups: Sequence[tuple[str, Sequence[_ParamRow]]],
                       dynamic: bool = False) -> None:
    table, poor = _param_table(groups)
    doc.add('<h2 id="parameters">Base parameters</h2>')
    rule = (f"A row is highlighted when the parameter is poorly determined: its std exceeds "
            f"{POOR_STD_OF_SCALE * 100:.0f} % of its scale, the robot's total mass M times its "
            "reach L to the power of the parameter's length unit (M for kg, M L for kg m, M L² "
            "for kg m²): the part of the robot's gravity wrench it can move. A combination that "
            "is zero by symmetry is then judged like the others; its note says when 0 lies "
            "within 2 std. ")
    if dynamic:
        doc.add("<p>The combinations of link masses (kg), first moments (kg m) and inertias "
                "(kg m², about each link's origin, in the link frame) that the motion "
                "determines, with one standard deviation. " + rule + "A faster, wider "
                "trajectory that turns the joints in every combination shrinks the std.</p>")
    else:
        doc.add("<p>The combinations of link masses and first moments that a base sensor can "
                "see, with one standard deviation. " + rule + "More poses or tilts that excite "
                "a poorly determined parameter shrink its std.</p>")
    doc.add(table)
    doc.add(f'<p class="{"fair" if poor else "ok"}">'
            + (f"{poor} poorly determined parameter(s)." if poor
               else "Every base parameter is determined to better than "
                    f"{POOR_STD_OF_SCALE * 100:.0f} % of its scale.") + "</p>")


def _correlation_section(doc: _Doc, figs: _Figures, corr: np.ndarray, labels: Sequence[str]) -> None:
    doc.add('<h2 id="correlation">Correlation of the estimates</h2>')
    pairs = _strong_pairs(corr, labels)
    doc.figure(figs.correlation(corr, labels), "correlation matrix of the estimates",
               "Correlation between the estimation errors of each pair of unknowns (red "
               "+1, blue −1). Off-diagonal values near ±1 mean the data barely tell the two "
               "apart: their sum or difference is known better than either. Pale off-diagonal "
               "cells are what a well-designed plan gives.")
    if pairs:
        doc.add("<p>Strongly correlated pairs (|r| ≥ 0.9): "
                + ", ".join(f'<span class="mono">{_e(t)}</span>' for t in pairs) + ".</p>")
    else:
        doc.add('<p class="ok">No pair of estimates is correlated beyond |r| = 0.9.</p>')


def write_identify_report(path: PathType, ident: Any, *, title: Optional[str] = None) -> None:
    """Write the HTML report of an identification.

    Args:
        path: the HTML file to write (atomically: a temporary file in the same
            directory, then renamed).
        ident: a :class:`massid.Identification` (from :func:`massid.identify`).
        title: the page title; default "massid identification — ROBOT".

    Raises:
        MatplotlibMissing: matplotlib is not installed.
        OSError: the file cannot be written.
    """
    with _Figures() as figs:
        text = _identify_html(ident, title, figs)
    _massid._write_file_atomically(path, text)


# --------------------------------------------------------------------------
# Prediction report


def _data_columns(data: Union[PathType, Mapping[str, Any]]) -> tuple[dict[str, np.ndarray], str]:
    if isinstance(data, Mapping):
        return {str(k): np.asarray(v, dtype=float).reshape(-1) for k, v in data.items()}, "(columns)"
    return dict(massid.read_csv(data)), os.fspath(data)


def _joint_matrix(cols: Mapping[str, np.ndarray], joints: Sequence[_JointInfo], n: int) -> np.ndarray:
    q = np.full((n, len(joints)), np.nan)
    for j, info in enumerate(joints):
        if info.name in cols:
            q[:, j] = cols[info.name]
        elif info.name + "_deg" in cols:
            q[:, j] = np.radians(cols[info.name + "_deg"])
    return q


def _params_rows(doc_json: Mapping[str, Any]) -> list[tuple[str, list[_ParamRow]]]:
    scales = _scales(doc_json)
    rows = [_ParamRow(str(p.get("name", "")), _num(p.get("value")), _num(p.get("std")),
                      str(p.get("unit", "")), str(p.get("expression", "")),
                      scale=scales.get(str(p.get("name", "")), math.nan))
            for p in doc_json.get("base_parameters", [])]
    groups: list[tuple[str, list[_ParamRow]]] = [("", rows)]
    drift = doc_json.get("drift") or None
    off = doc_json.get("sensor_offset")
    if isinstance(off, Mapping):
        where = " at the end of the log" if drift else ""
        orows = []
        for part, axes, unit in (("force", AXES[:3], "N"), ("moment", AXES[3:], "N m")):
            vals = list(off.get(part, []) or [])
            stds = list(off.get(part + "_std", []) or [])
            for i, a in enumerate(axes):
                if i < len(vals):
                    orows.append(_ParamRow(f"offset_{a}", _num(vals[i]),
                                           _num(stds[i]) if i < len(stds) else math.nan,
                                           unit, "sensor offset" + where, judge=False))
        groups.append(("sensor offsets" + where, orows))
    if isinstance(drift, Mapping):
        model = drift.get("model")
        groups.append((f"drift ({model})", [
            _drift_row(str(t.get("name", "")), _num(t.get("value")), _num(t.get("std")), model)
            for t in drift.get("terms", [])]))
    return groups


def _scales(doc_json: Mapping[str, Any]) -> dict[str, float]:
    """Each base parameter's scale by name, from a params file's JSON (absent: none)."""
    return {str(p.get("name", "")): _num(p.get("scale"))
            for p in doc_json.get("base_parameters", []) if isinstance(p, Mapping) and "scale" in p}


def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _params_of(params: Any) -> tuple[dict[str, Any], str, Any]:
    """The params JSON, its name and (for an Identification) its model, from whatever
    massid.predict accepts: a params file path, a massid.Params or a massid.Identification."""
    if isinstance(params, (str, os.PathLike)):
        path = os.fspath(params)
        with open(path, encoding="utf-8") as f:
            return json.load(f), path, None
    if isinstance(params, massid.Identification):
        return json.loads(params.to_json()), f"the identification of {params.source}", params.model
    if isinstance(params, massid.Params):
        with open(params.source, encoding="utf-8") as f:
            return json.load(f), params.source, None
    raise massid.InputError("params: expected a params file path, massid.Params or "
                            f"massid.Identification, not {type(params).__name__}")


def _predict_html(robot: Union[PathType, Any, None], params: Any,
                  data: Union[PathType, Mapping[str, Any]], title: Optional[str],
                  figs: _Figures, cutoff: Optional[float] = None,
                  root_gravity: Optional[Sequence[float]] = None,
                  columns: Optional[Mapping[str, str]] = None,
                  level_gravity: Optional[Sequence[float]] = None) -> str:
    motion_args: dict[str, Any] = {"cutoff": cutoff, "root_gravity": root_gravity,
                                   "level_gravity": level_gravity, "columns": columns}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        predicted = np.asarray(massid.predict(robot, params, data, **motion_args), dtype=float)
    warned = [str(w.message) for w in caught]
    pj, params_path, own_model = _params_of(params)
    if robot is None and own_model is not None:
        model = own_model
    elif isinstance(robot, (str, os.PathLike)):
        held = pj.get("held_joints") or None
        model = massid.load_model(robot, sensor=pj.get("sensor_link") or None,
                                  fixed={str(k): float(v) for k, v in held.items()} if held else None)
    else:
        model = robot
    dynamic = pj.get("model") == "dynamic"
    cols, source = _data_columns(data)
    # The columns by the roles massid reads them as (--columns, recorders' spellings).
    roles = massid.column_roles(model, list(cols), columns=columns)
    cols = {(role or f"\0{k}"): v for (k, v), role in zip(cols.items(), roles)}
    n = predicted.shape[0]
    predicted = predicted.reshape(n, 6)
    joints = _joint_infos(model)
    t = qd = qdd = None
    prepared_note = ""
    if dynamic:
        # The samples massid predict compares: derivatives given, or derived by the
        # filter (positions, gravity and wrench smoothed alike; the ends dropped).
        prep = massid.prepare_motion(model, data, decimation=1, **motion_args)
        rows = np.asarray(prep["row"], dtype=int)
        derived = rows.size < n or any(j.name + "_vel" not in cols for j in joints)
        if derived:
            prepared_note = (f" Joint velocities and accelerations derived from t and the "
                             f"positions by the zero-phase low-pass; the {n - rows.size} rows "
                             f"the filter drops at the ends are left out, and the measured "
                             f"wrench is smoothed by the same filter.")
        predicted = predicted[rows]
        cols = {k: np.asarray(v, dtype=float) for k, v in prep.items() if k != "row"}
        n = rows.size
        t = cols.get("t")
        qd = _joint_matrix({k[:-4]: v for k, v in cols.items() if k.endswith("_vel")}, joints, n)
        qdd = _joint_matrix({k[:-4]: v for k, v in cols.items() if k.endswith("_acc")}, joints, n)
    q = _joint_matrix(cols, joints, n)
    has_wrench = all(a in cols for a in AXES)
    if all(c in cols for c in ("gx", "gy", "gz")):
        gravity = np.column_stack([cols["gx"], cols["gy"], cols["gz"]])
        gnote = ""
    elif all(c in cols for c in ("fx", "fy", "fz")):
        f = np.column_stack([cols["fx"], cols["fy"], cols["fz"]])
        gravity = f
        gnote = " (taken along the measured force)"
    else:
        gravity, gnote = None, ""

    name = getattr(model, "name", "robot")
    doc = _Doc(title or f"massid prediction — {name}")
    doc.add(f"<h1>{_e(doc.title)}</h1>")
    doc.add('<p class="sub">'
            f"<span>robot: <b>{_e(name)}</b></span>"
            f"<span>parameters: <b>{_e(params_path)}</b></span>"
            f"<span>data: <b>{_e(source)}</b></span>"
            f"<span><b>{n}</b> samples</span>"
            + ("<span>model: <b>dynamic</b> (in motion)</span>" if dynamic else "")
            + f"<span>massid {_e(_version())}</span></p>")
    doc.add('<nav><a href="#summary">summary</a>'
            + ('<a href="#fit">fit</a><a href="#residuals">compensated wrench</a>' if has_wrench
               else '<a href="#wrench">predicted wrench</a>')
            + '<a href="#parameters">parameters</a><a href="#correlation">correlation</a>'
              '<a href="#coverage">coverage</a></nav>')
    mass_std = next((_num(p.get("std")) for p in pj.get("base_parameters", []) if p.get("name") == "M"),
                    math.nan)
    cond = _num(pj.get("condition_number"))
    cond_cls, cond_text = condition_verdict(cond, dynamic)
    total = _num(pj.get("total_mass"))
    cards = [
        _card("total mass (identified)",
              f"{format_value(total)} kg" if math.isfinite(total) else "not identifiable",
              f"± {_e(format_std(mass_std))} kg, from {_e(pj.get('samples', '?'))} samples"
              if math.isfinite(total) else
              _e("gravity was the same in every sample and the offsets were estimated")),
        _card("condition number" + (" (columns scaled)" if dynamic else " (eq. 36)"), _e(_fmt(cond, 4)),
              _e("of the identification: " + cond_text), cond_cls),
    ]
    comp = None
    if has_wrench:
        measured = np.column_stack([cols[a] for a in AXES])
        # massid.predict is the mechanism's wrench (fx_pred); the compensated
        # wrench also takes away the identified offsets (fx_comp).
        so = pj.get("sensor_offset") or {}
        offset = (np.array(list(so["force"]) + list(so["moment"]), dtype=float)
                  if isinstance(so.get("force"), list) else np.zeros(6))
        comp = measured - predicted - offset
        rms = np.sqrt(np.nanmean(comp ** 2, axis=0))
        rng = np.ptp(measured, axis=0)
        worst = int(np.nanargmax(rms / np.where(rng > 0, rng, np.inf))) if n else 0
        rel = rms[worst] / rng[worst] if rng[worst] > 0 else math.nan
        cards.append(_card("largest RMS error / range", _e(f"{rel * 100:.3g} %") if math.isfinite(rel) else "—",
                           _e(f"axis {AXES[worst]}: the compensated wrench's RMS over the axis' range"),
                           "good" if math.isfinite(rel) and rel < 0.01 else "fair"))
    doc.add('<h2 id="summary">Summary</h2>')
    doc.add(f'<div class="cards">{"".join(cards)}</div>')
    if comp is not None and dynamic:
        doc.add("<p>Compensated wrench = measured − predicted − the identified sensor offsets "
                "(massid predict's fx_comp). The predicted wrench is the mechanism's own in "
                "motion, weight and inertial forces. What remains is noise, the load beyond "
                "the robot itself, and model error." + _e(prepared_note) + "</p>")
    elif comp is not None:
        doc.add("<p>Compensated wrench = measured − predicted − the identified sensor offsets, "
                "if any (massid predict's fx_comp). What remains is noise, the load "
                "beyond the robot's own weight, and model error.</p>")
        doc.add(_axis_table([
            ("RMS of measured − predicted", rms),
            ("max |measured − predicted|", np.nanmax(np.abs(comp), axis=0)),
            ("measured range", rng),
            ("RMS / range [%]", 100 * rms / np.where(rng > 0, rng, np.nan)),
        ]))
    else:
        doc.add("<p>The data have no measured wrench (fx … mz): the report shows the "
                f"predicted {'wrench' if dynamic else 'gravity wrench'} only.</p>")
        doc.add(_axis_table([
            ("predicted min", np.nanmin(predicted, axis=0)),
            ("predicted max", np.nanmax(predicted, axis=0)),
        ]))
    doc.add("<h3>Warnings</h3>")
    doc.add(_warnings_html(warned))

    no_flags = np.zeros(n, dtype=bool)
    if comp is not None and dynamic:
        _dynamic_fit_figures(doc, figs, measured, predicted, comp, t, q, qd, joints, no_flags,
                             no_flags, None, None, "predicted",
                             "compensated wrench (measured − predicted)")
    elif comp is not None:
        _fit_figures(doc, figs, measured, predicted, comp, q, joints, no_flags, no_flags, None,
                     "predicted", "compensated wrench (measured − predicted)")
    elif n:
        idx, k = _subsample(n, np.empty(0, dtype=int))
        sub = f" One sample in every {k} of the {n} is plotted." if k > 1 else ""
        doc.add('<h2 id="wrench">Predicted wrench</h2>')
        if dynamic:
            doc.figure(figs.against_index(predicted, idx, no_flags, no_flags,
                                          "predicted wrench along time", zero_line=False,
                                          x=t, xlabel="time t [s]" if t is not None
                                          else "sample index (row of the data, from 0)"),
                       "predicted wrench along time",
                       f"The wrench in motion (weight and inertial forces) predicted at every "
                       f"sample.{_e(prepared_note)}{sub}")
        else:
            doc.figure(figs.against_index(predicted, idx, no_flags, no_flags,
                                          "predicted gravity wrench against sample index",
                                          zero_line=False),
                       "predicted wrench against sample index",
                       f"The gravity wrench predicted at every row of the data.{sub}")

    _parameter_section(doc, _params_rows(pj), dynamic)
    cov = pj.get("covariance")
    if isinstance(cov, Mapping) and cov.get("matrix"):
        mat = np.asarray(cov["matrix"], dtype=float)
        labels = [str(u) for u in cov.get("unknowns", [])]
        if mat.ndim == 2 and mat.shape[0] == mat.shape[1]:
            if len(labels) != mat.shape[0]:
                labels = [f"u{i + 1}" for i in range(mat.shape[0])]
            _correlation_section(doc, figs, _correlation_from_covariance(mat), labels)
    _coverage_section(doc, figs, q, joints, gravity, n, gnote, qd, qdd)
    return doc.render()


def write_predict_report(path: PathType, robot: Union[PathType, Any, None], params: Any,
                         data: Union[PathType, Mapping[str, Any]], *,
                         title: Optional[str] = None, cutoff: Optional[float] = None,
                         root_gravity: Optional[Sequence[float]] = None,
                         columns: Optional[Mapping[str, str]] = None,
                         level_gravity: Optional[Sequence[float]] = None) -> None:
    """Write the HTML report of a prediction.

    Args:
        path: the HTML file to write (atomically).
        robot: the URDF path or a :class:`massid.Model` (None with an
            Identification: its model). From a path the model is loaded with the
            params file's sensor link and held joints.
        params: what :func:`massid.predict` takes: the params JSON written by
            ``massid identify``, a :class:`massid.Params` or a
            :class:`massid.Identification` (the covariance gives the correlation plot).
        data: a CSV path or a dict of columns: joints (``JOINT`` or ``JOINT_deg``),
            ``gx, gy, gz`` and, if measured, ``fx … mz``. With a measured wrench
            the report compares it with the prediction and shows the compensated
            wrench (measured − predicted); otherwise it shows the prediction.
        title: the page title; default "massid prediction — ROBOT".
        cutoff: dynamic parameters and a log without ``JOINT_vel``/``JOINT_acc``:
            the low-pass cutoff (Hz) that derives them from ``t`` and the positions
            (default min(10, rate/20), as ``massid predict``).
        root_gravity: gravity in the URDF root frame (a sensor below movable joints).
        level_gravity: gravity in the sensor frame with the platform level, which
            ``tilt_x_deg, tilt_y_deg`` turn in data without ``gx, gy, gz``
            (``massid predict --gravity``; default: root_gravity through the fixed
            joints above the sensor link).
        columns: columns of other names read as roles, ``{ROLE: NAME}`` (``massid
            predict --columns``); the recorders' spellings of the wrench are read
            without it.

    With dynamic parameters the report compares the full wrench in motion and
    shows it along time, the spectrum of the compensated wrench and the
    compensated wrench against each joint's velocity.

    Raises:
        massid.InputError: unreadable robot, params or data.
        MatplotlibMissing: matplotlib is not installed.
        OSError: the file cannot be written.
    """
    with _Figures() as figs:
        text = _predict_html(robot, params, data, title, figs, cutoff, root_gravity, columns,
                             level_gravity)
    _massid._write_file_atomically(path, text)


# --------------------------------------------------------------------------
# Report of a tracked log (massid compensate --track)

#: The columns `massid compensate --track` writes after fx_comp..mz_comp (the spec's "Tracking").
TRACK_COLUMNS = ("payload_m", "payload_cx", "payload_cy", "payload_cz", "payload_m_std",
                 "payload_c_std", "payload_ixx", "payload_ixy", "payload_ixz", "payload_iyy",
                 "payload_iyz", "payload_izz", *(f"offset_{a}" for a in AXES), "event")
COMP_COLUMNS = tuple(f"{a}_comp" for a in AXES)
INERTIA_COLUMNS = TRACK_COLUMNS[6:12]
#: The estimates whose truth a log may carry, as an input column ``true_NAME`` that
#: compensate passes through (true_fx_comp..true_mz_comp: the external wrench).
TRUTH_OF = ("payload_m", "payload_cx", "payload_cy", "payload_cz", *INERTIA_COLUMNS,
            *(f"offset_{a}" for a in AXES), *COMP_COLUMNS)
#: Optional std columns of the offsets (drawn as bands when a log has them).
OFFSET_STD_COLUMNS = tuple(f"offset_{a}_std" for a in AXES)
EVENTS = ("", "change", "contact")
#: A tracked log's CSV is converted this many rows at a time (its text held for one block).
CSV_BLOCK_ROWS = 50000
#: A line along time shows at most about this many points (a min/max envelope beyond).
MAX_LINE_POINTS = 8000
_CONTACT_COLOR = "#f4a261"
_CHANGE_COLOR = "#c62828"


@dataclass
class TrackedLog:
    """The columns of a tracked log that its report uses.

    ``values`` holds t, fx_comp..mz_comp, the payload and offset columns, and
    the optional ``true_*`` and ``offset_*_std`` ones, as float arrays (an
    empty field is NaN); ``event`` the event column ("", "change",
    "contact"); ``lines`` each row's line in the file (1-based; the row's
    index + 1 for columns given in memory).
    """
    source: str
    time: str
    values: dict[str, np.ndarray]
    event: np.ndarray
    lines: np.ndarray

    @property
    def t(self) -> np.ndarray:
        return self.values[self.time]

    def __len__(self) -> int:
        return int(self.event.size)

    def truth(self, name: str) -> Optional[np.ndarray]:
        """The true value of an estimate column along the log (None when the log has no
        ``true_NAME`` column, or only empty fields in it)."""
        v = self.values.get("true_" + name)
        return v if v is not None and np.isfinite(v).any() else None


def read_tracked_log(log: Union[PathType, Mapping[str, Any]], time: str = "t") -> TrackedLog:
    """Read what the report of a tracked log needs from ``massid compensate --track``'s output.

    Args:
        log: the CSV (the input's columns, fx_comp..mz_comp, then payload_m .. event),
            or a dict of those columns (``event`` a sequence of strings).
        time: the time column's name (``t``; compensate keeps the input's name).

    Raises:
        massid.InputError: a missing column (named), a field that is not a number
            (file:line:column), an unknown event.
    """
    required = (time, *COMP_COLUMNS, *TRACK_COLUMNS)
    if isinstance(log, Mapping):
        missing = [c for c in required if c not in log]
        if missing:
            raise massid.InputError(f"the tracked log lacks column(s) {', '.join(missing)}: "
                                    "is it the output of massid compensate --track?")
        event = np.asarray([str(e) for e in log["event"]], dtype=object)
        values = {}
        for name, v in log.items():
            if name == "event" or not (name in required or name.startswith("true_")
                                       or name in OFFSET_STD_COLUMNS):
                continue
            values[name] = np.asarray(v, dtype=float).reshape(-1)
            if values[name].size != event.size:
                raise massid.InputError(f"the tracked log's column {name} has {values[name].size} "
                                        f"values, event has {event.size}")
        bad = sorted({e for e in event if e not in EVENTS})
        if bad:
            raise massid.InputError(f"the tracked log's event column holds {bad[0]!r}: expected "
                                    "'', 'change' or 'contact'")
        return TrackedLog("(columns)", time, values, event, np.arange(1, event.size + 1))
    path = os.fspath(log)
    try:
        return _read_tracked_csv(path, time, required)
    except UnicodeDecodeError as e:
        raise massid.InputError(f"{path}: not a UTF-8 text CSV ({e.reason})") from None


def _read_tracked_csv(path: str, time: str, required: Sequence[str]) -> TrackedLog:
    with open(path, encoding="utf-8-sig", newline="") as f:
        header: Optional[list[str]] = None
        header_line = 0
        for header_line, raw in enumerate(f, 1):
            text = raw.strip()
            if text and not text.startswith("#"):
                header = [h.strip() for h in raw.rstrip("\r\n").split(",")]
                break
        if header is None:
            raise massid.InputError(f"{path}: no header line")
        missing = [c for c in required if c not in header]
        if missing:
            raise massid.InputError(f"{path}:{header_line}: no column(s) {', '.join(missing)}: is it "
                                    "the output of massid compensate --track?")
        names = [h for h in header if h != "event" and (h in required or h.startswith("true_")
                                                         or h in OFFSET_STD_COLUMNS)]
        index = [header.index(h) for h in names]
        ev = header.index("event")
        # Parsed in blocks of rows (numpy converts a block's column at once): the rows'
        # text is held for one block only.
        columns: list[list[np.ndarray]] = [[] for _ in names]
        events: list[np.ndarray] = []
        lines: list[np.ndarray] = []
        width = len(header)
        block: list[list[str]] = []
        block_lines: list[int] = []

        def convert() -> None:
            for col, j in zip(columns, index):
                try:  # an empty field: unknown (NaN)
                    col.append(np.array([float(r[j]) if r[j] else math.nan for r in block]))
                except ValueError:  # blanks, or a field that is not a number
                    values = []
                    for r, line_no in zip(block, block_lines):
                        text = r[j].strip()
                        try:
                            values.append(float(text) if text else math.nan)
                        except ValueError:
                            raise massid.InputError(f"{path}:{line_no}:{j + 1}: '{text}' is not a "
                                                    f"number (column {header[j]})") from None
                    col.append(np.array(values))
            e = np.array([r[ev].strip() for r in block], dtype=object)
            bad = np.flatnonzero(~np.isin(e, EVENTS))
            if bad.size:
                raise massid.InputError(f"{path}:{block_lines[bad[0]]}:{ev + 1}: event "
                                        f"'{e[bad[0]]}': expected '', 'change' or 'contact'")
            events.append(e)
            lines.append(np.asarray(block_lines))
            block.clear()
            block_lines.clear()

        for line_no, raw in enumerate(f, header_line + 1):
            text = raw.rstrip("\r\n")
            if not text.strip() or text.lstrip().startswith("#"):
                continue
            fields = text.split(",")
            if len(fields) != width:
                raise massid.InputError(f"{path}:{line_no}: {len(fields)} fields, the header has "
                                        f"{width}")
            block.append(fields)
            block_lines.append(line_no)
            if len(block) == CSV_BLOCK_ROWS:
                convert()
        if block:
            convert()
    if not events:
        raise massid.InputError(f"{path}: no rows after the header")
    values = {name: np.concatenate(col) for name, col in zip(names, columns)}
    event, line = np.concatenate(events), np.concatenate(lines)
    bad_t = np.flatnonzero(~np.isfinite(values[time]))
    if bad_t.size:
        raise massid.InputError(f"{path}:{line[bad_t[0]]}:{header.index(time) + 1}: no time")
    return TrackedLog(path, time, values, event, line)


def contact_episodes(event: Sequence[str]) -> list[tuple[int, int]]:
    """Runs of consecutive ``contact`` rows: (first row, last row), 0-based."""
    flagged = np.asarray([e == "contact" for e in event], dtype=bool)
    if not flagged.any():
        return []
    d = np.diff(np.concatenate(([0], flagged.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(d == 1).tolist(), (np.flatnonzero(d == -1) - 1).tolist()))


def principal_moments(inertia: np.ndarray) -> np.ndarray:
    """[n x 3] principal moments (descending) of rows ixx, ixy, ixz, iyy, iyz, izz; NaN where a
    row is undetermined (an empty field)."""
    inertia = np.asarray(inertia, dtype=float).reshape(-1, 6)
    out = np.full((inertia.shape[0], 3), np.nan)
    ok = np.isfinite(inertia).all(axis=1)
    if ok.any():
        i = inertia[ok]
        m = np.stack([i[:, [0, 1, 2]], i[:, [1, 3, 4]], i[:, [2, 4, 5]]], axis=1)
        out[ok] = np.linalg.eigvalsh(m)[:, ::-1]
    return out


def _envelope_index(y: np.ndarray, limit: int = MAX_LINE_POINTS) -> np.ndarray:
    """Indices of y to draw: all of them, or per block the smallest and the largest (the
    line then looks as the full one does)."""
    n = y.size
    if n <= limit:
        return np.arange(n)
    b = math.ceil(n / (limit // 2))
    m = n // b * b
    blocks = y[:m].reshape(-1, b)
    lo = np.argmin(np.where(np.isnan(blocks), np.inf, blocks), axis=1)
    hi = np.argmax(np.where(np.isnan(blocks), -np.inf, blocks), axis=1)
    base = np.arange(blocks.shape[0]) * b
    return np.unique(np.concatenate((base + lo, base + hi, np.arange(m, n))))


def _event_spans(log: TrackedLog) -> tuple[list[tuple[float, float]], np.ndarray]:
    """Contact spans (time from, to) as drawn, and the change times."""
    t = log.t
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    spans = [(float(t[a]), float(t[b]) + dt) for a, b in contact_episodes(log.event)]
    # Many short spans (noise flagged here and there): merge those closer than 0.1 % of the log.
    if len(spans) > 200:
        gap = 1e-3 * float(t[-1] - t[0])
        merged = [spans[0]]
        for a, b in spans[1:]:
            if a - merged[-1][1] <= gap:
                merged[-1] = (merged[-1][0], b)
            else:
                merged.append((a, b))
        spans = merged
    return spans, t[log.event == "change"]


def _draw_events(ax: Any, events: tuple[list[tuple[float, float]], np.ndarray]) -> None:
    spans, changes = events
    for k, (a, b) in enumerate(spans):
        ax.axvspan(a, b, color=_CONTACT_COLOR, alpha=0.3, lw=0, label="contact" if k == 0 else None)
    for k, tc in enumerate(changes):
        ax.axvline(tc, color=_CHANGE_COLOR, lw=1.0, ls="--", label="change" if k == 0 else None)


def _limits(*arrays: Optional[np.ndarray], pad: float = 0.08) -> Optional[tuple[float, float]]:
    """y limits that hold the finite values of the arrays (not the bands)."""
    v = np.concatenate([np.asarray(a, dtype=float).reshape(-1) for a in arrays if a is not None])
    v = v[np.isfinite(v)]
    if v.size == 0:
        return None
    lo, hi = float(v.min()), float(v.max())
    span = hi - lo if hi > lo else max(abs(hi), 1e-9)
    return lo - pad * span, hi + pad * span


def _error_limit(err: np.ndarray, std: Optional[np.ndarray]) -> Optional[float]:
    """A half-range for an error panel: four times the typical std, or the bulk of the
    errors if larger; the moments right after a change (an error of the whole new load,
    a std of a still undetermined estimate) leave the panel."""
    known = np.isfinite(err)
    e = np.abs(err[known])
    if e.size == 0:
        return None
    lim = 1.5 * float(np.percentile(e, 75))
    if std is not None:
        s = std[known & np.isfinite(std)]
        if s.size:
            lim = max(lim, 4 * float(np.median(s)))
    else:
        lim = max(lim, 1.1 * float(np.percentile(e, 98)))
    return lim if lim > 0 else None


def _estimate_panel(ax: Any, t: np.ndarray, est: np.ndarray, std: Optional[np.ndarray],
                    truth: Optional[np.ndarray], events: Any, label: str, color: str = "C0") -> None:
    """An estimate along time with its ±1 std band and its truth, over the events."""
    _draw_events(ax, events)
    idx = _envelope_index(est)
    if std is not None:
        ax.fill_between(t[idx], (est - std)[idx], (est + std)[idx], color=color, alpha=0.22, lw=0,
                        label="± 1 std", rasterized=True)
    ax.plot(t[idx], est[idx], "-", lw=1.0, color=color, label="estimate", rasterized=True)
    if truth is not None:
        j = _envelope_index(truth)
        ax.plot(t[j], truth[j], "--", lw=1.1, color="k", alpha=0.8, label="truth")
    lim = _limits(est, truth)
    if lim is not None:
        ax.set_ylim(*lim)
    ax.set_ylabel(label)


def _error_panel(ax: Any, t: np.ndarray, err: np.ndarray, std: Optional[np.ndarray], events: Any,
                 label: str) -> None:
    """Estimate − truth with ±1 and ±3 std bands."""
    _draw_events(ax, events)
    idx = _envelope_index(err)
    if std is not None:
        std = np.where(np.isfinite(err), std, np.nan)  # no band where the truth is unknown
        for k, alpha in ((3, 0.12), (1, 0.25)):
            ax.fill_between(t[idx], -k * std[idx], k * std[idx], color="C2", alpha=alpha, lw=0,
                            label=f"± {k} std", rasterized=True)
    ax.plot(t[idx], err[idx], "-", lw=0.9, color="C3", label="estimate − truth", rasterized=True)
    ax.axhline(0.0, color="k", lw=0.6)
    lim = _error_limit(err, std)
    if lim is not None:
        ax.set_ylim(-lim, lim)
    ax.set_ylabel(label)


_TRACK_WIDTH = 11.5
_TRACK_MARGINS = (1.05, 0.2, 0.5, 0.75)  # left, right, bottom, top (title and legend), inches


def _track_figure(figs: _Figures, rows: int, cols: int, height: float, title: str) -> tuple[Any, Any]:
    """A figure of rows x cols time panels (shared time axis) under a title line and a legend
    line: fixed margins, so that the legend never covers a panel."""
    fig = figs.new(_TRACK_WIDTH, height, margins=_TRACK_MARGINS)
    fig.subplots_adjust(wspace=0.4 if cols > 1 else 0.2, hspace=0.12)
    axs = fig.subplots(rows, cols, sharex=True, squeeze=False)
    fig.text(_TRACK_MARGINS[0] / _TRACK_WIDTH, 1 - 0.1 / height, title, ha="left", va="top",
             fontsize=10.5)
    return fig, axs


def _legend(fig: Any, axes: Iterable[Any], xlabel: str) -> None:
    """The time label under the bottom panels; one legend for the figure, on its own line
    under the title (right-aligned)."""
    axes = [ax for ax in axes if ax.get_visible()]
    handles: dict[str, Any] = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    if handles:
        height = fig.get_figheight()
        fig.legend(list(handles.values()), list(handles), loc="upper right",
                   bbox_to_anchor=(1 - _TRACK_MARGINS[1] / _TRACK_WIDTH, 1 - 0.3 / height),
                   ncol=min(len(handles), 8), frameon=False, borderaxespad=0.0)
    bottom = max(ax.get_subplotspec().rowspan.stop for ax in axes) if axes else 0
    for ax in axes:
        if ax.get_subplotspec().rowspan.stop == bottom:
            ax.set_xlabel(xlabel)


def _track_mass_figure(figs: _Figures, log: TrackedLog, events: Any) -> str:
    t, m, s = log.t, log.values["payload_m"], log.values["payload_m_std"]
    truth = log.truth("payload_m")
    fig, axs = _track_figure(figs, 2 if truth is not None else 1, 1,
                             5.6 if truth is not None else 3.4, "payload mass")
    _estimate_panel(axs[0, 0], t, m, s, truth, events, "payload_m [kg]")
    if truth is not None:
        _error_panel(axs[1, 0], t, m - truth, s, events, "payload_m − truth [kg]")
    _legend(fig, axs.flat, f"{log.time} [s]")
    return figs.png(fig)


def _track_com_figure(figs: _Figures, log: TrackedLog, events: Any) -> str:
    t, s = log.t, log.values["payload_c_std"]
    truths = [log.truth(f"payload_c{c}") for c in "xyz"]
    with_truth = any(x is not None for x in truths)
    fig, axs = _track_figure(figs, 3, 2 if with_truth else 1, 7.5,
                             "payload centre of mass in the payload link's frame"
                             + (": estimate (left), estimate − truth (right)" if with_truth else ""))
    for k, c in enumerate("xyz"):
        est = log.values[f"payload_c{c}"]
        _estimate_panel(axs[k, 0], t, est, s, truths[k], events, f"payload_c{c} [m]")
        if with_truth:
            if truths[k] is not None:
                _error_panel(axs[k, 1], t, est - truths[k], s, events, f"c{c} − truth [m]")
            else:
                axs[k, 1].set_visible(False)
    _legend(fig, axs.flat, f"{log.time} [s]")
    return figs.png(fig)


def _track_inertia_figure(figs: _Figures, log: TrackedLog, events: Any,
                          moments: np.ndarray) -> str:
    t = log.t
    truth_cols = [log.values.get("true_" + c) for c in INERTIA_COLUMNS]
    truth = (principal_moments(np.column_stack(truth_cols))
             if all(c is not None for c in truth_cols) else None)
    fig, axs = _track_figure(figs, 1, 1, 3.8, "payload principal moments about its centre of "
                                              "mass, where the tracker wrote the inertia")
    ax = axs[0, 0]
    _draw_events(ax, events)
    for k in range(3):
        idx = _envelope_index(moments[:, k])
        ax.plot(t[idx], moments[idx, k], "-", lw=1.0, color=f"C{k}", label=f"I{k + 1}",
                rasterized=True)
        if truth is not None and np.isfinite(truth[:, k]).any():
            ax.plot(t, truth[:, k], "--", lw=1.1, color=f"C{k}", alpha=0.9,
                    label="truth" if k == 0 else None)
    lim = _limits(moments, truth)
    if lim is not None:
        ax.set_ylim(*lim)
    ax.set_ylabel("principal moment [kg m²]")
    _legend(fig, [ax], f"{log.time} [s]")
    return figs.png(fig)


def _track_offset_figure(figs: _Figures, log: TrackedLog, events: Any, errors: bool) -> str:
    t = log.t
    fig, axs = _track_figure(figs, 2, 3, 5.6, "sensor offsets: estimate − truth" if errors
                             else "sensor offsets")
    for k, a in enumerate(AXES):
        ax = axs.flat[k]
        est = log.values[f"offset_{a}"]
        std = log.values.get(f"offset_{a}_std")
        truth = log.truth(f"offset_{a}")
        if errors:
            if truth is None:
                ax.set_visible(False)
                continue
            _error_panel(ax, t, est - truth, std, events, f"{a} − truth [{UNITS[k]}]")
        else:
            _estimate_panel(ax, t, est, std, truth, events, f"offset_{a} [{UNITS[k]}]")
    _legend(fig, axs.flat, f"{log.time} [s]")
    return figs.png(fig)


def _track_comp_figure(figs: _Figures, log: TrackedLog, events: Any) -> str:
    t = log.t
    fig, axs = _track_figure(figs, 6, 1, 9.5, "compensated wrench: the external wrench "
                                              "(contact) and the noise")
    for k, a in enumerate(AXES):
        ax = axs[k, 0]
        _draw_events(ax, events)
        y = log.values[f"{a}_comp"]
        idx = _envelope_index(y)
        ax.plot(t[idx], y[idx], "-", lw=0.7, color="0.35", label="compensated", rasterized=True)
        truth = log.truth(f"{a}_comp")
        if truth is not None:
            j = _envelope_index(truth)
            ax.plot(t[j], truth[j], "--", lw=1.0, color="C1", label="true external wrench")
        ax.set_ylabel(f"{a}_comp [{UNITS[k]}]")
    _legend(fig, axs.flat, f"{log.time} [s]")
    return figs.png(fig)


@dataclass
class _FinalRow:
    name: str
    unit: str
    value: float
    std: float = math.nan
    truth: float = math.nan


def _final_rows(rows: Sequence[_FinalRow], period: int) -> list[str]:
    body = []
    for r in rows:
        err = r.value - r.truth
        z = err / r.std if math.isfinite(err) and r.std > 0 else math.nan
        body.append(f'<tr id="p{period}-{_e(r.name)}"><td class="l">{_e(r.name)}</td>'
                    f'<td class="mono value">{_fmt(r.value, 6)}</td>'
                    f'<td class="mono std">{_fmt(r.std, 3)}</td>'
                    f'<td class="mono truth">{_fmt(r.truth, 6)}</td>'
                    f'<td class="mono error">{_fmt(err, 3)}</td>'
                    f'<td class="mono z">{_fmt(z, 3)}</td><td class="l">{_e(r.unit)}</td></tr>')
    return body


def payload_periods(event: Sequence[str]) -> list[tuple[int, int, Optional[int]]]:
    """The log cut at its change rows: (first row, end row (excluded), the period's last row
    that is neither change nor contact, or None), 0-based. A period's estimates are read on
    that row: the tracker's last word on a load before the next change (the rows of a run
    before its change are contact)."""
    event = np.asarray(event, dtype=object)
    cuts = [0, *np.flatnonzero(event == "change").tolist(), event.size]
    out = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        free = np.flatnonzero(event[a:b] == "")
        out.append((a, b, int(a + free[-1]) if free.size else None))
    return out


def _count_row(key: str, label: str, value: Any, note: str = "") -> str:
    return (f'<tr id="count-{key}"><td class="l">{_e(label)}</td><td class="mono">{value}</td>'
            f'<td class="l">{note}</td></tr>')


def _tracking_html(log: TrackedLog, title: Optional[str], figs: _Figures) -> str:
    n = len(log)
    t = log.t
    doc = _Doc(title or f"massid tracking — {os.path.basename(log.source)}")
    duration = float(t[-1] - t[0])
    dt, _, unit = _sample_period(t)
    changes = np.flatnonzero(log.event == "change")
    episodes = contact_episodes(log.event)
    contact_rows = int(np.sum(log.event == "contact"))
    last = n - 1
    moments = principal_moments(np.column_stack([log.values[c] for c in INERTIA_COLUMNS]))
    determined = np.isfinite(moments).all(axis=1)

    doc.add(f"<h1>{_e(doc.title)}</h1>")
    doc.add('<p class="sub">'
            f"<span>log: <b>{_e(log.source)}</b></span>"
            f"<span><b>{n}</b> rows, {_fmt(duration, 4)} s"
            + (f" at {_fmt(1 / dt, 4)} Hz" if unit == "Hz" else "") + "</span>"
            f"<span>massid {_e(_version())}</span></p>")
    doc.add('<nav><a href="#summary">summary</a><a href="#events">events</a>'
            '<a href="#mass">mass</a><a href="#com">centre of mass</a>'
            + ('<a href="#inertia">principal moments</a>' if determined.any() else "")
            + '<a href="#offsets">offsets</a><a href="#compensated">compensated wrench</a></nav>')

    # Summary: the final estimates, the events.
    m, ms = float(log.values["payload_m"][last]), float(log.values["payload_m_std"][last])
    true_m = log.truth("payload_m")
    cards = [
        _card("payload mass at the end", f"{_fmt(m, 4)} kg",
              f"± {_e(format_std(ms))} kg (one std)"
              + (f"; truth {_e(_fmt(true_m[last], 4))} kg" if true_m is not None
                 and math.isfinite(true_m[last]) else "")),
        _card("changes", str(changes.size),
              _e("rows where a new payload was detected (grasp, release)")),
        _card("contact rows", str(contact_rows),
              _e(f"in {len(episodes)} episode(s): rows that carry an external wrench and "
                 "teach the tracker nothing"), "fair" if contact_rows else ""),
    ]
    doc.add('<h2 id="summary">Summary</h2>')
    doc.add(f'<div class="cards">{"".join(cards)}</div>')
    inertia_truth = [log.values.get("true_" + c) for c in INERTIA_COLUMNS]
    body = []
    periods = payload_periods(log.event)
    for j, (a, _, r) in enumerate(periods):
        where = "before the first change" if j == 0 else f"from the change at {_fmt(t[a], 6)} s"
        if r is None:
            body.append(f'<tr class="section"><td colspan="7">{_e(where)}: no row without an '
                        "event</td></tr>")
            continue
        body.append(f'<tr class="section"><td colspan="7">{_e(where)}: the estimates on its last '
                    f"free row, t = {_fmt(t[r], 6)} s (line {int(log.lines[r])})</td></tr>")
        rows = [_FinalRow("payload_m", "kg", float(log.values["payload_m"][r]),
                          float(log.values["payload_m_std"][r]), _at(true_m, r))]
        for c in "xyz":
            rows.append(_FinalRow(f"payload_c{c}", "m", float(log.values[f"payload_c{c}"][r]),
                                  float(log.values["payload_c_std"][r]),
                                  _at(log.truth(f"payload_c{c}"), r)))
        if determined[r]:
            tm = (principal_moments(np.column_stack([c[r:r + 1] for c in inertia_truth]))[0]
                  if all(c is not None for c in inertia_truth) else np.full(3, np.nan))
            for k in range(3):
                rows.append(_FinalRow(f"I{k + 1}", "kg m²", float(moments[r, k]), truth=float(tm[k])))
        for k, ax in enumerate(AXES):
            rows.append(_FinalRow(f"offset_{ax}", UNITS[k], float(log.values[f"offset_{ax}"][r]),
                                  _at(log.values.get(f"offset_{ax}_std"), r),
                                  _at(log.truth(f"offset_{ax}"), r)))
        body += _final_rows(rows, j)
    doc.add("<p>The log cut at its change rows into payload periods; each period's estimates "
            "on its last row without an event (the tracker's last word on that load), with "
            "the std the tracker wrote (payload_m_std; payload_c_std, the largest of the three "
            "coordinates'; the offsets' where the log has offset_*_std columns) and the truth "
            "from the log's true_* columns where it has them (docs/report.md). I1 ≥ I2 ≥ I3: "
            "the principal moments, on rows where the inertia is written.</p>")
    doc.add('<table class="final"><tr><th class="l">estimate</th><th>value</th><th>± std</th>'
            '<th>truth</th><th>value − truth</th><th>/ std</th><th class="l">unit</th></tr>'
            + "".join(body) + "</table>")

    # Events.
    doc.add('<h2 id="events">Events</h2>')
    counts = [_count_row("rows", "rows", n),
              _count_row("change", "change rows", changes.size,
                         _e("the payload restarts there, the offsets are kept")),
              _count_row("contact", "contact rows", contact_rows),
              _count_row("episodes", "contact episodes", len(episodes),
                         _e("runs of consecutive contact rows"))]
    true_ext = [log.values.get(f"true_{a}_comp") for a in AXES]
    if all(x is not None for x in true_ext):
        touching = np.any(np.abs(np.column_stack(true_ext)) > 0, axis=1)
        flagged = log.event == "contact"
        counts.append(_count_row("true-contact", "true contact rows flagged",
                                 f"{int(np.sum(flagged & touching))} of {int(touching.sum())}",
                                 _e("rows where the true external wrench is not zero")))
        counts.append(_count_row("free-flagged", "free rows flagged",
                                 f"{int(np.sum(flagged & ~touching))} of {int((~touching).sum())}",
                                 _e("rows without an external wrench, flagged contact")))
    doc.add('<table class="counts">' + "".join(counts) + "</table>")
    def span(a: int, b: int) -> str:
        return str(int(log.lines[a])) if a == b else f"{int(log.lines[a])}–{int(log.lines[b])}"

    listed = sorted([(int(i), int(i), "change") for i in changes[:20]]
                    + [(a, b, "contact") for a, b in episodes[:20]])
    listed = [f'<tr><td class="l">{kind}</td><td class="mono">{_fmt(t[a], 6)}</td>'
              f'<td class="mono">{_fmt(t[b], 6)}</td><td class="mono">{b - a + 1}</td>'
              f'<td class="mono">{span(a, b)}</td></tr>' for a, b, kind in listed]
    if listed:
        doc.add('<table class="events"><tr><th class="l">event</th><th>from [s]</th><th>to [s]</th>'
                '<th>rows</th><th>lines</th></tr>' + "".join(listed) + "</table>")
        if changes.size > 20 or len(episodes) > 20:
            doc.add("<p>(the first 20 changes and contact episodes)</p>")
    doc.add("<p>In every figure below, a change is a red dashed line and contact rows are "
            "shaded orange. The rows of a run before its change is declared are written as "
            "contact (docs/tracking.md): a change comes after a short shaded span.</p>")

    events = _event_spans(log)
    doc.add('<h2 id="mass">Payload mass</h2>')
    doc.figure(_track_mass_figure(figs, log, events), "payload mass along time",
               "The payload's mass with its ± 1 std band (payload_m_std)"
               + (", the truth (dashed) and, below, the error with ± 1 and ± 3 std bands (the "
                  "error panel is cut at the bulk of the errors: the moments around a change "
                  "leave it)" if true_m is not None else "") + ".")
    doc.add('<h2 id="com">Payload centre of mass</h2>')
    doc.figure(_track_com_figure(figs, log, events), "payload centre of mass along time",
               "The centre of mass in the payload link's frame with ± payload_c_std (the largest "
               "std of the three coordinates: a wide band until the motion has turned the "
               "payload). Written as 0 while the mass is not beyond three std.")
    if determined.any():
        doc.add('<h2 id="inertia">Payload principal moments</h2>')
        doc.figure(_track_inertia_figure(figs, log, events, moments),
                   "payload principal moments along time",
                   "The principal moments of the payload's inertia about its centre of mass "
                   "(eigenvalues of payload_ixx..izz, largest first), on the rows where the "
                   "tracker writes them (determined by the motion); the tracker writes no std "
                   "for them.")
    doc.add('<h2 id="offsets">Sensor offsets</h2>')
    has_std = all(c in log.values for c in OFFSET_STD_COLUMNS)
    doc.figure(_track_offset_figure(figs, log, events, errors=False), "sensor offsets along time",
               "The offsets' estimates" + (" with ± 1 std" if has_std else
                                           " (the log has no offset std columns: no band)")
               + (" and their truth (dashed)." if log.truth("offset_fx") is not None else "."))
    if any(log.truth(f"offset_{a}") is not None for a in AXES):
        doc.figure(_track_offset_figure(figs, log, events, errors=True),
                   "offset errors along time",
                   "Offset estimate − truth" + (" with ± 1 and ± 3 std." if has_std else "."))
    doc.add('<h2 id="compensated">Compensated wrench</h2>')
    doc.figure(_track_comp_figure(figs, log, events), "compensated wrench along time",
               "fx_comp..mz_comp: measured − predicted (mechanism and payload) − offset; the "
               "noise in free motion, the external wrench in contact"
               + (" (its truth dashed)." if log.truth("fx_comp") is not None else "."))
    return doc.render()


def _at(v: Optional[np.ndarray], i: int) -> float:
    return float(v[i]) if v is not None else math.nan


def write_tracking_report(path: PathType, log: Union[PathType, Mapping[str, Any]], *,
                          title: Optional[str] = None, time: str = "t",
                          source: Optional[str] = None) -> None:
    """Write the HTML report of a tracked log (``massid compensate --track``'s output).

    Args:
        path: the HTML file to write (atomically).
        log: the tracked log's CSV, or a dict of its columns (``event`` as strings).
            Input columns ``true_NAME`` (NAME one of payload_m, payload_cx..cz,
            payload_ixx..izz, offset_fx..mz, fx_comp..mz_comp), which compensate
            passes through, are drawn as the truth; ``offset_fx_std..offset_mz_std``,
            if present, as the offsets' std bands.
        title: the page title; default "massid tracking — LOG".
        time: the time column's name.
        source: the log's name as the report shows it (default: its path).

    Raises:
        massid.InputError: the log is not a tracked log (a missing column, a bad field).
        MatplotlibMissing: matplotlib is not installed.
        OSError: a file cannot be read or written.
    """
    tracked = read_tracked_log(log, time)
    if source:
        tracked.source = source
    with _Figures() as figs:
        text = _tracking_html(tracked, title, figs)
    _massid._write_file_atomically(path, text)


# --------------------------------------------------------------------------
# Files and the command line


def _parse_fixed(items: Optional[Iterable[str]]) -> Optional[dict[str, float]]:
    if not items:
        return None
    out: dict[str, float] = {}
    for item in items:
        joint, sep, value = item.partition("=")
        if not sep or not joint or not value:
            raise massid.InputError(f"--fixed: '{item}' should read JOINT=VALUE")
        try:
            out[joint] = float(value)
        except ValueError:
            raise massid.InputError(f"--fixed {joint}: '{value}' is not a number") from None
    return out


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python3 -m massid.report",
        description="Write a self-contained HTML report of a massid identification, a prediction or "
                    "a tracked log.")
    p.add_argument("--check", action="store_true",
                   help="only check that matplotlib can be imported (exit 0), then stop")
    sub = p.add_subparsers(dest="command", metavar="{identify,predict,draw-identify,track}")
    ident = sub.add_parser("identify", help="identify, then write the report")
    ident.add_argument("robot", help="URDF file")
    ident.add_argument("data", help="data CSV")
    ident.add_argument("-o", "--output", required=True, help="the HTML report to write")
    ident.add_argument("--sensor", help="sensor link (default: the URDF's root)")
    ident.add_argument("--offset", action="store_true", help="estimate the six sensor offsets")
    ident.add_argument("--fixed", action="append", metavar="JOINT=VALUE",
                       help="a joint held still (repeatable)")
    ident.add_argument("--robust", action="store_true", help="reject outliers")
    ident.add_argument("--drift", choices=("linear", "per-block"), help="sensor drift model")
    ident.add_argument("--sigma-force", type=float, metavar="N", help="force noise, N")
    ident.add_argument("--sigma-moment", type=float, metavar="NM", help="moment noise, N m")
    ident.add_argument("--no-checks", action="store_true", help="skip the set-up checks")
    ident.add_argument("--dynamic", action="store_true",
                       help="identification in motion: ten parameters per link")
    ident.add_argument("--cutoff", type=_positive, metavar="HZ",
                       help="with --dynamic, a log without JOINT_vel/_acc: low-pass cutoff, Hz")
    ident.add_argument("--root-gravity", type=_three_numbers, metavar="GX,GY,GZ",
                       help="with --dynamic: gravity in the URDF root frame (sensor below joints)")
    draw = sub.add_parser("draw-identify",
                          help="the report of a fit `massid identify --report` recorded (the CLI's "
                               "entry: massid.load_identification), without fitting again")
    draw.add_argument("record", help="the identification record the CLI wrote")
    draw.add_argument("-o", "--output", required=True, help="the HTML report to write")
    track = sub.add_parser("track", help="the report of a tracked log (massid compensate --track's "
                                         "output CSV)")
    track.add_argument("log", help="the tracked log CSV")
    track.add_argument("-o", "--output", required=True, help="the HTML report to write")
    track.add_argument("--time", default="t", metavar="NAME", help="the time column (default t)")
    track.add_argument("--title", help="the page title")
    track.add_argument("--source", metavar="NAME", help="the log's name as the report shows it")
    pred = sub.add_parser("predict", help="predict, then write the report")
    pred.add_argument("robot", help="URDF file")
    pred.add_argument("params", help="params JSON from massid identify")
    pred.add_argument("data", help="data CSV")
    pred.add_argument("-o", "--output", required=True, help="the HTML report to write")
    pred.add_argument("--cutoff", type=_positive, metavar="HZ",
                      help="dynamic params, a log without JOINT_vel/_acc: low-pass cutoff, Hz")
    pred.add_argument("--root-gravity", type=_three_numbers, metavar="GX,GY,GZ",
                      help="gravity in the URDF root frame (sensor below movable joints)")
    pred.add_argument("--gravity", type=_three_numbers, metavar="GX,GY,GZ",
                      help="gravity in the sensor frame with the platform level, which the "
                           "tilt_x_deg,tilt_y_deg columns turn")
    pred.add_argument("--columns", action="append", metavar="ROLE=NAME,...",
                      help="read columns of other names as roles (repeatable)")
    return p


def _parse_columns(items: Optional[Iterable[str]]) -> Optional[dict[str, str]]:
    if not items:
        return None
    out: dict[str, str] = {}
    for item in items:
        for pair in item.split(","):
            role, sep, name = pair.partition("=")
            if not sep or not role or not name:
                raise massid.InputError(f"--columns: '{pair}' should read ROLE=NAME")
            if role in out:
                raise massid.InputError(f"--columns: role '{role}' is bound twice")
            out[role] = name
    return out


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (v > 0 and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"'{text}' is not a positive number")
    return v


def _three_numbers(text: str) -> list[float]:
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"'{text}' should read gx,gy,gz (three numbers)")
    return values


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command-line entry (``python3 -m massid.report``); returns the exit code.

    Exit codes as the CLI's: 0 written, 2 bad input or no matplotlib, 3 data
    that cannot determine the parameters. Errors go to stderr as
    "massid: error: ..."; the fit's warnings go into the report only.
    """
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        if args.check:
            _matplotlib()
            return 0
        if args.command is None:
            parser.error("a command is needed: identify, predict or track (or --check)")
        _matplotlib()  # fail before any work when it is missing
        # The fit's warnings are listed in the report; the CLI that spawns this
        # has printed them already, so they are not printed twice.
        warnings.filterwarnings("ignore", category=getattr(massid, "MassidWarning", UserWarning))
        if args.command == "identify":
            motion = ({"dynamic": True, "cutoff": args.cutoff, "root_gravity": args.root_gravity}
                      if args.dynamic else {})
            if not args.dynamic and (args.cutoff is not None or args.root_gravity is not None):
                raise massid.InputError("--cutoff and --root-gravity go with --dynamic")
            ident = massid.identify(
                args.robot, args.data, offset=args.offset, sensor=args.sensor,
                fixed=_parse_fixed(args.fixed), robust=args.robust, drift=args.drift,
                sigma_force=args.sigma_force, sigma_moment=args.sigma_moment,
                checks=not args.no_checks, **motion)
            write_identify_report(args.output, ident)
        elif args.command == "track":
            write_tracking_report(args.output, args.log, title=args.title, time=args.time,
                                  source=args.source)
        elif args.command == "draw-identify":
            write_identify_report(args.output, massid.load_identification(args.record))
        else:
            write_predict_report(args.output, args.robot, args.params, args.data,
                                 cutoff=args.cutoff, root_gravity=args.root_gravity,
                                 columns=_parse_columns(args.columns),
                                 level_gravity=args.gravity)
    except MatplotlibMissing:
        print(f"massid: error: {MATPLOTLIB_MISSING}", file=sys.stderr)
        return 2
    except massid.IdentifiabilityError as e:
        print(f"massid: error: {e}", file=sys.stderr)
        return 3
    except massid.InputError as e:
        print(f"massid: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        where = f"{e.filename}: " if getattr(e, "filename", None) else ""
        print(f"massid: error: {where}{e.strerror or e}", file=sys.stderr)
        return 2
    except json.JSONDecodeError as e:
        print(f"massid: error: {args.params}:{e.lineno}:{e.colno}: {e.msg}", file=sys.stderr)
        return 2
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
