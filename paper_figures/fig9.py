"""Fig. 9: the gridworld of Section 5.3 (TunnelToGoal), and its exact joint optimum by dynamic programming.

Writes fig9.png/.pdf (the map) and fig9_optimum.png/.pdf (the value-iteration optimum next to
agents that each take their own shortest path). Deterministic: no runs, no seed.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from glamas import atomic, cli, plotting  # noqa: E402
from glamas.cli import DEFAULT_OUT  # noqa: E402
from glamas.experiments import gridworld_optimum  # noqa: E402
from glamas.gridworld import draw, tunnel_to_goal  # noqa: E402


@cli.guard
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"directory for the PNG and PDF (default {DEFAULT_OUT})")
    args = parser.parse_args(argv)
    try:
        atomic.check_writable_directory(args.out, "--out")
    except ValueError as error:
        parser.error(str(error))

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
