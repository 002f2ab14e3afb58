"""The field's maps with their optimal plans as path finding counts them: the collision-free plan
of least sum of costs, and the least makespan beside it; exact where the joint tables fit, the lower
bounds elsewhere."""

from glamas import errors, figures
from glamas.experiments import benchmark_maps


def main(argv=None):
    with figures.figure(benchmark_maps.EXPERIMENT, "benchmark_maps_plans", __doc__, argv, size=(13.0, 13.0),
                        nrows=3, ncols=3) as (axes, result, _):
        for ax, map_name in zip(benchmark_maps.map_panels(axes), result.map_names()):
            benchmark_maps.plot_plan(ax, result, map_name)


if __name__ == "__main__":
    errors.run(main)
