"""Fig. 7b: probability of the optimal action L in region I for both AND-network agents."""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import and_network  # noqa: E402


def main(argv=None):
    defaults = and_network.ANDNetworkConfig()
    parser = cli.figure_parser(__doc__.splitlines()[0], runs=defaults.runs, iterations=defaults.iterations)
    args = cli.parse(parser, argv)
    config = and_network.ANDNetworkConfig(iterations=args.iterations, runs=args.runs,
                                          record_points=min(defaults.record_points, args.iterations))
    result = and_network.run(config, seed=args.seed, workers=args.workers, progress="fig7b")

    fig, ax = plotting.new_figure(6.0, 4.0)
    and_network.plot_prob_left(ax, result)
    for path in cli.write_outputs(args, "fig7b", fig, config, result.arrays()):
        print(path)


if __name__ == "__main__":
    main()
