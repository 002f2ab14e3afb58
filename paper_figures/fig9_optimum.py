"""Fig. 9's gridworld solved: the exact joint optimum by dynamic programming (value iteration)
next to agents that each take their own shortest path (chapter Section 5.3)."""

from glamas import errors, figures
from glamas.experiments import gridworld_optimum


def main(argv=None):
    with figures.fixed_figure("fig9_optimum", __doc__, argv, size=(6.4, 3.9), ncols=2) as (optimal, selfish):
        result = gridworld_optimum.run(gridworld_optimum.GridworldOptimumConfig())
        gridworld_optimum.plot_episode(optimal, result, "optimal")
        gridworld_optimum.plot_episode(selfish, result, "selfish")


if __name__ == "__main__":
    errors.run(main)
