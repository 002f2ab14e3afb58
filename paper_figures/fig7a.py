"""Fig. 7a: the boundaries two typical runs of AND-network agents learn over the parabola."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import and_network  # noqa: E402


@cli.guard
def main(argv=None):
    defaults = and_network.ANDNetworkConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    if args.runs < 2:
        parser.error("--runs must be at least 2: the figure shows two typical runs")
    config = and_network.ANDNetworkConfig(iterations=args.iterations, runs=args.runs,
                                          record_points=min(defaults.record_points, args.iterations))
    result = cli.load_or_run(args, "fig7", config, and_network.run, and_network.ANDNetworkResult)

    fig, axes = plotting.new_figure(8.0, 4.0, ncols=2)
    middle = (args.runs - 2) // 2  # typical_runs' first rank by final P(L) in region I
    for rank, ax, run_index in zip((middle, middle + 1), axes, and_network.typical_runs(result, 2)):
        and_network.plot_boundaries(ax, result, run_index, title=_title(rank, args.runs))
    for path in plotting.save_figure(fig, args.out, "fig7a"):
        print(path)


def _title(rank: int, runs: int) -> str:
    """What the run of ``rank`` (0 = lowest final P(L) in region I, of ``runs``) is: the median
    run, or the one just below or above the median."""
    median = (runs - 1) / 2
    where = "with the median" if rank == median else ("just below the median" if rank < median
                                                      else "just above the median")
    return f"run {where}\nfinal P(L) in region I"


if __name__ == "__main__":
    main()
