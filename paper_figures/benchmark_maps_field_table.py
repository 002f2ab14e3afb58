"""The field's maps under the field's rewards (-1 per move, 0 at the goal, a collision -10 in place
of the move's cost) and learning settings: every learner's greedy policy after training against
each map's exact optimum."""

from glamas import errors, figures
from glamas.experiments import benchmark_maps


def main(argv=None):
    with figures.figure(benchmark_maps.FIELD_EXPERIMENT, "benchmark_maps_field_table", __doc__, argv,
                        size=(11.0, 5.0)) as (ax, result, _):
        benchmark_maps.plot_table(ax, result)


if __name__ == "__main__":
    errors.run(main)
