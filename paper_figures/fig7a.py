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
    for ax, run_index in zip(axes, and_network.typical_runs(result, 2)):
        and_network.plot_boundaries(ax, result, run_index)
    for path in plotting.save_figure(fig, args.out, "fig7a"):
        print(path)


if __name__ == "__main__":
    main()
