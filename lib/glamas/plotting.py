"""Shared figure helpers: byte-reproducible PNG and PDF output, the same on every processor (log
scales through :mod:`glamas.portable`), and mean curves with bootstrap bands."""

import zlib
from functools import partial
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt
from matplotlib import patheffects
from matplotlib import scale as mscale
from matplotlib.text import Text
from matplotlib.transforms import ScaledTranslation

from glamas import atomic, portable
from glamas.curves import mean_and_band

# No creation dates, producers or software versions: the same data gives the same bytes.
_PDF_METADATA = {"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None}
_PNG_METADATA = {"Software": None}


class LogTransform(mscale.LogTransform):
    """matplotlib's log transform, computed by :func:`glamas.portable.log_base`: numpy's ``log10``
    differs in the last bit between processors, and a label placed through it moved the bytes of
    a PDF."""

    def transform_non_affine(self, values):
        if np.ma.isMaskedArray(values):
            return np.ma.array(self.transform_non_affine(values.data), mask=values.mask)
        values = np.asarray(values, dtype=np.float64)
        out = portable.log_base(values, self.base)
        if self._clip:
            out[values <= 0] = -1000  # as matplotlib's own clips non-positive values
        return out

    def inverted(self):
        return InvertedLogTransform(self.base)


class InvertedLogTransform(mscale.InvertedLogTransform):
    """matplotlib's inverse log transform, computed by :func:`glamas.portable.power` (autoscaled
    limits of a log axis pass through it)."""

    def transform_non_affine(self, values):
        if np.ma.isMaskedArray(values):
            return np.ma.array(self.transform_non_affine(values.data), mask=values.mask)
        return portable.power(self.base, values)

    def inverted(self):
        return LogTransform(self.base)


class LogScale(mscale.LogScale):
    """matplotlib's ``"log"`` scale with :class:`LogTransform`: registered under matplotlib's own
    name when this module is imported, so that every ``set_xscale("log")`` (a notebook's
    included) draws the same bytes on every processor."""

    def __init__(self, *, base=10, subs=None, nonpositive="clip"):
        super().__init__(base=base, subs=subs, nonpositive=nonpositive)
        self._transform = LogTransform(base, nonpositive)


mscale.register_scale(LogScale)


def save_figure(fig, out_dir, name: str) -> list[Path]:
    """Write ``fig`` as ``name.png`` and ``name.pdf`` in ``out_dir`` without metadata, each
    atomically: a run killed while saving leaves the previous file, not a truncated one."""
    out_dir = Path(out_dir)
    png, pdf = out_dir / f"{name}.png", out_dir / f"{name}.pdf"
    with atomic.locked(out_dir):
        atomic.write(png, partial(fig.savefig, format="png", dpi=150, metadata=_PNG_METADATA))
        atomic.write(pdf, partial(fig.savefig, format="pdf", metadata=_PDF_METADATA))
    return [png, pdf]


LEARNER_STYLES = {
    "independent": {"color": "tab:blue", "marker": "o"},
    "joint_state": {"color": "tab:orange", "marker": "s"},
    "mmdp": {"color": "tab:green", "marker": "^"},
    "two_observe": {"color": "tab:red", "marker": "D", "underneath": True},
    "two_observe_rule": {"color": "tab:brown", "marker": "v"},
    "sparse_maq": {"color": "tab:purple", "marker": "P"},
    "cq": {"color": "tab:gray", "marker": "X"},
}
"""One colour and marker per learner, the same in every figure and notebook. A learner drawn
``underneath`` is drawn first and wide: 2observe's curve lies on the others' in the long run, and
drawn on top it would hide them."""
OTHER_COLOURS = ("tab:olive", "tab:cyan", "tab:pink")
"""Colours of learners without a style of their own (a learner registered later), by name."""


def learner_style(name: str, marker: bool = False) -> dict:
    """Matplotlib style keywords of learner ``name`` (its colour; with ``marker``, its marker too)."""
    style = LEARNER_STYLES.get(name) or {"color": OTHER_COLOURS[zlib.crc32(name.encode()) % len(OTHER_COLOURS)],
                                         "marker": "*"}
    return {"color": style["color"], "marker": style["marker"]} if marker else {"color": style["color"]}


def drawn_underneath(name: str) -> bool:
    """Whether learner ``name``'s curve goes under the others (LEARNER_STYLES)."""
    return LEARNER_STYLES.get(name, {}).get("underneath", False)


def plot_mean_band(ax, x, curves, label: str, **style):
    """Draw the mean of ``curves`` over runs with its 95 % bootstrap band."""
    mean, low, high = mean_and_band(curves)
    line, = ax.plot(x, mean, label=label, **style)
    ax.fill_between(x, low, high, color=line.get_color(), alpha=0.25, linewidth=0)
    return line


def new_figure(width: float = 6.0, height: float = 4.0, **kwargs):
    """A figure of the given size in inches, with constrained layout."""
    return plt.subplots(figsize=(width, height), layout="constrained", **kwargs)


def legend_below(ax, ncols: int = 2, **kwargs):
    """The legend of ``ax`` under its x axis label, outside the data (constrained layout makes
    room for it), so that no curve, band or marker is ever hidden behind it."""
    return ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=ncols, fontsize="small",
                     frameon=False, **kwargs)


