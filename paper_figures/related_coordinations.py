"""Related work on TunnelToGoal: steps on which the agents observe each other, of 2observe, sparse
tabular MAQ and CQ-learning (Fig. 12b-style comparison, beyond the chapter)."""

from glamas import errors, figures
from glamas.experiments import related_work


def main(argv=None):
    with figures.figure(related_work.EXPERIMENT, "related_coordinations", __doc__, argv) as (ax, result, config):
        related_work.plot_coordinations(ax, result)
        related_work.note_cq_solo_phase(ax, result, config)


if __name__ == "__main__":
    errors.run(main)
