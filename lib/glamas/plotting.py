"""Shared figure helpers: byte-reproducible PNG and PDF output and mean-with-band curves."""

from functools import partial
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from glamas import atomic

# No creation dates, producers or software versions: the same data gives the same bytes.
_PDF_METADATA = {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None}
_PNG_METADATA = {"Software": None}


def save_figure(fig, out_dir, name: str) -> list[Path]:
    """Write ``fig`` as ``name.png`` and ``name.pdf`` in ``out_dir`` without metadata, each
    atomically: a run killed while saving leaves the previous file, not a truncated one."""
    out_dir = Path(out_dir)
    png, pdf = out_dir / f"{name}.png", out_dir / f"{name}.pdf"
    with atomic.locked(out_dir):
        atomic.write(png, partial(fig.savefig, format="png", dpi=150, metadata=_PNG_METADATA))
        atomic.write(pdf, partial(fig.savefig, format="pdf", metadata=_PDF_METADATA))
    return [png, pdf]


def mean_and_band(curves: np.ndarray, z: float = 1.96):
    """Mean over runs (axis 0) and the half-width of its normal-approximation 95 % band."""
    curves = np.asarray(curves, dtype=np.float64)
    n = curves.shape[0]
    mean = curves.mean(axis=0)
    half = z * curves.std(axis=0, ddof=1) / np.sqrt(n) if n > 1 else np.zeros_like(mean)
    return mean, half


def plot_mean_band(ax, x, curves, label: str, **style):
    """Draw the mean of ``curves`` over runs with its 95 % band."""
    mean, half = mean_and_band(curves)
    line, = ax.plot(x, mean, label=label, **style)
    ax.fill_between(x, mean - half, mean + half, color=line.get_color(), alpha=0.25, linewidth=0)
    return line


def new_figure(width: float = 6.0, height: float = 4.0, **kwargs):
    """A figure of the given size in inches, with constrained layout."""
    return plt.subplots(figsize=(width, height), layout="constrained", **kwargs)
