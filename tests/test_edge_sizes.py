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
from glamas.experiments import gridworld, gridworld_optimum, related_work, scaling
from glamas.gridworld import GridMap, MapError, maps, tunnel_to_goal
from glamas.learners import registry

FAST = ["--backend", "threads", "--workers", "1"]


def test_the_steps_figures_draw_fewer_episodes_than_their_zoom_starts_at(tmp_path, script):
    assert gridworld.TAIL_FROM > 50
    reproduce.script_main(script)(["--runs", "1", "--iterations", "50", "--out", str(tmp_path),
                                   "--results", str(tmp_path), *FAST])
    assert (tmp_path / f"{script}.png").is_file() and (tmp_path / f"{script}.pdf").is_file()


def test_a_final_mmdp_reward_of_zero_makes_its_ratios_undecidable():
    config = related_work.scaled(1, 1)
    result = related_work.run(config, seed=42, workers=parallel.Threads(1))  # seed 42: its one MMDP episode pays 0
    measured = related_work.measure(result, config)
    assert measured["reward_mmdp"] == 0.0
    assert math.isnan(measured["reward_two_observe_over_mmdp"]) and math.isnan(measured["reward_cq_over_mmdp"])
    assert related_work.claim_rows(result, config)
