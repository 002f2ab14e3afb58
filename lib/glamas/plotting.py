"""Shared figure helpers: byte-reproducible PNG and PDF output, the same on every processor (log
scales through :mod:`glamas.portable`), and mean curves with bootstrap bands."""

import re
import zlib
from functools import partial
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt
from matplotlib import patheffects
from matplotlib import scale as mscale
from matplotlib.collections import PathCollection
from matplotlib.text import Text
from matplotlib.transforms import BlendedAffine2D, BlendedGenericTransform, ScaledTranslation

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
    side (a marker's width apart), so that none hides another, and their written values in rows
    inside the axes, clear of the markers and the frame: under a triangle at the top, beside one at
    the bottom, on the side of the axes' middle. Call it once the axis' scale and range are set."""
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
            left_half = (ax.transScale + ax.transLimits).transform([(at, shown)])[0][0] < 0.5
            if marker == "^":  # under the markers, inside the axes, ending at the first marker's outer edge
                where = {"xytext": (-4 if left_half else 4, -7 - 9 * row), "va": "top",
                         "ha": "left" if left_half else "right"}
            else:  # beside its marker, inside the axes, on the side of the axes' middle
                where = {"xytext": (6 + 8 * k if left_half else -6, 5 + 9 * row),
                         "ha": "left" if left_half else "right"}
            ax.annotate(_written(value), (at, shown), textcoords="offset points", fontsize="x-small",
                        path_effects=ON_LINES, **where, **learner_style(name))
    ax.set_ylim(low, high)


def _written(value: float) -> str:
    """A value as a reader reads it: whole thousands with separators (9,534), smaller ones to three
    significant digits (99.5, 0.213)."""
    return f"{value:,.0f}" if abs(value) >= 1000 else f"{value:.3g}"


def _shifted(ax, points: float):
    """The data transform of ``ax`` moved ``points`` to the right."""
    return ax.transData + ScaledTranslation(points / 72.0, 0.0, ax.figure.dpi_scale_trans)


def greedy_legend_entry(ax):
    """The legend's entries of :func:`mark_greedy`'s markers (one per axes): the diamond, and where
    a value of any axes of the figure lies beyond its axis, the triangle at the edge."""
    ax.plot([], [], linestyle="none", marker="D", color="white", markeredgecolor="black", label=GREEDY_LABEL)
    if any(other.__dict__.get("_greedy_off_scale") for other in ax.figure.axes):
        ax.plot([], [], linestyle="none", marker="^", color="white", markeredgecolor="black",
                label="greedy value off the axis (written by it)")


def layout_faults(fig) -> list[str]:
    """What a reader would find wrong in ``fig``'s layout, one line each (empty: nothing): a text
    outside the canvas, two texts drawn over each other, a text over a marker or cut by its axes'
    frame, a configuration token in a text (:func:`_configuration_tokens`), a logarithmic axis
    without tick labels, a legend outside the canvas, an axis stretched by a few off-scale points
    (:func:`_squeezed`), plotted values an axis of few of them does not label
    (:func:`_unlabelled_values`), a point outside its data's bounds (:func:`data_bounds`), and the
    level of a claim the figure shows (:func:`shows_claims`) not drawn. Texts are every visible,
    non-empty text of the figure (titles, labels, tick labels, legend entries, annotations),
    measured as drawn (their window extents)."""
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
    faults += _texts_on_markers(fig, texts) + _texts_cut_by_frames(fig, texts)
    faults += _configuration_tokens(fig, texts)
    for ax in fig.axes:
        for axis, scale in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
            if scale == "log" and axis.get_visible() and ax.get_visible() and ax.axison and not any(
                    ticks.get(id(label)) and label.get_text().strip()
                    for label in axis.get_ticklabels() + axis.get_ticklabels(minor=True)):
                faults.append(f"a logarithmic axis of {ax.get_title()!r} has no tick labels")
        legend = ax.get_legend()
        if legend is not None and not _inside(legend.get_window_extent(renderer), canvas):
            faults.append(f"the legend of {ax.get_title()!r} reaches outside the canvas")
        if ax.get_visible() and ax.axison:
            faults += _squeezed(ax) + _unlabelled_values(ax, ticks) + _out_of_bounds(ax)
    faults += ["the figure's legend reaches outside the canvas" for legend in fig.legends
               if not _inside(legend.get_window_extent(renderer), canvas)]
    faults += _claim_levels_missing(fig)
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


SQUEEZED = 0.25
"""An axis is stretched when a few off-scale points (at most OFF_SCALE_POINTS, set apart from the
rest by an empty stretch of at least this share of the axis) leave the rest of the data less than
this share of it (:func:`_squeezed`)."""
OFF_SCALE_POINTS = 2
"""The most points :func:`_squeezed` takes as off-scale (one in fifty where there are more)."""
SQUEEZED_POINTS = 8
"""The fewest points (distinct places) :func:`_squeezed` finds squeezed: a few points far apart
(a learner's reward far below four others') are what the data say, not a range stretched."""


def _squeezed(ax) -> list[str]:
    """Each axis of ``ax`` whose range a few off-scale points set, squeezing the rest of its data
    points (every line's points in data coordinates, reference lines across the axes left out; at
    least SQUEEZED_POINTS places) into under SQUEEZED of it: a value far off the scale belongs at
    the axis' edge, marked as off it (:func:`mark_greedy`), not inside a range it alone sets."""
    faults = []
    points = _data_points(ax)
    for k, name in enumerate("xy"):
        inside = points[(np.abs(points[:, 1 - k] - 0.5) <= 0.5) & (np.abs(points[:, k] - 0.5) <= 0.52)]
        at = np.unique(np.round(inside[:, k], 4))
        most = max(OFF_SCALE_POINTS, at.size // 50)
        for high in range(most + 1):
            for low in range(most + 1 - high):
                rest = at[low:at.size - high]
                if not 0 < high + low or rest.size < SQUEEZED_POINTS or rest[-1] - rest[0] >= SQUEEZED:
                    continue
                if ((not high or at[at.size - high] - rest[-1] >= SQUEEZED)
                        and (not low or rest[0] - at[low - 1] >= SQUEEZED)):
                    faults.append(f"the {name} axis of {ax.get_title()!r} is stretched by {high + low} off-scale "
                                  f"point(s): the rest of its data fill {rest[-1] - rest[0]:.0%} of it")
                    break
            else:
                continue
            break
    return faults


def _data_points(ax) -> np.ndarray:
    """(n, 2) positions, as fractions of ``ax``'s width and height, of the points of every visible
    line of ``ax`` drawn in data coordinates (shifted or not), and of its scatter points;
    reference lines across the axes (axhline, axvline) are not data."""
    to_axes = ax.transAxes.inverted()
    found = [np.empty((0, 2))] + [to_axes.transform(line.get_transform().transform(line.get_xydata()))
                                  for line in _data_lines(ax)]
    for collection in ax.collections:
        if isinstance(collection, PathCollection) and collection.get_visible() and len(collection.get_offsets()):
            offsets = np.asarray(collection.get_offsets(), dtype=float)
            found.append(to_axes.transform(collection.get_offset_transform().transform(offsets)))
    points = np.concatenate(found)
    return points[np.isfinite(points).all(axis=1)]


def _data_lines(ax) -> list:
    """The visible lines of ``ax`` drawn in data coordinates (shifted or not): not a reference line
    across the axes (axhline, axvline), whose one coordinate is a share of the axes."""
    return [line for line in ax.lines if line.get_visible()
            and not isinstance(line.get_transform(), (BlendedGenericTransform, BlendedAffine2D))]


def _has_markers(line) -> bool:
    return line.get_marker() not in (None, "None", "", " ") and bool(line.get_markersize())


CATEGORIES = 12
"""An axis whose data points stand at no more than this many separate places (:func:`_unlabelled_values`)
is one of a few chosen values (budgets, numbers of agents, rewards swept), each to be labelled."""
CATEGORY_WIDTH = 0.04
"""Points less than this share of the axis apart stand at one place (side by side); a tick
labels a place when it stands this close to it."""
PLACE_WIDTH = 0.1
"""The widest a place may be (a share of the axis): points spread wider are not a few values."""


def _unlabelled_values(ax, ticks: dict) -> list[str]:
    """``ax``'s x axis when its marked points (lines with markers) stand at a few separate places
    (CATEGORIES; those set side by side at one place count once), each place holding two points
    or more (several series, or a point and its error bar's caps), and a tick label does not stand
    at each: a reader cannot tell which values were run."""
    points = np.concatenate([np.empty((0, 2))] + [
        ax.transAxes.inverted().transform(line.get_transform().transform(line.get_xydata()))
        for line in _data_lines(ax) if _has_markers(line)])
    xs = np.round(points[np.isfinite(points).all(axis=1) & (np.abs(points[:, 0] - 0.5) <= 0.5), 0], 4)
    at = np.unique(xs)
    if at.size < 2:
        return []
    places = np.split(at, np.flatnonzero(np.diff(at) > CATEGORY_WIDTH) + 1)
    if (len(places) > CATEGORIES or len(places) < 2 or any(p[-1] - p[0] > PLACE_WIDTH for p in places)
            or any(np.sum((xs >= p[0]) & (xs <= p[-1])) < 2 for p in places)):
        return []
    to_axes = ax.transScale + ax.transLimits
    labelled = np.array([to_axes.transform([(tick.get_loc(), ax.get_ylim()[0])])[0][0]
                         for tick in ax.xaxis.get_major_ticks()
                         if ticks.get(id(tick.label1)) and tick.label1.get_text().strip()])
    to_data = ax.transAxes + ax.transData.inverted()
    missing = [to_data.transform([((p[0] + p[-1]) / 2, 0.0)])[0][0] for p in places
               if not np.any((labelled >= p[0] - CATEGORY_WIDTH) & (labelled <= p[-1] + CATEGORY_WIDTH))]
    return [f"the x axis of {ax.get_title()!r} labels no tick at its plotted value(s) "
            f"{', '.join(f'{value:.3g}' for value in missing)}"] if missing else []


def data_bounds(ax, y: tuple[float, float]):
    """Declare the bounds ``y`` = (low, high) of ``ax``'s data (a count of six maps: (0, 6); a
    share: (0, 1)): :func:`layout_faults` finds any point drawn outside them (jitter that moves a
    count below zero)."""
    ax.__dict__["_data_bounds"] = y


def _out_of_bounds(ax) -> list[str]:
    """The points of ``ax``'s lines outside its declared bounds (:func:`data_bounds`)."""
    bounds = ax.__dict__.get("_data_bounds")
    if bounds is None:
        return []
    values = np.concatenate([np.empty(0)] + [np.asarray(line.get_ydata(), dtype=float) for line in _data_lines(ax)])
    outside = values[np.isfinite(values) & ((values < bounds[0]) | (values > bounds[1]))]
    return [f"a point of {ax.get_title()!r} lies at y = {value:.3g}, outside its data's bounds "
            f"[{bounds[0]:g}, {bounds[1]:g}]" for value in np.unique(outside)]


THIN_MARKERS = {"_": (1, 0), "|": (0, 1), 0: (1, 0), 1: (1, 0), 2: (0, 1), 3: (0, 1)}
"""Markers that are a line (an error bar's cap, a tick): (1, 0) as wide as their size and as high
as their edge, (0, 1) the other way round."""


def _texts_on_markers(fig, texts) -> list[str]:
    """Each text drawn over a marker of a line (its box: markersize points wide, a line's width
    for a thin marker) by more than OVERLAP_PIXELS: a value written on a marker cannot be read."""
    boxes = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for line in ax.lines:
            if not line.get_visible() or not _has_markers(line):
                continue
            centres = line.get_transform().transform(_marked(line))
            centres = centres[np.isfinite(centres).all(axis=1)]
            if line.get_clip_on():
                box = ax.bbox
                centres = centres[(centres[:, 0] >= box.x0) & (centres[:, 0] <= box.x1)
                                  & (centres[:, 1] >= box.y0) & (centres[:, 1] <= box.y1)]
            size, edge = (line.get_markersize() + line.get_markeredgewidth()) / 2, line.get_markeredgewidth() / 2
            thin = THIN_MARKERS.get(line.get_marker())
            half = np.array([size, size] if thin is None else [size if wide else edge for wide in thin])
            half = half * fig.dpi / 72.0  # points to pixels
            boxes.append(np.column_stack([centres - half, centres + half]))
    if not boxes:
        return []
    boxes = np.concatenate(boxes)
    faults = []
    for text, box in texts:
        width = np.minimum(boxes[:, 2], box.x1) - np.maximum(boxes[:, 0], box.x0)
        height = np.minimum(boxes[:, 3], box.y1) - np.maximum(boxes[:, 1], box.y0)
        if np.any((width > 0) & (height > 0) & (width * height > OVERLAP_PIXELS)):
            faults.append(f"text {text.get_text()!r} is drawn over a marker")
    return faults


def _marked(line) -> np.ndarray:
    """The points of ``line`` that carry a marker: those markevery lists (as indices), or all."""
    points, every = np.asarray(line.get_xydata(), dtype=float), line.get_markevery()
    if every is not None and not isinstance(every, (int, float, slice, tuple)) and all(
            isinstance(k, (int, np.integer)) for k in every):
        return points[np.asarray(every, dtype=int)]
    return points


def _texts_cut_by_frames(fig, texts) -> list[str]:
    """Each text written in an axes (an annotation, a label placed in data coordinates) that its
    frame crosses: partly inside the axes, partly outside, a spine drawn through it."""
    owned = {id(text): text.axes for ax in fig.axes for text in ax.texts}
    faults = []
    for text, box in texts:
        ax = owned.get(id(text))
        if ax is not None and ax.axison and ax.get_visible():
            frame = ax.bbox.padded(1.0)
            if _overlap(box, frame) > 0 and not _inside(box, frame):
                faults.append(f"text {text.get_text()!r} is cut by the frame of {ax.get_title()!r}")
    return faults


_TOKEN = re.compile(r"[A-Za-z0-9]+(?:_[A-Za-z0-9]+)+")
"""A name from the code or a configuration (``tunnel_to_goal_3``, ``two_observe``)."""


def _configuration_tokens(fig, texts) -> list[str]:
    """Each title, axis label or legend entry that shows a configuration token where a reader needs
    words: a name with underscores (a map's or learner's key), or an axis label that is a bare name
    of a measurement (glamas.learners.episode.METRICS: 'collisions', without 'per episode')."""
    from glamas.learners.episode import METRICS  # the measurements' names, as the results store them

    labels = {id(ax.xaxis.label) for ax in fig.axes} | {id(ax.yaxis.label) for ax in fig.axes}
    faults = []
    for text, _ in texts:
        words = text.get_text()
        token = _TOKEN.search(words)
        if token:
            faults.append(f"text {words!r} shows the configuration token {token.group()!r}")
        elif id(text) in labels and words.strip().lower() in METRICS:
            faults.append(f"axis label {words!r} is a bare measurement name (say what it counts, per what)")
    return faults


def shows_claims(fig, claims):
    """Declare that ``fig`` is the figure the ``claims`` (glamas.claims.Claim) are judged on:
    :func:`layout_faults` then finds each claim's level (its threshold) missing where no line of
    the figure is drawn at it within an axes' view (:func:`draw_claim_level`)."""
    fig.__dict__["_claims_shown"] = list(claims)


def draw_claim_level(ax, level: float, label: str | None):
    """A horizontal line at ``level``, the value a claim is judged against, labelled ``label``
    (None: no legend entry)."""
    ax.axhline(level, color="black", linestyle=":", linewidth=1.2, label=label)


def _claim_levels_missing(fig) -> list[str]:
    """The claims declared shown by ``fig`` (:func:`shows_claims`) whose level no visible horizontal
    or vertical line of the figure's axes draws inside the view."""
    faults = []
    for claim in fig.__dict__.get("_claims_shown", ()):
        if not any(_draws_level(ax, line, claim.threshold) for ax in fig.axes if ax.get_visible() for line in ax.lines):
            faults.append(f"the level {claim.threshold:g} that claim {claim.id!r} is judged at is not drawn")
    return faults


def _draws_level(ax, line, level: float) -> bool:
    """Whether ``line`` is a visible horizontal or vertical line at ``level`` inside ``ax``'s view."""
    if not line.get_visible():
        return False
    for values, (low, high) in ((line.get_ydata(), ax.get_ylim()), (line.get_xdata(), ax.get_xlim())):
        values = np.asarray(values, dtype=float)
        if values.size and np.all(values == level) and min(low, high) <= level <= max(low, high):
            return True
    return False
