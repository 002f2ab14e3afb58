"""Scaling study: final steps to goal, reward, collisions and episodes to converge against the
number of agents, 2 to 6."""

from glamas import plotting
from glamas import errors, figures
from glamas.experiments import scaling


def main(argv=None):
    with figures.figure(scaling.EXPERIMENT, "scaling_performance", __doc__, argv, size=(12.0, 8.0), nrows=2,
                        ncols=2) as (axes, result, _):
        for ax, metric in zip(axes.flat, ("steps", "reward", "collisions", "convergence")):
            scaling.plot_final(ax, result, metric, legend=False)
        plotting.legend_below_figure(axes.flat[0], ncols=4)


if __name__ == "__main__":
    errors.run(main)
