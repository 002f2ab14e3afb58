"""Fig. 9: the gridworld of Section 5.3 (TunnelToGoal), and its exact joint optimum by dynamic programming.

Writes fig9.png/.pdf (the map) and fig9_optimum.png/.pdf (the value-iteration optimum next to
agents that each take their own shortest path). Deterministic: no runs, no seed.
"""

import matplotlib

matplotlib.use("Agg")

from glamas import cli, plotting  # noqa: E402
from glamas.experiments import gridworld_optimum  # noqa: E402
from glamas.gridworld import draw, tunnel_to_goal  # noqa: E402


@cli.guard
def main(argv=None):
    # The figure scripts' common options; this figure is deterministic, so only --out matters.
    parser = cli.figure_parser(__doc__.splitlines()[0] + " (deterministic: only --out changes what it writes)",
                               runs=1, iterations=None)
    args = cli.parse(parser, argv)

    fig, ax = plotting.new_figure(3.2, 3.2)
    draw.draw_map(ax, tunnel_to_goal())
    written = plotting.save_figure(fig, args.out, "fig9")

    result = gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig())
    fig, axes = plotting.new_figure(6.4, 3.9, ncols=2)
    gridworld_optimum.plot_episode(axes[0], result, "optimal")
    gridworld_optimum.plot_episode(axes[1], result, "selfish")
    written += plotting.save_figure(fig, args.out, "fig9_optimum")
    for path in written:
        print(path)


if __name__ == "__main__":
    main()