def legend_below_figure(ax, ncols: int = 4):
    """One legend for the whole figure of ``ax``, below all its axes, from the entries of ``ax``
    (for panels that draw the same lines)."""
    return ax.figure.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncols=ncols,
                            fontsize="small", frameon=False)


def legend_right(ax, **kwargs):
    """The legend of ``ax`` right of it, outside the data (for legends too long to go below)."""
    return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", frameon=False, **kwargs)


ON_LINES = [patheffects.withStroke(linewidth=2.5, foreground="white")]
"""Path effects of a text drawn where lines pass (a cell's label, a step number): a white outline,
so that a line under the text does not cross it out."""


GREEDY_LABEL = "greedy policy after training, mean over runs"
"""The legend's words for the markers of :func:`mark_greedy`."""


def mark_greedy(ax, x, values, name: str):
    """Learner ``name``'s greedy values (an evaluation of what it learned) at ``x``: diamonds in its
    colour, edged in black; a value beyond the axis' current range is drawn at its edge as a
    triangle, the value written beside it, so that a trapped policy's thousands of steps or
    collisions do not squeeze the curves. Markers of several learners at one ``x`` are set side by
    side (a marker's width apart), so that none hides another, and their written values one under
    the other. Call it once the axis' scale and range are set."""
    low, high = ax.get_ylim()
    placed = ax.__dict__.setdefault("_greedy_placed", {})
    for at, value in zip(np.atleast_1d(x), np.atleast_1d(values)):
        k = placed.get(float(at), 0)
        placed[float(at)] = k + 1
        shown = min(max(float(value), low), high)
        marker = "^" if value > high else "v" if value < low else "D"
        ax.plot(at, shown, linestyle="none", marker=marker, markersize=7, markeredgecolor="black", clip_on=False,
                transform=_shifted(ax, 8 * k), **learner_style(name))
        if shown != value:
            ax.__dict__["_greedy_off_scale"] = True
            written = ax.__dict__.setdefault("_greedy_written", {})
            row = written.get((float(at), marker), 0)
            written[(float(at), marker)] = row + 1
            ax.annotate(f"{value:.3g}", (at, shown), textcoords="offset points", fontsize="x-small",
                        xytext=(6 + 8 * k, -3 - 9 * row if marker == "^" else 3 + 9 * row), **learner_style(name))
    ax.set_ylim(low, high)


def _shifted(ax, points: float):
    """The data transform of ``ax`` moved ``points`` to the right."""
    return ax.transData + ScaledTranslation(points / 72.0, 0.0, ax.figure.dpi_scale_trans)


