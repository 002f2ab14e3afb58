"""The field's maps: every learner's collisions per episode while learning, one panel per map, and its greedy policy's after training."""

from glamas import errors, figures, plotting
from glamas.experiments import benchmark_maps


def main(argv=None):
    with figures.figure(benchmark_maps.EXPERIMENT, "benchmark_maps_curves", __doc__, argv, size=(13.0, 8.0),
                        nrows=2, ncols=3) as (axes, result, _):
        benchmark_maps.plot_curves(axes, result, "collisions")
        plotting.legend_below_figure(axes.flat[0], ncols=4)


if __name__ == "__main__":
    errors.run(main)
