"""The check that every figure a reader sees is laid out cleanly (:func:`glamas.plotting.layout_faults`:
no text reaches outside the canvas, no two texts are drawn over each other, every logarithmic axis
has tick labels and every legend lies inside the canvas) finds each of these faults when made, on a
figure as drawn and as saved. Every figure script's figure is checked by it where it is redrawn from
the committed results (tests/test_committed_outputs.py)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from glamas import plotting  # noqa: E402


def _two_labels():
    fig, ax = plotting.new_figure(4.0, 3.0)
    ax.plot([1, 2], [1, 2])
    first = ax.text(1.2, 1.8, "first label")
    second = ax.text(1.6, 1.2, "second label")
    return fig, ax, first, second


def test_the_check_fails_on_a_label_moved_onto_another():
    fig, ax, first, second = _two_labels()
    assert plotting.layout_faults(fig) == []
    second.set_position(first.get_position())
    assert plotting.layout_faults(fig) == ["texts 'first label' and 'second label' overlap"]
    plt.close(fig)


def test_the_check_fails_on_a_saved_figure_as_the_redrawn_figures_are_checked(tmp_path):
    fig, ax, first, second = _two_labels()
    second.set_position(first.get_position())
    plotting.save_figure(fig, tmp_path, "overlap")
    assert plotting.layout_faults(fig) == ["texts 'first label' and 'second label' overlap"]
    plt.close(fig)


def test_the_check_fails_on_a_text_or_a_legend_outside_the_canvas():
    fig, ax, first, _ = _two_labels()
    first.set_position((5.0, 1.8))  # far right of the data, past the canvas
    ax.plot([1, 2], [2, 1], label="a line")
    ax.legend(loc="upper left", bbox_to_anchor=(1.5, 1.0))
    faults = plotting.layout_faults(fig)
    assert "text 'first label' reaches outside the canvas" in faults
    assert "the legend of '' reaches outside the canvas" in faults
    plt.close(fig)


def test_the_check_fails_on_a_log_axis_without_tick_labels():
    fig, ax, _, _ = _two_labels()
    ax.set_yscale("log")
    ax.set_title("log")
    assert plotting.layout_faults(fig) == []
    ax.yaxis.set_major_formatter(matplotlib.ticker.NullFormatter())
    ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    assert plotting.layout_faults(fig) == ["a logarithmic axis of 'log' has no tick labels"]
    plt.close(fig)
