"""Edge sizes: every size works or is refused before computing. Fig. 11a and the related-work
steps with fewer episodes than the zoomed tail starts at, one run of one episode whose MMDP reward
is exactly 0, nine agents in the scaling study, a value-iteration epsilon too coarse to give an
optimum, and maps built in Python that the rules cannot play."""

import dataclasses
import math
import re

import numpy as np
import pytest

from glamas import parallel, reproduce
from glamas.experiments import gridworld_optimum, related_work, scaling
from glamas.experiments.gridworld import plots as gridworld_plots
from glamas.gridworld import GridMap, MapError, maps, tunnel_to_goal
from glamas.gridworld.maps import goals_from_table, make_goals
from glamas.learners import registry

FAST = ["--backend", "threads", "--workers", "1"]


@pytest.mark.parametrize("script", ["fig11a", "related_steps"])
def test_the_steps_figures_draw_fewer_episodes_than_their_zoom_starts_at(tmp_path, script):
    assert gridworld_plots.TAIL_FROM > 50
    reproduce.script_main(script)(["--runs", "1", "--iterations", "50", "--out", str(tmp_path),
                                   "--results", str(tmp_path), *FAST])
    assert (tmp_path / f"{script}.png").is_file() and (tmp_path / f"{script}.pdf").is_file()


def test_a_final_mmdp_reward_of_zero_makes_its_ratios_undecidable():
    config = related_work.scaled(1, 1)
    result = related_work.run(config, seed=283, workers=parallel.Threads(1))  # seed 283: its one MMDP episode pays 0
    measured = related_work.measure(result, config)
    assert measured["reward_mmdp"] == 0.0
    assert math.isnan(measured["reward_two_observe_over_mmdp"]) and math.isnan(measured["reward_cq_over_mmdp"])
    assert related_work.claim_rows(result, config)


def _nine_agents(tmp_path) -> str:
    """A 6 x 6 room with agents 1-9 along the top and the goal in the far corner: the map pattern."""
    size = 6
    cells = [["."] * size for _ in range(size)]
    for agent in range(9):
        cells[agent // size][agent % size] = str(agent + 1)
    cells[-1][-1] = "G"
    lines = ["+" + "-+" * size]
    for r, row in enumerate(cells):
        lines += ["|" + " ".join(row) + "|", "+" + ("-+" if r == size - 1 else " +") * size]
    (tmp_path / "room_9.txt").write_text("\n".join(lines) + "\n")
    return str(tmp_path / "room_{n}.txt")


def test_nine_agents_skip_the_learners_beyond_the_budget_and_run_the_others(tmp_path):
    config = scaling.ScalingConfig(agents=(9,), map=_nine_agents(tmp_path), episodes=100, runs=1)
    gridmap = config.gridmap(9)
    assert registry.get("mmdp").bytes_per_run(config.setup("mmdp"), gridmap) == 36 ** 9 * 4 ** 9 * 8  # Python ints: exact
    result = scaling.run(config, workers=parallel.Threads(1))
    names = result.names()
    assert not result.ran[names.index("mmdp"), 0] and not result.ran[names.index("joint_state"), 0]
    assert result.ran[names.index("two_observe"), 0] and result.ran[names.index("independent"), 0]
    assert result.bytes_needed[names.index("mmdp"), 0] == np.iinfo(np.int64).max  # more than an int64 counts
    assert result.parameters()[names.index("mmdp"), 0] == pytest.approx(36 ** 9 * 4 ** 9)
    assert scaling.claim_rows(result)


def test_an_epsilon_too_coarse_for_an_optimum_is_refused():
    with pytest.raises(ValueError, match=r"epsilon must be a float > 0 and at most 0\.000111 for gamma=0\.9 .*got 100\.0"):
        gridworld_optimum.GridworldOptimumConfig(epsilon=100.0)
    coarse = gridworld_optimum.GridworldOptimumConfig(gamma=0.5, epsilon=1e-3)  # within the bound, too coarse at 0.5
    with pytest.raises(ValueError, match="the policy that policy iteration found with epsilon=0.001 does not bring "
                                         "every agent to the goal of 'tunnel_to_goal': lower epsilon"):
        gridworld_optimum.run(coarse)


@pytest.mark.parametrize("change, message", [
    (lambda g: {"starts": np.array([np.flatnonzero(g.is_goal)[0], g.starts[1]])}, "agent 1 starts on its own goal"),
    (lambda g: {"starts": np.array([g.starts[0], g.starts[0]])}, "agents 1 and 2 both start at"),
    (lambda g: {"starts": np.array([g.starts[0], 99])}, "agent 2's start 99 is outside the cells 0..24"),
    (lambda g: {"starts": [1, 2]}, "starts must be an array of integer of shape (2,)"),
    (lambda g: {"goals": goals_from_table(np.zeros((2, g.n_cells), bool))}, "has no goal for agent 1"),
    (lambda g: {"goals": np.zeros((2, g.n_cells), bool)}, "goals must be a Goals"),
    (lambda g: {"goals": make_goals(g.goals.shared, [[g.cell(0, 1), g.cell(0, 1)], []])}, "agent 1's own goals repeat"),
    (lambda g: {"goals": make_goals(g.goals.shared, [[99], []])}, "an own goal lies outside the cells 0..24"),
    (lambda g: {"next_cell": g.next_cell[:5]}, "next_cell must be an array of integer of shape (25, 4)"),
])
def test_a_map_built_in_python_is_checked_as_a_map_file_is(change, message):
    tunnel = tunnel_to_goal()
    with pytest.raises(MapError, match=f"map 'tunnel_to_goal'.*{re.escape(message)}"):
        dataclasses.replace(tunnel, **change(tunnel))


def test_map_files_and_python_maps_share_one_check(monkeypatch):
    checked = []
    monkeypatch.setattr(maps, "check_layout", checked.append)
    monkeypatch.setattr(maps, "_PARSED", {})  # a map file is parsed once per content: parse it here again
    tunnel = tunnel_to_goal()
    GridMap("by hand", tunnel.n_rows, tunnel.n_cols, tunnel.next_cell, tunnel.is_goal, tunnel.blocked, tunnel.starts)
    assert [gridmap.name for gridmap in checked] == ["tunnel_to_goal", "by hand"]
