"""Fig. 6's right panel: the expected reward of each context encoding over log-scaled iterations,
on a given matplotlib Axes (the left panel is :func:`glamas.experiments.single_gla.plot_reward_curves`)."""

from glamas.plotting import legend_below, plot_mean_band


def plot_expected_curves(ax, results: dict):
    """Fig. 6 without sampling noise: the expected reward at the checkpoints (the result's ``expected_reward``)
    per context encoding over log-scaled iterations, mean and 95 % band over runs."""
    for name, res in results.items():
        after_start = res.checkpoint > 0  # the start has no place on a log axis
        plot_mean_band(ax, res.checkpoint[after_start], res.expected_reward[:, after_start], label=name)
    ax.set_xscale("log")
    ax.set_xlabel("iteration")
    ax.set_ylabel("expected reward")
    legend_below(ax, ncols=3)