def greedy_legend_entry(ax):
    """The legend's entries of :func:`mark_greedy`'s markers (one per axes): the diamond, and where
    a value of any axes of the figure lies beyond its axis, the triangle at the edge."""
    ax.plot([], [], linestyle="none", marker="D", color="white", markeredgecolor="black", label=GREEDY_LABEL)
    if any(other.__dict__.get("_greedy_off_scale") for other in ax.figure.axes):
        ax.plot([], [], linestyle="none", marker="^", color="white", markeredgecolor="black",
                label="greedy value off the axis (written beside it)")


def layout_faults(fig) -> list[str]:
    """What a reader would find wrong in ``fig``'s layout, one line each (empty: nothing): a text
    outside the canvas, two texts drawn over each other, a logarithmic axis without tick labels,
    a legend outside the canvas. Texts are every visible, non-empty text of the figure (titles,
    labels, tick labels, legend entries, annotations), measured as drawn (their window extents)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    canvas = fig.bbox.padded(1.0)  # a pixel of rounding
    ticks = _tick_labels(fig)
    texts = [(text, text.get_window_extent(renderer)) for text in fig.findobj(Text)
             if text.get_text().strip() and ticks.get(id(text), _shown(text))]
    faults = [f"text {text.get_text()!r} reaches outside the canvas" for text, box in texts
              if not _inside(box, canvas)]
    for k, (text, box) in enumerate(texts):
        faults += [f"texts {text.get_text()!r} and {other.get_text()!r} overlap" for other, other_box in texts[k + 1:]
                   if _overlap(box, other_box) > OVERLAP_PIXELS]
    for ax in fig.axes:
        for axis, scale in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
            if scale == "log" and axis.get_visible() and ax.get_visible() and ax.axison and not any(
                    ticks.get(id(label)) and label.get_text().strip()
                    for label in axis.get_ticklabels() + axis.get_ticklabels(minor=True)):
                faults.append(f"a logarithmic axis of {ax.get_title()!r} has no tick labels")
        legend = ax.get_legend()
        if legend is not None and not _inside(legend.get_window_extent(renderer), canvas):
            faults.append(f"the legend of {ax.get_title()!r} reaches outside the canvas")
    faults += [f"the figure's legend reaches outside the canvas" for legend in fig.legends
               if not _inside(legend.get_window_extent(renderer), canvas)]
    return faults


OVERLAP_PIXELS = 10.0
"""The area (square pixels at the figure's dpi) two texts may share before they overlap: boxes
touching at an edge are not an overlap a reader sees; a label moved
onto another shares tens of square pixels or more."""


def _shown(text) -> bool:
    """Whether ``text`` (not a tick label) is drawn: it and its axes visible."""
    return text.get_visible() and (text.axes is None or text.axes.get_visible())


def _tick_labels(fig) -> dict:
    """{id of a tick label: whether it is drawn}: a label is drawn when it is visible and its tick
    lies within its axis' view (matplotlib keeps labels of ticks outside the view, undrawn)."""
    drawn = {}
    for ax in fig.axes:
        to_axes = ax.transScale + ax.transLimits  # data to the axes' fraction, on any scale
        corner = (ax.get_xlim()[0], ax.get_ylim()[0])
        for k, axis in enumerate((ax.xaxis, ax.yaxis)):
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                point = list(corner)
                point[k] = tick.get_loc()
                where = to_axes.transform([point])[0][k]
                inside = -1e-6 <= where <= 1 + 1e-6
                for label in (tick.label1, tick.label2):
                    drawn[id(label)] = (inside and label.get_visible() and ax.get_visible() and ax.axison
                                        and axis.get_visible())
    return drawn


def _inside(box, canvas) -> bool:
    return box.x0 >= canvas.x0 and box.y0 >= canvas.y0 and box.x1 <= canvas.x1 and box.y1 <= canvas.y1


def _overlap(a, b) -> float:
    width = min(a.x1, b.x1) - max(a.x0, b.x0)
    height = min(a.y1, b.y1) - max(a.y0, b.y0)
    return width * height if width > 0 and height > 0 else 0.0
