"""2observe's coordination in a crowd: its runs on the benchmark's warehouses replayed greedily with the coordination as learned (solid) and switched off on the same tables (dashed): the share of agents in (ISR, top) and of steps that bring the crowd back to a joint state it was in before (bottom), under the chapter's rewards (left) and the field's (right)."""

from glamas import errors, figures, plotting
from glamas.experiments import crowd


def main(argv=None):
    with figures.figure(crowd.EXPERIMENT, "crowd", __doc__, argv, size=(11.0, 8.0), nrows=2,
                        ncols=2) as (axes, result, _):
        crowd.plot_crowd(axes[0], result, "in_goal")
        crowd.plot_crowd(axes[1], result, "revisits")
        plotting.legend_below_figure(axes[1, 0], ncols=2)


if __name__ == "__main__":
    errors.run(main)
