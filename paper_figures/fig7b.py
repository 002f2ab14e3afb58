"""Fig. 7b: probability of the optimal action L in region I for both AND-network agents."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import and_network  # noqa: E402


@cli.guard
def main(argv=None):
    defaults = and_network.ANDNetworkConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    config = and_network.ANDNetworkConfig(iterations=args.iterations, runs=args.runs,
                                          record_points=min(defaults.record_points, args.iterations))
    result = cli.load_or_run(args, "fig7", config, and_network.run, and_network.ANDNetworkResult)

    fig, ax = plotting.new_figure(6.0, 4.0)
    and_network.plot_prob_left(ax, result)
    for path in plotting.save_figure(fig, args.out, "fig7b"):
        print(path)


if __name__ == "__main__":
    main()
