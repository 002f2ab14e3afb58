"""The field's maps with an optimal joint episode of each (value iteration, or exhaustive search where the tables are too large)."""

from glamas import errors, figures
from glamas.experiments import benchmark_maps


def main(argv=None):
    with figures.figure(benchmark_maps.EXPERIMENT, "benchmark_maps_optimum", __doc__, argv, size=(13.0, 13.0),
                        nrows=3, ncols=3) as (axes, result, _):
        for ax, map_name in zip(benchmark_maps.map_panels(axes), result.map_names()):
            benchmark_maps.plot_optimum(ax, result, map_name)


if __name__ == "__main__":
    errors.run(main)
