"""Many agents, 2 to 128 on generated warehouses: values stored per run, and the greedy policy's collisions and completion after training."""

from glamas import errors, figures, plotting
from glamas.experiments import scaling


def main(argv=None):
    with figures.figure(scaling.MANY_AGENTS, "many_agents", __doc__, argv, size=(13.0, 4.5),
                        ncols=3) as (axes, result, config):
        scaling.plot_sizes(axes[0], result, config, legend=False)
        for ax, metric in zip(axes[1:], ("collisions", "completion")):
            scaling.plot_greedy(ax, result, metric, legend=False)
        plotting.legend_below_figure(axes[0], ncols=3)


if __name__ == "__main__":
    errors.run(main)
