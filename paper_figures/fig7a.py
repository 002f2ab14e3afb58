"""Fig. 7a: the boundaries two typical runs of AND-network agents learn over the parabola."""

from glamas import errors, figures
from glamas.experiments import and_network


def main(argv=None):
    with figures.figure(and_network.FIG7, "fig7a", __doc__, argv, size=(8.0, 4.0), ncols=2,
                        min_runs=2) as (axes, result, config):
        middle = (config.runs - 2) // 2  # typical_runs' first rank by final P(L) in region I
        for rank, ax, run_index in zip((middle, middle + 1), axes, and_network.typical_runs(result, 2)):
            and_network.plot_boundaries(ax, result, run_index, title=_title(rank, config.runs))


def _title(rank: int, runs: int) -> str:
    """What the run of ``rank`` (0 = lowest final P(L) in region I, of ``runs``) is: the median
    run, or the one just below or above the median."""
    median = (runs - 1) / 2
    where = "with the median" if rank == median else ("just below the median" if rank < median
                                                      else "just above the median")
    return f"run {where}\nfinal P(L) in region I"


if __name__ == "__main__":
    errors.run(main)
