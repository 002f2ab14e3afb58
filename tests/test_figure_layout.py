"""The check that every figure a reader sees is laid out cleanly (:func:`glamas.plotting.layout_faults`:
no text reaches outside the canvas, no two texts are drawn over each other, no text over a marker
or cut by its axes' frame, no configuration token where words belong, every logarithmic axis has
tick labels, every legend lies inside the canvas, no axis stretched by a few off-scale points, the
plotted values of an axis of a few labelled, no point outside its data's bounds, and the level of
every claim a figure shows drawn) finds each of these faults when made, on a small made-up figure,
as drawn and as saved. Every figure script's figure is checked by it where it is redrawn from the
committed results (tests/test_committed_outputs.py)."""

import dataclasses

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from glamas import plotting  # noqa: E402
from glamas.claims import Claim  # noqa: E402


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


def _learners_and_two_skipped_tables():
    """Seven learners' tables at four N on a log axis (10^2 to 10^12 values), and two learners'
    skipped tables of 10^85 and 10^105 values, as the study of many agents once drew them."""
    fig, ax = plotting.new_figure(4.0, 3.0)
    n = np.array([2, 8, 32, 128])
    for k in range(7):
        ax.plot(n, 10.0 ** (2 + k + n / 32), "o-")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_title("sizes")
    return fig, ax


def test_the_check_fails_on_an_axis_stretched_by_two_off_scale_points():
    fig, ax = _learners_and_two_skipped_tables()
    assert plotting.layout_faults(fig) == []
    ax.plot([32, 32], [1e85, 1e105], "s", mfc="none")
    faults = plotting.layout_faults(fig)
    assert len(faults) == 1 and faults[0].startswith("the y axis of 'sizes' is stretched by 2 off-scale point(s)")
    plt.close(fig)


def test_a_few_points_far_apart_are_data_not_a_stretched_axis():
    fig, ax = plotting.new_figure(4.0, 3.0)
    for x, y in ((100, 99.0), (140, 97.2), (1600, 98.5), (5000, 99.1), (52000, 97.2), (100, 70.5)):
        ax.plot(x, y, "o")
    ax.set_xscale("log")
    assert plotting.layout_faults(fig) == []  # the related work's sizes: one learner's reward far below four
    plt.close(fig)


def _budgets(labelled: bool):
    fig, ax = plotting.new_figure(4.0, 3.0)
    budgets = np.array([2000, 20000, 200000])
    for k in range(3):
        ax.plot(budgets * 10.0 ** (0.03 * (k - 1)), [k, k + 1, k + 2], "o-")
    ax.set_xscale("log")
    if labelled:
        ax.set_xticks(budgets, [f"{b:,}" for b in budgets])
    ax.set_title("budgets")
    return fig


def test_the_check_fails_on_plotted_values_an_axis_of_few_does_not_label():
    fig = _budgets(labelled=False)
    assert plotting.layout_faults(fig) == ["the x axis of 'budgets' labels no tick at its plotted value(s) 2e+03, "
                                           "2e+04, 2e+05"]
    plt.close(fig)
    fig = _budgets(labelled=True)
    assert plotting.layout_faults(fig) == []
    plt.close(fig)


def test_the_check_fails_on_jitter_outside_the_datas_bounds():
    fig = _budgets(labelled=True)
    ax = fig.axes[0]
    plotting.data_bounds(ax, (0, 6))
    assert plotting.layout_faults(fig) == []
    ax.plot([2000, 20000], [-0.2, 5.1], "o")  # counts shifted apart: 0 - 0.2 is no count of maps
    assert plotting.layout_faults(fig) == ["a point of 'budgets' lies at y = -0.2, outside its data's bounds [0, 6]"]
    plt.close(fig)


def test_the_check_fails_on_a_text_over_a_marker_or_cut_by_the_frame():
    fig, ax = plotting.new_figure(4.0, 3.0)
    ax.plot([1, 10], [1, 2], "^", markersize=7)
    value = ax.annotate("9.5e+03", (10, 2), textcoords="offset points", xytext=(-8, -20), ha="right")
    assert plotting.layout_faults(fig) == []
    value.set_position((4, -3))  # written onto its marker
    assert plotting.layout_faults(fig) == ["text '9.5e+03' is drawn over a marker"]
    value.set_position((30, -20))  # running past the axes' right edge, the frame through it
    assert plotting.layout_faults(fig) == ["text '9.5e+03' is cut by the frame of ''"]
    plt.close(fig)


def test_the_check_fails_on_configuration_tokens_in_titles_legends_and_labels():
    fig, ax = plotting.new_figure(4.0, 3.0)
    ax.plot([1, 2], [1, 2], label="2observe")
    ax.set_title("TunnelToGoal 3")
    ax.set_ylabel("collisions per episode")
    ax.legend()
    assert plotting.layout_faults(fig) == []
    ax.set_title("tunnel_to_goal_3")
    ax.set_ylabel("collisions")
    ax.legend(labels=["two_observe"])
    assert sorted(plotting.layout_faults(fig)) == [
        "axis label 'collisions' is a bare measurement name (say what it counts, per what)",
        "text 'tunnel_to_goal_3' shows the configuration token 'tunnel_to_goal_3'",
        "text 'two_observe' shows the configuration token 'two_observe'"]
    plt.close(fig)


def test_the_check_fails_where_the_level_a_claim_is_judged_at_is_not_drawn():
    claim = Claim(id="no_collisions", where="Fig. 12a", chapter="zero collisions", kind="chapter", why="a test",
                  metric="collisions", op="<=", threshold=0.05, rule="level_on_curve")
    fig, ax = plotting.new_figure(4.0, 3.0)
    ax.plot([1, 2, 3], [3.0, 0.5, 0.04])
    plotting.shows_claims(fig, [claim])
    assert plotting.layout_faults(fig) == ["the level 0.05 that claim 'no_collisions' is judged at is not drawn"]
    plotting.draw_claim_level(ax, 0.1, "another level")
    assert plotting.layout_faults(fig) == ["the level 0.05 that claim 'no_collisions' is judged at is not drawn"]
    plotting.draw_claim_level(ax, claim.threshold, "zero collisions")
    assert plotting.layout_faults(fig) == []
    ax.set_ylim(1, 4)  # drawn, but outside the view
    assert plotting.layout_faults(fig) == ["the level 0.05 that claim 'no_collisions' is judged at is not drawn"]
    plt.close(fig)


def test_fig12a_reads_the_level_of_its_claims_from_the_chapters_data(monkeypatch):
    from glamas.experiments.gridworld import analysis, plots

    moved = [dataclasses.replace(claim, threshold=0.07) for claim in analysis.curve_collision_claims()]
    assert moved, "Fig. 12a shows no claim of zero collisions"
    monkeypatch.setattr(analysis.chapter, "load", lambda experiment: moved)
    assert plots.collision_levels() == [0.07]
