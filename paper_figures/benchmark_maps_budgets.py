"""The field's maps at more than one budget: the maps each learner's greedy policy solves
(collision-free, every agent in its goal) after 2,000, 20,000 and 200,000 training episodes, under
the chapter's rewards and under the field's."""

from glamas import errors, figures
from glamas.experiments import benchmark_maps


def main(argv=None):
    with figures.figure(benchmark_maps.BUDGETS_EXPERIMENT, "benchmark_maps_budgets", __doc__, argv, size=(11.0, 4.8),
                        ncols=2) as (axes, result, _):
        benchmark_maps.plot_budgets(axes, result)


if __name__ == "__main__":
    errors.run(main)
